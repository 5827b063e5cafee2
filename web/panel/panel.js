// The panel: a foxglove.websocket.v1 client of edsp-web. The token the page
// was opened with (?token=T) opens the WebSocket too; the page's scripts and
// styles need none. The 3-D view is view3d.js, the plots plots.js, the
// operator's requests controls.js, the calibration view calibration.js.
"use strict";

const SUBPROTOCOL = "foxglove.websocket.v1";
const WATCHED = ["EDSP_CONFIG", "EDSP_PLATFORM_STATE", "EDSP_LEG_STATE", "EDSP_LEG_COMMAND", "EDSP_TRACKER",
  "EDSP_MOTION_STATUS", "EDSP_STATUS", "EDSP_FAULT", "EDSP_MOTION_REPLY", "EDSP_REPLY"];
const FAULT_SEVERITY = ["info", "warning", "error"];
// motion_status_t's STATE_* and END_*, by value
const MOTION_STATE = ["idle", "moving", "halting", "holding", "refused", "fault", "cueing"];
const MOTION_END = ["", "completed", "halted", "stopped"];
const MAX_FAULTS = 200;

const panel = {
  channels: new Map(),      // id -> advertised channel
  subscriptions: new Map(), // subscription id -> topic
  nodes: new Map(),         // node name -> its table row
};

const TOKEN = new URL(window.location.href).searchParams.get("token");

function socketUrl() {
  const url = new URL(window.location.href);
  const scheme = url.protocol === "https:" ? "wss:" : "ws:";
  return `${scheme}//${url.host}/` + (TOKEN ? `?token=${encodeURIComponent(TOKEN)}` : "");
}

function setConnection(text, cls) {
  const el = document.getElementById("connection");
  el.textContent = text;
  el.className = "state " + cls;
}

function subscribe(ws) {
  const subscriptions = [];
  let next = 1;
  for (const [id, channel] of panel.channels) {
    if (WATCHED.includes(channel.topic)) {
      panel.subscriptions.set(next, channel.topic);
      subscriptions.push({ id: next++, channelId: id });
    }
  }
  ws.send(JSON.stringify({ op: "subscribe", subscriptions }));
}

function showPlatform(state) {
  showPose(state);
  plots.onPlatformState(state);
  view3d.setPlatformState(state);
  controls.prefill(state.target_pose);
  showStroke();
}

// Each leg's share of its stroke, from the 3-D view's legs as drawn.
function showStroke() {
  const legs = view3d.legs();
  const table = document.getElementById("legs");
  if (!legs) return;
  legs.forEach((leg, i) => {
    const row = table.rows[i + 1];
    if (row) row.cells[3].textContent = (leg.stroke_share * 100).toFixed(1);
  });
}

function showPose(state) {
  // mm and degrees; a value the server sent as null (not finite) shown as a dash
  state.pose.forEach((v, i) => {
    const shown = v === null ? "–" : (i < 3 ? v * 1e3 : v * 180 / Math.PI).toFixed(i < 3 ? 3 : 4);
    document.getElementById(`pose-${i}`).textContent = shown;
  });
  const residual = state.fk_residual_m === null ? "–" : (state.fk_residual_m * 1e6).toFixed(2);
  document.getElementById("fk").textContent = `forward kinematics status ${state.fk_status}, residual ${residual} µm`;
}

function showLegs(state) {
  plots.onLegState(state);
  const table = document.getElementById("legs");
  state.encoder_length_m.forEach((length, i) => {
    let row = table.rows[i + 1];
    if (!row) {
      row = table.insertRow();
      for (let c = 0; c < 4; ++c) row.insertCell();
      row.cells[0].textContent = `${i + 1}`;
    }
    row.cells[1].textContent = length === null ? "–" : (length * 1e3).toFixed(3);
    row.cells[2].textContent = `${state.drive_status[i]}`;
  });
}

