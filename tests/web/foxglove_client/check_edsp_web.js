// edsp-web through Foxglove's own client library of foxglove.websocket.v1
// (@foxglove/ws-protocol's FoxgloveClient, the one Foxglove and Lichtblick
// connect with), as such a tool would use it: the server's info, every
// channel's schema parsed as a JSON schema, messages decoded by their
// advertised encoding and held to their schema, an operator's request sent
// on a client channel and answered, and a viewer's refused. Prints what it
// saw as one JSON object; exits 1 naming the first thing that failed.
//   node check_edsp_web.js ws://HOST:PORT OPERATOR_TOKEN VIEWER_TOKEN
"use strict";

const { FoxgloveClient } = require("@foxglove/ws-protocol");
const WebSocket = require("ws");

const [url, operatorToken, viewerToken] = process.argv.slice(2);
const WATCH_S = 3;
const WATCHED = ["EDSP_PLATFORM_STATE", "EDSP_LEG_STATE", "EDSP_MOTION_STATUS", "EDSP_MOTION_REPLY", "EDSP_STATUS"];

function fail(what) {
  process.stderr.write(`check_edsp_web: ${what}\n`);
  process.exit(1);
}

// A client on `token`, with what it heard: the server's info, the
// channels it advertised, messages per topic and statuses.
function open(token) {
  const client = new FoxgloveClient({
    ws: new WebSocket(`${url}/?token=${encodeURIComponent(token)}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
  });
  const heard = { info: null, channels: new Map(), statuses: [], messages: new Map(), topics: new Map() };
  client.on("error", (error) => fail(`the connection failed: ${error.message || error}`));
  client.on("serverInfo", (info) => { heard.info = info; });
  client.on("status", (status) => heard.statuses.push(status));
  client.on("advertise", (channels) => channels.forEach((c) => heard.channels.set(c.id, c)));
  client.on("message", ({ subscriptionId, data }) => {
    const topic = heard.topics.get(subscriptionId);
    const text = new TextDecoder().decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    if (!heard.messages.has(topic)) heard.messages.set(topic, []);
    heard.messages.get(topic).push(JSON.parse(text));
  });
  return { client, heard };
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

async function until(what, seconds, test) {
  for (let waited = 0; waited < seconds * 1000; waited += 50) {
    const value = test();
    if (value) return value;
    await sleep(50);
  }
  return fail(`${what} within ${seconds} s`);
}

// A message against its channel's JSON schema: an object with exactly the
// schema's required properties, each of its type and array length.
function schemaProblem(message, schema) {
  const keys = Object.keys(message);
  if (JSON.stringify(keys) !== JSON.stringify(schema.required)) return `keys ${keys} against ${schema.required}`;
  for (const key of keys) {
    let [value, property] = [message[key], schema.properties[key]];
    while (property.type === "array") {
      if (!Array.isArray(value) || (property.minItems !== undefined && value.length !== property.minItems)) {
        return `${key} is not an array of ${property.minItems}`;
      }
      [value, property] = [value[0], property.items];
    }
    const types = [].concat(property.type);
    const type = value === null ? "null" : Number.isInteger(value) && types.includes("integer") ? "integer"
      : typeof value === "number" ? "number" : typeof value;
    if (!types.includes(type)) return `${key}: ${type} where the schema says ${types}`;
  }
  return null;
}

function topicId(heard, topic) {
  for (const [id, c] of heard.channels) if (c.topic === topic) return id;
  return fail(`${topic} was not advertised`);
}

async function operatorSession() {
  const { client, heard } = open(operatorToken);
  await until("serverInfo and the channels", 10, () => heard.info && heard.channels.size > 0);
  const schemas = new Map();
  for (const c of heard.channels.values()) {
    if (c.encoding !== "json" || c.schemaEncoding !== "jsonschema") fail(`${c.topic}: ${c.encoding}/${c.schemaEncoding}`);
    schemas.set(c.topic, JSON.parse(c.schema));
  }
  for (const topic of WATCHED) heard.topics.set(client.subscribe(topicId(heard, topic)), topic);
  await sleep(WATCH_S * 1000);
  const counts = {};
  for (const [topic, messages] of heard.messages) {
    counts[topic] = messages.length;
    for (const m of messages) {
      const problem = schemaProblem(m, schemas.get(topic));
      if (problem) fail(`a ${topic} message does not fit its schema: ${problem}`);
    }
  }
  // an operator's request on a client channel, answered on EDSP_MOTION_REPLY
  const kinds = JSON.parse(heard.info.metadata.request_kinds);
  const channel = client.advertise({ topic: "EDSP_MOTION_REQUEST", encoding: "json", schemaName: "edsp.motion_request_t" });
  const requestId = Date.now() * 1000 + 7;
  const request = { kind: kinds.check, relative: true, pose: [0, 0, 0.001, 0, 0, 0], request_id: requestId };
  client.sendMessage(channel, new TextEncoder().encode(JSON.stringify(request)));
  const reply = await until("the planner's answer", 10, () =>
    (heard.messages.get("EDSP_MOTION_REPLY") || []).find((r) => r.request_id === requestId));
  client.close();
  return { name: heard.info.name, capabilities: heard.info.capabilities, channels: heard.channels.size,
           counts, seconds: WATCH_S, reply: { accepted: reply.accepted, reason: reply.reason } };
}

async function viewerSession() {
  const { client, heard } = open(viewerToken);
  await until("the viewer's serverInfo", 10, () => heard.info && heard.channels.size > 0);
  const channel = client.advertise({ topic: "EDSP_MOTION_REQUEST", encoding: "json", schemaName: "edsp.motion_request_t" });
  client.sendMessage(channel, new TextEncoder().encode(JSON.stringify({ kind: 2, request_id: 1 })));
  const refused = await until("the viewer's refusal", 10, () => heard.statuses.find((s) => s.level === 2));
  client.close();
  return { capabilities: heard.info.capabilities, refusal: refused.message };
}

(async () => {
  const operator = await operatorSession();
  const viewer = await viewerSession();
  process.stdout.write(JSON.stringify({ operator, viewer }) + "\n");
  process.exit(0);
})().catch((error) => fail(error.stack || String(error)));
