// The panel's live plots (dygraphs from Debian's libjs-dygraphs: canvas
// drawing that redraws thousands of points in a few ms, so the panel keeps
// up at the channels' 30 frames a second): the legs' encoder lengths, the
// platform's tracking error (commanded − measured pose, both from one
// EDSP_PLATFORM_STATE message, so no two clocks are mixed), the tracker's
// point A against the model's (EDSP_TRACKER against EDSP_PLATFORM_STATE's
// point, interpolated to the tracker's instant, the tracker's frame fitted
// to {B} over the pairs kept: rigid_fit.js), and every node's loop time
// (EDSP_STATUS, once a second). Pause, a window of the last minutes, drag
// to zoom (double-click: back), export of what is shown as CSV.
"use strict";

const plots = (() => {
  const KEEP_S = 600;     // history kept, whatever the window shown
  const REDRAW_MS = 200;  // five redraws a second: a plot needs no more
  const series = {
    legs: { labels: ["t (s)", "leg 1", "leg 2", "leg 3", "leg 4", "leg 5", "leg 6"], unit: "mm", rows: [] },
    tracking: { labels: ["t (s)", "x", "y", "z", "rotation"], unit: "µm, µrad", rows: [] },
    tracker: { labels: ["t (s)", "x", "y", "z", "distance"], unit: "µm", rows: [] },
    loops: { labels: ["t (s)"], unit: "µs (p99)", rows: [], nodes: [] },
  };
  const graphs = {};
  let t0 = null, paused = false, windowS = 120, lastDraw = 0;
  // Tracker against model: the model's point A of the last seconds (to
  // interpolate at a tracker sample's instant), tracker samples waiting for
  // the model's point after them, the pairs made, and the frame fitted.
  const MODEL_KEEP_S = 2;
  const REFIT_MS = 2000;
  const MAX_FIT_PAIRS = 2000;
  const MIN_SPREAD_M2 = 2e-3 * 2e-3;  // the model's points 2 mm RMS along a plane's second axis before a rotation
  const modelPoints = [], waiting = [], pairs = [];
  let fit = null, lastRotation = null, lastFit = -Infinity;

  function seconds(utime) {
    if (t0 === null) t0 = utime;
    return (utime - t0) / 1e6;
  }

  function keep(rows, t) {
    while (rows.length && rows[0][0] < t - KEEP_S) rows.shift();
  }

  // In time order: messages of several publishers (EDSP_STATUS) arrive a
  // little out of it.
  function add(name, row) {
    const rows = series[name].rows;
    let at = rows.length;
    while (at > 0 && rows[at - 1][0] > row[0]) --at;
    rows.splice(at, 0, row);
    keep(rows, rows[rows.length - 1][0]);
  }

  function shown(name) {
    const rows = series[name].rows;
    if (!rows.length) return [];
    const end = rows[rows.length - 1][0];
    return rows.filter((r) => r[0] >= end - windowS);
  }

  // The model's point A at instant t, between the two kept around it; none past the newest.
  function modelAt(t) {
    for (let k = modelPoints.length - 1; k > 0; --k) {
      const [t1, p1] = modelPoints[k], [t0_, p0] = modelPoints[k - 1];
      if (t0_ <= t && t <= t1) {
        const w = t1 > t0_ ? (t - t0_) / (t1 - t0_) : 0;
        return p0.map((v, i) => v + w * (p1[i] - v));
      }
    }
    return null;
  }

  function residualRow(pair) {
    const d = rigidFit.apply(fit, pair.tracker).map((v, i) => (v - pair.model[i]) * 1e6);
    return [pair.t, d[0], d[1], d[2], Math.hypot(d[0], d[1], d[2])];
  }

  // The tracker's frame fitted again over the pairs kept (every pair's row
  // recomputed with it): a rotation once the model's points span a plane.
  function refit(now) {
    if (pairs.length < 3 || now - lastFit < REFIT_MS) return;
    lastFit = now;
    const step = Math.max(1, Math.floor(pairs.length / MAX_FIT_PAIRS));
    const used = pairs.filter((_, k) => k % step === 0);
    fit = rigidFit.fit(used.map((p) => p.tracker), used.map((p) => p.model), MIN_SPREAD_M2, lastRotation);
    if (fit.rotated) lastRotation = fit.rotation;
    series.tracker.rows = pairs.map(residualRow);
    document.getElementById("tracker-fit").textContent = fit.rotated || lastRotation
      ? `the tracker's frame fitted to {B} over ${used.length} pairs`
      : "the tracker's frame only translated onto {B}: the platform has not moved over a plane yet";
  }

  function pairWaiting() {
    while (waiting.length && modelPoints.length && waiting[0].t <= modelPoints[modelPoints.length - 1][0]) {
      const sample = waiting.shift();
      const model = modelAt(sample.t);
      if (!model) continue;  // older than the points kept
      const pair = { t: sample.t, tracker: sample.point, model };
      pairs.push(pair);
      while (pairs.length && pairs[0].t < pair.t - KEEP_S) pairs.shift();
      if (fit) add("tracker", residualRow(pair));
    }
  }

  function draw(now) {
    refit(now);
    if (paused || typeof Dygraph === "undefined") return;
    if (now - lastDraw < REDRAW_MS) return;
    lastDraw = now;
    for (const name of Object.keys(series)) {
      const rows = shown(name);
      if (!rows.length) continue;
      const labels = series[name].labels;
      if (!graphs[name] || graphs[name].numColumns() !== labels.length) {
        if (graphs[name]) graphs[name].destroy();
        // A copy: the loops' labels grow as nodes appear, and a graph redrawn
        // (a resize) with its labels grown under it throws "Unknown series"
        // (its rows are replaced, not grown, for the same reason).
        graphs[name] = new Dygraph(document.getElementById(`plot-${name}`), rows,
          { labels: [...labels], ylabel: series[name].unit, legend: "always", labelsSeparateLines: false, animatedZooms: false,
            connectSeparatedPoints: true, strokeWidth: 1.2 });
      } else if (!graphs[name].isZoomed()) {
        graphs[name].updateOptions({ file: rows });
      }
    }
  }

  function finite(v) { return typeof v === "number" && Number.isFinite(v); }

  // What the plot shows: its zoomed or paused range, else the window.
  function visible(name) {
    const graph = graphs[name];
    if (!graph) return shown(name);
    const [from, to] = graph.xAxisRange();
    return series[name].rows.filter((r) => r[0] >= from && r[0] <= to);
  }

  function csv(name) {
    const head = series[name].labels.map((l) => `"${l.replace(/"/g, '""')}"`).join(",");
    const unit = `# ${series[name].unit}`;
    const body = visible(name).map((r) => r.map((v) => (v === null ? "" : `${v}`)).join(","));
    return [unit, head, ...body].join("\n") + "\n";
  }

  function download(name) {
    const link = document.createElement("a");
    link.href = URL.createObjectURL(new Blob([csv(name)], { type: "text/csv" }));
    link.download = `edsp-${name}.csv`;
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 1000);
  }

  return {
    bind() {
      document.getElementById("plot-pause").onclick = (event) => {
        paused = !paused;
        event.target.textContent = paused ? "Resume" : "Pause";
      };
      document.getElementById("plot-window").onchange = (event) => { windowS = Number(event.target.value); };
      for (const name of Object.keys(series)) {
        document.getElementById(`csv-${name}`).onclick = () => download(name);
      }
      const frame = (now) => { draw(now); requestAnimationFrame(frame); };
      requestAnimationFrame(frame);
    },
    onLegState(state) {
      add("legs", [seconds(state.utime), ...state.encoder_length_m.map((v) => (finite(v) ? v * 1e3 : null))]);
    },
    onPlatformState(state) {
      if (state.observation_point_m.every(finite) && state.fk_status === 0) {
        const t = seconds(state.utime);
        modelPoints.push([t, state.observation_point_m]);
        while (modelPoints.length > 2 && modelPoints[0][0] < t - MODEL_KEEP_S) modelPoints.shift();
        pairWaiting();
      }
      if (![...state.pose, ...state.target_pose].every(finite)) return;
      const d = state.target_pose.map((v, i) => v - state.pose[i]);
      add("tracking", [seconds(state.utime), d[0] * 1e6, d[1] * 1e6, d[2] * 1e6, Math.hypot(d[3], d[4], d[5]) * 1e6]);
    },
    // EDSP_TRACKER: a valid sample waits for the model's point after it.
    onTracker(sample) {
      if (!sample.valid || !sample.point_m.every(finite)) return;
      waiting.push({ t: seconds(sample.utime), point: sample.point_m });
      if (waiting.length > 100) waiting.shift();  // the model silent: keep the newest
      pairWaiting();
    },
    // One row per status message: its node's loop p99, the others' left
    // empty (dygraphs joins a series' points across them).
    onStatus(status) {
      const s = series.loops;
      if (!s.nodes.includes(status.node)) {
        s.nodes.push(status.node);
        s.labels.push(status.node);
        s.rows = s.rows.map((r) => [...r, null]);  // new rows: the graph drawn keeps the ones it was given
      }
      const row = new Array(s.labels.length).fill(null);
      row[0] = seconds(status.utime);
      row[s.nodes.indexOf(status.node) + 1] = finite(status.loop_p99_us) ? status.loop_p99_us : null;
      add("loops", row);
    },
    csv,
    rows(name) { return series[name].rows.length; },
    // How far behind its newest row the plot shows (s): a busy browser
    // redraws late, and the CSV exports what is shown.
    lag(name) {
      const rows = series[name].rows;
      if (!graphs[name] || !rows.length) return Infinity;
      return rows[rows.length - 1][0] - graphs[name].xAxisRange()[1];
    },
  };
})();