function showNode(status) {
  plots.onStatus(status);
  let row = panel.nodes.get(status.node);
  if (!row) {
    row = document.getElementById("nodes").insertRow();
    for (let c = 0; c < 5; ++c) row.insertCell();
    row.cells[0].textContent = status.node;
    panel.nodes.set(status.node, row);
  }
  row.cells[1].textContent = `${status.state}`;
  row.cells[2].textContent = `${status.loop_p99_us}`;
  row.cells[3].textContent = `${status.deadline_misses}`;
  row.cells[4].textContent = `${status.rejected}`;
}

function showFault(fault) {
  const list = document.getElementById("faults");
  const item = document.createElement("li");
  const when = new Date(fault.utime / 1000).toISOString().substring(11, 23);
  item.textContent = `${when} ${fault.node} [${FAULT_SEVERITY[fault.severity] ?? fault.severity}] code ${fault.code} on ${fault.channel}: ${fault.reason}`;
  if (fault.severity >= 2) item.className = "error";
  list.prepend(item);
  while (list.children.length > MAX_FAULTS) list.lastChild.remove();
}

function showMotion(status) {
  view3d.setPivot(status.pivot);
  view3d.setWorkFrame(status.frame, status.frame_pose);
  controls.prefillPivot(status.pivot);
  const ended = MOTION_END[status.last_end] ? `, last motion ${MOTION_END[status.last_end]}` : "";
  const onTarget = status.on_target ? ", on target" : "";
  const motion = document.getElementById("motion");
  motion.textContent = `${MOTION_STATE[status.state] ?? status.state}${onTarget}: ${status.activity || "nothing asked yet"}, ` +
    `progress ${((status.progress ?? 0) * 100).toFixed(0)}%, ${status.queued} queued${ended}, frame ${status.frame || "base"}` +
    (status.reason ? ` (${status.reason})` : "");
  motion.dataset.state = MOTION_STATE[status.state] ?? "";
  motion.dataset.requestId = `${status.request_id}`;
  motion.dataset.onTarget = status.on_target ? "1" : "0";
}

const SHOW = {
  EDSP_CONFIG: (config) => {
    view3d.setConfig(config, document.getElementById("view"));
    calibration.onConfig(config);
  },
  EDSP_LEG_COMMAND: (command) => calibration.onLegCommand(command),
  EDSP_TRACKER: (sample) => plots.onTracker(sample),
  EDSP_PLATFORM_STATE: showPlatform,
  EDSP_LEG_STATE: showLegs,
  EDSP_MOTION_STATUS: showMotion,
  EDSP_STATUS: showNode,
  EDSP_FAULT: showFault,
  EDSP_MOTION_REPLY: (reply) => controls.onReply(reply),
  EDSP_REPLY: (reply) => controls.onReply(reply),
};

function onBinary(data) {
  const view = new DataView(data);
  if (view.getUint8(0) !== 1) return;  // message data only
  const topic = panel.subscriptions.get(view.getUint32(1, true));
  const message = JSON.parse(new TextDecoder().decode(new Uint8Array(data, 13)));
  if (topic && SHOW[topic]) SHOW[topic](message);
}

function onText(text) {
  const message = JSON.parse(text);
  if (message.op === "serverInfo") {
    document.getElementById("server").textContent = `${message.name}, session ${message.sessionId}`;
    controls.attach(panel.ws, message);
    calibration.attach(message, TOKEN);
  } else if (message.op === "advertise") {
    for (const channel of message.channels) panel.channels.set(channel.id, channel);
    subscribe(panel.ws);
  } else if (message.op === "status") {
    console.warn(`edsp-web: ${message.message}`);
    if (message.level === 2) controls.onServerError(message.message);
  }
}

function connect() {
  const ws = new WebSocket(socketUrl(), [SUBPROTOCOL]);
  ws.binaryType = "arraybuffer";
  panel.ws = ws;
  ws.onopen = () => setConnection("connected", "open");
  ws.onclose = () => {
    setConnection("disconnected: retrying", "closed");
    controls.detach();
    panel.channels.clear();
    panel.subscriptions.clear();
    setTimeout(connect, 1000);
  };
  ws.onmessage = (event) => (typeof event.data === "string" ? onText(event.data) : onBinary(event.data));
}

controls.bind();
plots.bind();
view3d.start();
connect();
