// The panel's calibration view: the model the kinematics runs (the closing
// comment of EDSP_CONFIG's config text, which the kinematics node writes
// whenever it applies or switches one), what it takes off each leg's
// length now (EDSP_LEG_COMMAND: inverse kinematics − PR correction −
// calibration = command), and the last drift check's verdict, when edsp-web
// was given its file (--drift-report: `edsp-gap drift --json`'s output,
// read again every DRIFT_EVERY_MS so a new verdict shows without a reload;
// serverInfo's metadata says whether there is one).
"use strict";

const calibration = (() => {
  const DRIFT_EVERY_MS = 10000;
  const UM = 1e6;

  function um(metres, digits = 1) { return typeof metres === "number" ? (metres * UM).toFixed(digits) : "–"; }
  // A report's number as written (NaN and infinities come as null): "–" when it is none.
  function shown(value, format) { return typeof value === "number" ? format(value) : "–"; }

  // "# edsp-kinematics applies the calibration …" or "… switches the calibration: …", last of the text.
  function modelInForce(configToml) {
    const lines = (configToml || "").trimEnd().split("\n");
    const last = lines[lines.length - 1] || "";
    const match = last.match(/^# edsp-kinematics (applies the calibration|switches the calibration:) (.*)$/);
    if (!match) return "none: the kinematics runs the nominal model";
    return match[1].startsWith("switches") ? `switching: ${match[2]}` : match[2];
  }

  function legRow(table, i) {
    let row = table.rows[i + 1];
    if (!row) {
      row = table.insertRow();
      for (let c = 0; c < 4; ++c) row.insertCell();
      row.cells[0].textContent = `${i + 1}`;
    }
    return row;
  }

  function listed(items, describe) { return items && items.length ? items.map(describe).join("; ") : "none"; }

  function showDrift(report) {
    const el = document.getElementById("drift-report");
    const z = (v) => shown(v, (x) => x.toFixed(1));
    const legs = listed(report.legs_changed, (l) => `leg ${l.leg} ${l.change_m > 0 ? "+" : ""}${um(l.change_m)} µm (z ${z(l.z)})`);
    const changed = listed(report.changed, (c) => `${c.effect}${c.leg ? " leg " + c.leg : ""} ${c.parameter} ` +
      `${shown(c.before, (x) => x.toExponential(2))} → ${shown(c.after, (x) => x.toExponential(2))} (z ${z(c.z)})`);
    el.textContent = `last drift check: ${report.recalibrate ? "recalibrate" : "no recalibration needed"}; ` +
      `the calibration leaves ${um(report.heldout_rms_m)} µm RMS; legs changed: ${legs}; parameters changed: ${changed}; ` +
      `appeared: ${listed(report.appeared, String)}; vanished: ${listed(report.vanished, String)}`;
    el.className = report.recalibrate ? "recalibrate" : "";
    el.dataset.recalibrate = report.recalibrate ? "1" : "0";
  }

  function showDriftAbsent(why) {
    const el = document.getElementById("drift-report");
    el.textContent = `no drift check: ${why}`;
    el.className = "unit";
    delete el.dataset.recalibrate;
  }

  let driftTimer = null;

  async function readDrift(token) {
    let response;
    try {
      response = await fetch("drift-report.json" + (token ? `?token=${encodeURIComponent(token)}` : ""),
                             { cache: "no-store" });
    } catch (error) {
      return showDriftAbsent(`edsp-web did not answer (${error.message})`);
    }
    const body = await response.text();
    if (response.status === 401 || response.status === 429) {
      clearInterval(driftTimer);  // a revoked token asking again would only get this address blocked
      return showDriftAbsent(`${body.trim()} (no longer asked: reload the page)`);
    }
    if (!response.ok) return showDriftAbsent(body.trim());
    try {
      showDrift(JSON.parse(body));
    } catch (error) {
      showDriftAbsent(`the report could not be shown (${error.message})`);
    }
  }

  return {
    // serverInfo: its metadata names the drift report's file when edsp-web has one.
    attach(info, token) {
      clearInterval(driftTimer);
      if ((info.metadata || {}).drift_report !== "true") {
        return showDriftAbsent("edsp-web was started without --drift-report FILE");
      }
      readDrift(token);
      driftTimer = setInterval(() => readDrift(token), DRIFT_EVERY_MS);
    },
    onConfig(config) {
      document.getElementById("calibration-model").textContent = `in force: ${modelInForce(config.config_toml)}`;
    },
    onLegCommand(command) {
      const table = document.getElementById("calibration-legs");
      command.ik_length_m.forEach((ik, i) => {
        const pr = command.pr_correction_m[i], commanded = command.command_length_m[i];
        const row = legRow(table, i);
        const finite = [ik, pr, commanded].every((v) => typeof v === "number");
        row.cells[1].textContent = typeof ik === "number" ? (ik * 1e3).toFixed(3) : "–";
        row.cells[2].textContent = um(pr, 2);
        row.cells[3].textContent = finite ? um(ik - pr - commanded, 2) : "–";
      });
    },
  };
})();
