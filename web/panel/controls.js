// The operator's controls: a move to a pose (in {B}, or relative to the last
// target), halt (the planner decelerates along the path), stop (at the legs'
// limit) and re-arm (the actuator bridge, after it latched a hold). Each is
// a request published through the protocol's clientPublish, which edsp-web
// offers to operators only, and stamps with the group's session and
// "web:NAME"; the answer (EDSP_MOTION_REPLY, EDSP_REPLY) is shown beside it.
"use strict";

const controls = (() => {
  const PUBLISHED = [
    { id: 1, topic: "EDSP_MOTION_REQUEST", schemaName: "edsp.motion_request_t" },
    { id: 2, topic: "EDSP_ARM", schemaName: "edsp.arm_t" },
  ];
  const KIND = { move: 1, halt: 4, stop: 5 };
  const MM = 1e-3, DEG = Math.PI / 180;
  const POSE_UNITS = [MM, MM, MM, DEG, DEG, DEG];

  const pending = new Map();  // request id -> what it asked, for the answer's line
  let socket = null, nextId = Date.now() * 1000, formTouched = false;

  function channelId(topic) { return PUBLISHED.find((c) => c.topic === topic).id; }

  function note(text, cls) {
    const el = document.getElementById("control-reply");
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

  function ask(topic, request, what) {
    if (!socket || socket.readyState !== WebSocket.OPEN) return note("not connected", "error");
    pending.set(publish(topic, request), what);
    note(`${what}: sent`);
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

  function move() {
    const { pose, error } = formPose();
    if (error) return note(error, "error");
    const relative = document.getElementById("goal-relative").checked;
    ask("EDSP_MOTION_REQUEST", { kind: KIND.move, relative, pose }, relative ? "move by" : "move to");
  }

  function setEnabled(enabled, why) {
    for (const id of ["move", "halt", "stop", "rearm"]) document.getElementById(id).disabled = !enabled;
    document.getElementById("control-role").textContent = why;
  }

  return {
    // serverInfo: operators may publish; a viewer's panel shows no live controls.
    attach(ws, info) {
      socket = ws;
      const operator = (info.capabilities || []).includes("clientPublish");
      setEnabled(operator, operator ? "operator" : "viewer: read-only");
      if (operator) {
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
      document.getElementById("halt").onclick = () => ask("EDSP_MOTION_REQUEST", { kind: KIND.halt }, "halt");
      document.getElementById("stop").onclick = () => ask("EDSP_MOTION_REQUEST", { kind: KIND.stop }, "stop");
      document.getElementById("rearm").onclick = () => ask("EDSP_ARM", {}, "re-arm");
      for (let i = 0; i < 6; ++i) document.getElementById(`goal-${i}`).oninput = () => { formTouched = true; };
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
    // EDSP_MOTION_REPLY and EDSP_REPLY: the answer to one of this page's requests.
    onReply(reply) {
      const what = pending.get(reply.request_id);
      if (what === undefined) return;
      pending.delete(reply.request_id);
      const ok = reply.accepted !== undefined ? reply.accepted : reply.code === 0;
      note(`${what}: ${ok ? "accepted" : "refused"}${reply.reason ? ": " + reply.reason : ""}`, ok ? "" : "error");
    },
  };
})();
