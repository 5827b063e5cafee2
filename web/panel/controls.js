// The operator's controls: a move to a pose (in {B} or a work frame, or
// relative to the last target, at a speed or the default), a jog along one
// axis, the pivot, a program run (named motions or a trajectory CSV), halt
// (the planner decelerates along the path), stop (at the legs' limit) and
// re-arm (the actuator bridge, after it latched a hold). Each is a request
// published through the protocol's clientPublish, which edsp-web offers to
// operators only, and stamps with the group's session and "web:NAME"; the
// answer (EDSP_MOTION_REPLY, EDSP_REPLY) is shown beside it. The form's
// move is checked along its whole path by the planner as it is edited (a
// check request), so its answer shows before the move is sent. Halt and
// stop sit in the page's header, always in view; Escape halts and
// Shift+Escape stops, wherever the focus is.
"use strict";

const controls = (() => {
  const PUBLISHED = [
    { id: 1, topic: "EDSP_MOTION_REQUEST", schemaName: "edsp.motion_request_t" },
    { id: 2, topic: "EDSP_ARM", schemaName: "edsp.arm_t" },
  ];
  let KIND = {};  // the request kinds by name, from the server (serverInfo's metadata.request_kinds)
  const CHECK_AFTER_EDIT_MS = 400;
  const MM = 1e-3, DEG = Math.PI / 180;
  const POSE_UNITS = [MM, MM, MM, DEG, DEG, DEG];
  const AXES = ["x", "y", "z", "roll", "pitch", "yaw"];
  // edsp-web closes a client that sends a frame over 64 KiB (its Halt with
  // it): a request that would be larger is refused here, unsent. A CSV is
  // sent whole in one frame.
  const MAX_FRAME_BYTES = 64 * 1024;
  const MAX_CSV_BYTES = 60 * 1024;
  const CONTROLS = ["move", "check", "halt", "stop", "rearm", "jog-minus", "jog-plus", "set-pivot", "run"];

  const pending = new Map();  // request id -> {what, line}: the answer's line
  let socket = null, nextId = Date.now() * 1000, formTouched = false, operator = false, checkTimer = null;
  let latestCheck = 0;  // only the answer to the form as it is now is shown
  let halts = 0;  // halts and stops sent: a program read from a file before one is not sent after it

  function channelId(topic) { return PUBLISHED.find((c) => c.topic === topic).id; }

  function note(text, cls, line = "control-reply") {
    const el = document.getElementById(line);
    el.textContent = text;
    el.className = cls || "";
  }

  // The request's id, or 0 when it would be a frame too large to send.
  function publish(topic, request) {
    const id = nextId++;
    const payload = new TextEncoder().encode(JSON.stringify({ ...request, request_id: id }));
    if (5 + payload.length > MAX_FRAME_BYTES) return 0;
    const frame = new Uint8Array(5 + payload.length);
    frame[0] = 0x01;  // client message data
    new DataView(frame.buffer).setUint32(1, channelId(topic), true);
    frame.set(payload, 5);
    socket.send(frame);
    return id;
  }

  function ask(topic, request, what, line = "control-reply") {
    if (!socket || socket.readyState !== WebSocket.OPEN) return note("not connected", "error", line);
    const id = publish(topic, request);
    if (!id) return note(`${what}: not sent, more than the ${MAX_FRAME_BYTES / 1024} KiB edsp-web takes in one frame`, "error", line);
    pending.set(id, { what, line });
    note(`${what}: sent`, "", line);
    return id;
  }

  // Numbers typed in fields `ids`, each times its unit, or why one is not a number.
  function numbers(ids, names, units) {
    const values = [];
    for (let i = 0; i < ids.length; ++i) {
      const text = document.getElementById(ids[i]).value.trim();
      const value = Number(text);
      if (text === "" || !Number.isFinite(value)) return { error: `${names[i]} is not a number` };
      values.push(value * units[i]);
    }
    return { values };
  }

  // A speed field: empty is the planner's default (0 on the wire).
  function speed(id, what, unit) {
    const text = document.getElementById(id).value.trim();
    if (text === "") return { value: 0 };
    const value = Number(text);
    if (!Number.isFinite(value) || value <= 0) return { error: `${what} must be a positive number or empty (the default)` };
    return { value: value * unit };
  }

  // What a move, check or jog carries besides its pose: the frame and the speeds.
  function moveSettings() {
    const linear = speed("goal-speed", "speed (mm/s)", MM);
    const angular = speed("goal-speed-rot", "speed (°/s)", DEG);
    const error = linear.error || angular.error;
    if (error) return { error };
    return { frame: document.getElementById("goal-frame").value.trim(), speed_m_s: linear.value, speed_rad_s: angular.value };
  }

  function goal(kind) {
    const { values: pose, error } = numbers(AXES.map((_, i) => `goal-${i}`), AXES, POSE_UNITS);
    const settings = moveSettings();
    if (error || settings.error) return { error: error || settings.error };
    return { request: { kind, relative: document.getElementById("goal-relative").checked, pose, ...settings } };
  }

  function move() {
    const { request, error } = goal(KIND.move);
    if (error) return note(error, "error");
    ask("EDSP_MOTION_REQUEST", request, request.relative ? "move by" : "move to");
  }

  function check() {
    const { request, error } = goal(KIND.check);
    latestCheck = 0;
    if (error) return note(error, "error", "check-reply");
    latestCheck = ask("EDSP_MOTION_REQUEST", request, "path check", "check-reply") || 0;
  }

  function checkSoon() {
    formTouched = true;
    latestCheck = 0;  // what was checked is no longer the form
    note("", "", "check-reply");
    clearTimeout(checkTimer);
    if (operator) checkTimer = setTimeout(check, CHECK_AFTER_EDIT_MS);
  }

  // One step along one axis of the form's frame, from the last target (the
  // planner allows at most 10 mm or 10 mrad a step).
  function jog(sign) {
    const axis = Number(document.getElementById("jog-axis").value);
    const { values, error } = numbers(["jog-step"], ["jog step"], [POSE_UNITS[axis]]);
    const settings = moveSettings();
    if (error || settings.error) return note(error || settings.error, "error");
    const pose = [0, 0, 0, 0, 0, 0];
    pose[axis] = sign * values[0];
    ask("EDSP_MOTION_REQUEST", { kind: KIND.jog, pose, ...settings }, `jog ${AXES[axis]} ${sign > 0 ? "+" : "−"}`);
  }

  function setPivot() {
    const { values, error } = numbers(["pivot-0", "pivot-1", "pivot-2"], ["pivot x", "pivot y", "pivot z"], [MM, MM, MM]);
    if (error) return note(error, "error");
    ask("EDSP_MOTION_REQUEST", { kind: KIND.pivot, point: values }, "pivot");
  }

  // A program: the named motions typed, or the trajectory CSV chosen (its whole text).
  function run() {
    const motions = document.getElementById("run-motions").value.trim();
    const file = document.getElementById("run-csv").files[0];
    if (!motions === !file) return note("run: name motions (Lz,Lx) or choose a trajectory CSV, not both", "error");
    if (motions) return ask("EDSP_MOTION_REQUEST", { kind: KIND.run, motions }, `run ${motions}`);
    if (file.size > MAX_CSV_BYTES) {
      return note(`run: ${file.name} is ${Math.ceil(file.size / 1024)} KiB; the panel sends at most ` +
                  `${MAX_CSV_BYTES / 1024} KiB (edsp-ctl run --csv has no such limit)`, "error");
    }
    const haltsBefore = halts;
    file.text().then((text) => {
      if (halts !== haltsBefore) return note(`run ${file.name}: not sent, halted while the file was read`, "error");
      ask("EDSP_MOTION_REQUEST", { kind: KIND.run, csv_text: text, csv_origin: file.name }, `run ${file.name}`);
    });
  }

  function halt() { ++halts; ask("EDSP_MOTION_REQUEST", { kind: KIND.halt }, "halt"); }
  function stop() { ++halts; ask("EDSP_MOTION_REQUEST", { kind: KIND.stop }, "stop"); }

  function onKey(event) {
    if (event.key !== "Escape" || event.repeat || !operator) return;
    event.preventDefault();
    if (event.shiftKey) stop(); else halt();
  }

  function setEnabled(enabled, why) {
    operator = enabled;
    for (const id of CONTROLS) document.getElementById(id).disabled = !enabled;
    document.getElementById("control-role").textContent = why;
  }

  return {
    // serverInfo: operators may publish; a viewer's panel shows no live controls.
    attach(ws, info) {
      socket = ws;
      KIND = JSON.parse((info.metadata || {}).request_kinds || "{}");
      const mayPublish = (info.capabilities || []).includes("clientPublish");
      setEnabled(mayPublish, mayPublish ? "operator (Esc halts, Shift+Esc stops)" : "viewer: read-only");
      if (mayPublish) {
        ws.send(JSON.stringify({ op: "advertise",
          channels: PUBLISHED.map((c) => ({ ...c, encoding: "json" })) }));
      }
    },
    detach() {
      socket = null;
      setEnabled(false, "disconnected");
    },
    bind() {
      document.getElementById("move").onclick = move;
      document.getElementById("check").onclick = check;
      document.getElementById("halt").onclick = halt;
      document.getElementById("stop").onclick = stop;
      document.getElementById("rearm").onclick = () => ask("EDSP_ARM", {}, "re-arm");
      document.getElementById("jog-minus").onclick = () => jog(-1);
      document.getElementById("jog-plus").onclick = () => jog(+1);
      document.getElementById("set-pivot").onclick = setPivot;
      document.getElementById("run").onclick = run;
      for (const id of [...AXES.map((_, i) => `goal-${i}`), "goal-frame", "goal-speed", "goal-speed-rot"]) {
        document.getElementById(id).oninput = checkSoon;
      }
      document.getElementById("goal-relative").onchange = checkSoon;
      document.addEventListener("keydown", onKey);
      setEnabled(false, "connecting");
    },
    // The form starts at the target the platform holds, until edited.
    prefill(target) {
      if (formTouched || !Array.isArray(target) || !target.every((v) => typeof v === "number")) return;
      target.forEach((v, i) => {
        document.getElementById(`goal-${i}`).value = (v / POSE_UNITS[i]).toFixed(i < 3 ? 3 : 4);
      });
      formTouched = true;  // once: a held pose's jitter never rewrites what the operator reads
    },
    // The pivot fields start at the pivot in force, until edited.
    prefillPivot(point) {
      const fields = [0, 1, 2].map((i) => document.getElementById(`pivot-${i}`));
      if (!Array.isArray(point) || fields.some((f) => f.value !== "" || f === document.activeElement)) return;
      point.forEach((v, i) => { fields[i].value = typeof v === "number" ? (v / MM).toFixed(3) : ""; });
    },
    // A status of level 2 from edsp-web: a request of this page it refused
    // (malformed, too many a second): the requests still waiting are not
    // coming back, and the operator reads why.
    onServerError(message) {
      if (pending.size === 0) return;
      pending.clear();
      latestCheck = 0;
      note(`edsp-web refused: ${message}`, "error");
    },
    // EDSP_MOTION_REPLY and EDSP_REPLY: the answer to one of this page's requests.
    onReply(reply) {
      const asked = pending.get(reply.request_id);
      if (asked === undefined) return;
      pending.delete(reply.request_id);
      if (asked.line === "check-reply" && reply.request_id !== latestCheck) return;  // the form changed since
      const ok = reply.accepted !== undefined ? reply.accepted : reply.code === 0;
      const took = ok && reply.kind === KIND.check && Number.isFinite(reply.duration_s)
        ? `, ${reply.duration_s.toFixed(2)} s` : "";
      note(`${asked.what}: ${ok ? "accepted" : "refused"}${took}${reply.reason ? ": " + reply.reason : ""}`,
           ok ? "" : "error", asked.line);
    },
  };
})();
