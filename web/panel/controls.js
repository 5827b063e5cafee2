// The operator's controls: a move to a pose (in {B}, or relative to the last
// target), halt (the planner decelerates along the path), stop (at the legs'
// limit) and re-arm (the actuator bridge, after it latched a hold). Each is
// a request published through the protocol's clientPublish, which edsp-web
// offers to operators only, and stamps with the group's session and
// "web:NAME"; the answer (EDSP_MOTION_REPLY, EDSP_REPLY) is shown beside it.
// The form's pose is checked along its whole path by the planner as it is
// edited (a check request), so its answer shows before the move is sent.
// Escape halts and Shift+Escape stops, wherever the focus is.
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

  const pending = new Map();  // request id -> {what, line}: the answer's line
  let socket = null, nextId = Date.now() * 1000, formTouched = false, operator = false, checkTimer = null;
  let latestCheck = 0;  // only the answer to the form as it is now is shown

  function channelId(topic) { return PUBLISHED.find((c) => c.topic === topic).id; }

  function note(text, cls, line = "control-reply") {
    const el = document.getElementById(line);
    el.textContent = text;
    el.className = cls || "";
  }

  function publish(topic, request) {
    const id = nextId++;
    const payload = new TextEncoder().encode(JSON.stringify({ ...request, request_id: id }));
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
    pending.set(id, { what, line });
    note(`${what}: sent`, "", line);
    return id;
  }

  // The form's pose in SI units, or why it is not one.
  function formPose() {
    const pose = [];
    for (let i = 0; i < 6; ++i) {
      const text = document.getElementById(`goal-${i}`).value.trim();
      const value = Number(text);
      if (text === "" || !Number.isFinite(value)) return { error: `${["x", "y", "z", "roll", "pitch", "yaw"][i]} is not a number` };
      pose.push(value * POSE_UNITS[i]);
    }
    return { pose };
  }

  function goal(kind) {
    const { pose, error } = formPose();
    if (error) return { error };
    return { request: { kind, relative: document.getElementById("goal-relative").checked, pose } };
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

  function halt() { ask("EDSP_MOTION_REQUEST", { kind: KIND.halt }, "halt"); }
  function stop() { ask("EDSP_MOTION_REQUEST", { kind: KIND.stop }, "stop"); }

  function onKey(event) {
    if (event.key !== "Escape" || event.repeat || !operator) return;
    event.preventDefault();
    if (event.shiftKey) stop(); else halt();
  }

  function setEnabled(enabled, why) {
    operator = enabled;
    for (const id of ["move", "check", "halt", "stop", "rearm"]) document.getElementById(id).disabled = !enabled;
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
      for (let i = 0; i < 6; ++i) document.getElementById(`goal-${i}`).oninput = checkSoon;
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
