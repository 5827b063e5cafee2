"""edsp-web beside a live sim group, through a foxglove.websocket.v1 client
written here from the protocol's specification (github.com/foxglove/
ws-protocol, docs/spec.md), not from edsp's code, on python3-websockets;
schemas and messages held to the .lcm files as lcm_pure reads them.

Rates: a cyclic channel must come at most at the cap (plus the one frame a
window's edges can add) and at no less than a third of it: the server looks
for due frames every 5 ms, so a third leaves a starved machine two of every
three cap intervals to lose and still fails a feed that stops or collapses."""
import asyncio
import json
import os
import re
import struct
import time
import http.client
import ssl
import subprocess

import pytest
import websockets

import lcm_pure
import served_web

SOURCE = os.environ["EDSP_SOURCE_DIR"]
BIN = os.environ["EDSP_BIN_DIR"]
SUBPROTOCOL = "foxglove.websocket.v1"
CAP_HZ = 30.0
LCM_TYPES = lcm_pure.parse_lcm_types(os.path.join(SOURCE, "lcmtypes"))
CYCLIC = ["EDSP_SETPOINT", "EDSP_LEG_COMMAND", "EDSP_LEG_STATE", "EDSP_PLATFORM_STATE", "EDSP_TRACKER",
          "EDSP_RIG_TRUTH"]


def _edsp_channels():
    """Every EDSP_* channel name of interfaces.md's table."""
    text = open(os.path.join(SOURCE, "docs", "interfaces.md"), encoding="utf-8").read()
    return set(re.findall(r"^\| `(EDSP_[A-Z_]+)` \|", text, flags=re.M))


def _rss_kib(pid):
    with open(f"/proc/{pid}/status", encoding="ascii") as f:
        return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    with served_web.serve(tmp_path_factory.mktemp("web")) as server:
        yield server


class Client:
    """A foxglove.websocket.v1 client: server info, channels, subscriptions,
    message data frames decoded by the spec's layout."""

    def __init__(self, ws, info, channels):
        self.ws, self.info = ws, info
        self.channels = {c["topic"]: c for c in channels}
        self.topics = {}  # subscription id -> topic
        self.statuses = []

    @classmethod
    async def open(cls, port, token, origin=None, max_queue=64):
        ws = await websockets.connect(f"ws://127.0.0.1:{port}/?token={token}", subprotocols=[SUBPROTOCOL],
                                      origin=origin, max_queue=max_queue, max_size=1 << 24)
        info = json.loads(await ws.recv())
        advertise = json.loads(await ws.recv())
        assert info["op"] == "serverInfo" and advertise["op"] == "advertise"
        return cls(ws, info, advertise["channels"])

    async def subscribe(self, topics):
        subscriptions = []
        for topic in topics:
            sid = len(self.topics) + 100
            self.topics[sid] = topic
            subscriptions.append({"id": sid, "channelId": self.channels[topic]["id"]})
        await self.ws.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))

    async def collect(self, seconds):
        """{topic: [(receive ns, message)]} of what came in `seconds`, and the
        time it really took."""
        got = {topic: [] for topic in self.topics.values()}
        start = time.monotonic()
        while (left := seconds - (time.monotonic() - start)) > 0:
            try:
                frame = await asyncio.wait_for(self.ws.recv(), timeout=left)
            except asyncio.TimeoutError:
                break
            if isinstance(frame, str):
                self.statuses.append(json.loads(frame))
                continue
            assert frame[0] == 0x01, f"opcode {frame[0]}"
            sid, receive_ns = struct.unpack_from("<IQ", frame, 1)
            got[self.topics[sid]].append((receive_ns, json.loads(frame[13:])))
        return got, time.monotonic() - start


def run(coroutine):
    return asyncio.run(coroutine)


def _expect_lcm_fields(message, type_name):
    fields = LCM_TYPES[type_name]
    assert list(message) == [f for f, _, _ in fields]
    for name, lcm_type, dims in fields:
        value = message[name]
        for n in dims:
            assert isinstance(value, list) and len(value) == n, name
            value = value[0]
        expected = {"string": str, "double": (float, int, type(None))}.get(lcm_type, int)
        assert isinstance(value, expected), (name, lcm_type, value)


def test_every_channel_is_advertised_with_its_lcm_fields_as_schema(served):
    async def body():
        client = await Client.open(served["port"], served["viewer"])
        await client.ws.close()
        return client

    client = run(body())
    assert client.info["sessionId"]
    assert set(client.channels) == _edsp_channels()
    for topic, channel in client.channels.items():
        type_name = channel["schemaName"].removeprefix("edsp.")
        assert channel["encoding"] == "json" and channel["schemaEncoding"] == "jsonschema"
        schema = json.loads(channel["schema"])
        assert schema["required"] == [f for f, _, _ in LCM_TYPES[type_name]], topic


def test_the_server_reports_on_edsp_status_as_every_node_does(served):
    """Once a second: running, what it took from the bus and what it sent,
    both growing while a client watches (its own frames among them)."""
    async def body():
        client = await Client.open(served["port"], served["viewer"])
        await client.subscribe(["EDSP_STATUS", "EDSP_PLATFORM_STATE"])
        got, _ = await client.collect(3.5)
        await client.ws.close()
        return got

    got = run(body())
    web = [m for _, m in got["EDSP_STATUS"] if m["node"] == "web"]
    seen = [(m["pid"], m["seq"], m["utime"], m["state"], m["messages_in"], m["messages_out"]) for m in web]
    assert len(web) >= 2, [m["node"] for _, m in got["EDSP_STATUS"]]
    assert all(m["pid"] == served["pid"] for m in web), (served["pid"], seen)
    assert all(m["state"] == 1 for m in web), seen  # STATE_RUNNING
    # Growth, not a count: the first report seen may be the one the server
    # sent as it started, before the bus brought it anything, reaching the
    # board after the subscription on a slow machine.
    assert web[-1]["messages_in"] > web[0]["messages_in"], seen
    assert web[-1]["messages_out"] > web[0]["messages_out"], seen


def test_cyclic_channels_come_at_the_cap_newest_first_and_as_the_lcm_types_say(served):
    async def body():
        client = await Client.open(served["port"], served["viewer"])
        await client.subscribe(CYCLIC)
        got, elapsed = await client.collect(4.0)
        await client.ws.close()
        return got, elapsed, client

    got, elapsed, client = run(body())
    for topic in CYCLIC:
        frames = got[topic]
        assert len(frames) <= CAP_HZ * elapsed + 2, (topic, len(frames), elapsed)
        assert len(frames) >= CAP_HZ * elapsed / 3, (topic, len(frames), elapsed)
        type_name = client.channels[topic]["schemaName"].removeprefix("edsp.")
        for _, message in frames:
            _expect_lcm_fields(message, type_name)
        seqs = [m["seq"] for _, m in frames]
        assert seqs == sorted(seqs) and len(set(seqs)) == len(seqs), topic  # never a message twice, never older
        times = [t for t, _ in frames]
        assert times == sorted(times)
        # Latest-wins: a 1 kHz channel's frames skip the messages between them.
        if topic in ("EDSP_LEG_STATE", "EDSP_RIG_TRUTH"):
            assert (seqs[-1] - seqs[0]) / max(len(seqs) - 1, 1) > 5, topic
    # The platform stands at home: the measured pose is the rig's truth.
    measured = got["EDSP_PLATFORM_STATE"][-1][1]["pose"]
    truth = got["EDSP_RIG_TRUTH"][-1][1]["pose"]
    assert max(abs(a - b) for a, b in zip(measured[:3], truth[:3])) < 1e-4, (measured, truth)


def test_every_request_and_reply_arrives_however_fast_they_come(served):
    ctl = os.path.join(BIN, "edsp-ctl")
    n = 12

    async def check_out_of_reach():  # refused, with a reply
        proc = await asyncio.create_subprocess_exec(
            ctl, "check", "--pose", "0,0,5,0,0,0", "--group", served["group"], "--json",
            stdout=asyncio.subprocess.DEVNULL, stderr=asyncio.subprocess.DEVNULL)
        await proc.wait()

    async def body():
        client = await Client.open(served["port"], served["viewer"])
        await client.subscribe(["EDSP_MOTION_REQUEST", "EDSP_MOTION_REPLY"])
        # The subscription holds once a reply comes through it (the protocol
        # acknowledges none): one request first, then the n counted.
        await check_out_of_reach()
        warm = await _until(client, 30.0, lambda got: got["EDSP_MOTION_REPLY"])
        assert warm["EDSP_MOTION_REPLY"], "no reply forwarded within 30 s"
        for _ in range(n):
            await check_out_of_reach()
        # Each edsp-ctl had its reply before it exited: all are on their way.
        got = await _until(client, 30.0, lambda got: all(
            len({m["request_id"] for _, m in got[topic]}) >= n for topic in ("EDSP_MOTION_REQUEST", "EDSP_MOTION_REPLY")))
        await client.ws.close()
        return got

    got = run(body())
    replies = [m for _, m in got["EDSP_MOTION_REPLY"]]
    requests = [m for _, m in got["EDSP_MOTION_REQUEST"]]
    assert len({r["request_id"] for r in replies}) == n, replies
    assert all(not r["accepted"] for r in replies)
    assert {r["request_id"] for r in replies} <= {r["request_id"] for r in requests}


def _get(port, path, headers=None):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request("GET", path, headers=headers or {})
    response = conn.getresponse()
    body = response.read().decode("utf-8", "replace")
    conn.close()
    return response.status, body


def test_pages_need_a_token_their_assets_none_and_both_stay_inside_their_folders(served):
    port, viewer = served["port"], served["viewer"]
    status, body = _get(port, f"/?token={viewer}")
    assert status == 200 and "edsp panel" in body
    assert _get(port, f"/index.html?token={viewer}")[0] == 200
    status, body = _get(port, "/")
    assert status == 401 and "token" in body
    assert _get(port, "/index.html")[0] == 401
    assert _get(port, "/?token=0123")[0] == 401
    # the panel's code and Debian's libraries are the same for everyone: no token, nothing of the rig
    assert _get(port, "/panel.js")[0] == 200
    status, body = _get(port, "/javascript/three/three.min.js")
    assert status == 200 and "REVISION" in body
    for escape in ("/../../etc/passwd", "/javascript/../../../etc/passwd", "/javascript/%2e%2e/x", "/.hidden",
                   "/javascript/three/", "/javascript/"):
        assert _get(port, f"{escape}?token={viewer}")[0] == 404, escape


def test_over_tls_the_pages_and_the_protocol_need_the_certificate_and_a_token(served):
    """--tls-cert/--tls-key: https and wss with the given certificate; a
    client that trusts it gets the page and the protocol with a token and
    is refused without one; plain HTTP on the port gets nothing served."""
    work = served["work"]
    cert, key = served_web.certificate(work)
    trusting = ssl.create_default_context(cafile=cert)
    with served_web.server(work / "tls.err", served["group"], served["tokens"],
                           ["--tls-cert", cert, "--tls-key", key]) as (port, _):
        def get(path):
            conn = http.client.HTTPSConnection("127.0.0.1", port, timeout=10, context=trusting)
            conn.request("GET", path)
            response = conn.getresponse()
            return response.status, response.read().decode()

        status, body = get(f"/?token={served['viewer']}")
        assert status == 200 and "edsp panel" in body
        assert get("/")[0] == 401

        async def watch():
            async with websockets.connect(f"wss://127.0.0.1:{port}/?token={served['viewer']}",
                                          subprotocols=[SUBPROTOCOL], ssl=trusting) as ws:
                return json.loads(await ws.recv())

        assert run(watch())["op"] == "serverInfo"
        # a client that does not trust the certificate is refused by its own TLS
        with pytest.raises(ssl.SSLCertVerificationError):
            http.client.HTTPSConnection("127.0.0.1", port, timeout=10,
                                        context=ssl.create_default_context()).request("GET", "/")
        plain = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
        with pytest.raises((http.client.HTTPException, ConnectionError, OSError)):
            plain.request("GET", f"/?token={served['viewer']}")
            plain.getresponse().read()


def test_a_key_that_is_not_the_certificates_is_refused_at_start_naming_it(served):
    work = served["work"]
    cert, _ = served_web.certificate(work, "one")
    _, other_key = served_web.certificate(work, "two")
    result = subprocess.run([served_web.WEB, "--group", served["group"], "--port", "0", "--tokens", served["tokens"],
                             "--tls-cert", cert, "--tls-key", other_key], capture_output=True, text=True, timeout=30)
    assert result.returncode != 0 and other_key in result.stderr and cert in result.stderr, result.stderr
    result = subprocess.run([served_web.WEB, "--group", served["group"], "--port", "0", "--tokens", served["tokens"],
                             "--tls-cert", cert], capture_output=True, text=True, timeout=30)
    assert result.returncode != 0 and "--tls-key" in result.stderr, result.stderr


def test_websockets_refuse_a_wrong_token_a_foreign_origin_and_no_subprotocol(served):
    port, viewer = served["port"], served["viewer"]

    async def status_of(url, **kwargs):
        try:
            ws = await websockets.connect(url, **kwargs)
        except websockets.exceptions.InvalidStatusCode as e:
            return e.status_code
        await ws.close()
        return 101

    assert run(status_of(f"ws://127.0.0.1:{port}/?token=nope", subprotocols=[SUBPROTOCOL])) == 401
    assert run(status_of(f"ws://127.0.0.1:{port}/", subprotocols=[SUBPROTOCOL])) == 401
    assert run(status_of(f"ws://127.0.0.1:{port}/?token={viewer}", subprotocols=[SUBPROTOCOL],
                         origin="http://evil.example")) == 403
    assert run(status_of(f"ws://127.0.0.1:{port}/?token={viewer}")) == 400
    assert run(status_of(f"ws://127.0.0.1:{port}/?token={viewer}", subprotocols=[SUBPROTOCOL],
                         origin=f"http://127.0.0.1:{port}")) == 101


def test_ten_thousand_bad_frames_are_answered_change_nothing_and_starve_no_one(served):
    viewer = served["viewer"]
    bad = ["not json", "[]", '{"op":"publish"}', '{"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]}',
           '{"op":"unsubscribe","subscriptionIds":[12345]}', b"\x01\x00\x00\x00\x00{}"]

    async def flood(client):
        """How many it sent before the server let it go (a client that sends
        and does not read its answers is dropped: also serving the others)."""
        for i in range(10000):
            try:
                await client.ws.send(bad[i % len(bad)])
            except websockets.exceptions.ConnectionClosed:
                return i
            if i % 100 == 0:
                await asyncio.sleep(0)
        return 10000

    async def drain(client, flooding):
        """Every answer, until the flood is over and 2 s pass without one;
        True if the server closed the connection."""
        quiet_since = None
        while True:
            try:
                frame = await asyncio.wait_for(client.ws.recv(), timeout=0.2)
                quiet_since = None
                if isinstance(frame, str):
                    client.statuses.append(json.loads(frame))
            except asyncio.TimeoutError:
                if flooding.done():
                    quiet_since = quiet_since or time.monotonic()
                    if time.monotonic() - quiet_since > 2.0:
                        return False
            except websockets.exceptions.ConnectionClosed:
                return True

    async def body():
        watcher = await Client.open(served["port"], viewer)
        await watcher.subscribe(["EDSP_LEG_STATE", "EDSP_RIG_TRUTH"])
        before, before_s = await watcher.collect(2.0)
        attacker = await Client.open(served["port"], viewer)
        flooding = asyncio.ensure_future(flood(attacker))
        draining = asyncio.ensure_future(drain(attacker, flooding))
        during, during_s = await watcher.collect(4.0)
        sent = await flooding
        closed = await draining
        await attacker.ws.close()
        after, _ = await watcher.collect(0.5)
        await watcher.ws.close()
        newcomer = await Client.open(served["port"], viewer)  # still serving
        await newcomer.ws.close()
        return before, before_s, during, during_s, after, attacker, sent, closed

    before, before_s, during, during_s, after, attacker, sent, closed = run(body())
    errors = [s for s in attacker.statuses if s.get("level") == 2]
    # Each bad frame answered, unless the server let the client go (it
    # holds at most 256 unread answers for anyone).
    assert len(errors) == sent or (closed and errors), (sent, len(errors), closed)
    assert all(s["message"] for s in errors)
    assert {s["message"] for s in errors} > {errors[0]["message"]}  # each names its own fault
    # The watcher kept its feed: a third of the rate it had before the flood.
    assert before["EDSP_LEG_STATE"], "the watcher had no feed to compare with"
    assert len(during["EDSP_LEG_STATE"]) / during_s >= len(before["EDSP_LEG_STATE"]) / before_s / 3
    # Nothing moved: the rig's truth before and after the flood.
    p0, p1 = before["EDSP_RIG_TRUTH"][-1][1]["pose"], after["EDSP_RIG_TRUTH"][-1][1]["pose"]
    assert max(abs(a - b) for a, b in zip(p0, p1)) < 1e-6


def test_a_client_that_stops_reading_slows_no_one_and_holds_no_backlog(served):
    port, viewer, pid = served["port"], served["viewer"], served["pid"]

    async def body():
        watcher = await Client.open(port, viewer)
        await watcher.subscribe(["EDSP_LEG_STATE"])
        before, before_s = await watcher.collect(2.0)
        rss_before = _rss_kib(pid)
        stalled = await Client.open(port, viewer, max_queue=1)
        await stalled.subscribe(list(stalled.channels))  # everything, and then reads nothing
        during, during_s = await watcher.collect(12.0)
        rss_after = _rss_kib(pid)
        # It vanishes as a stalled client does: a close handshake would wait
        # on the frames it never read (websockets' close_timeout, twice).
        stalled.ws.transport.abort()
        await watcher.ws.close()
        return len(before["EDSP_LEG_STATE"]) / before_s, len(during["EDSP_LEG_STATE"]) / during_s, \
            rss_before, rss_after

    rate_before, rate_during, rss_before, rss_after = run(body())
    assert rate_before > 0, "the watcher had no feed to compare with"
    assert rate_during >= 0.7 * rate_before, (rate_before, rate_during)
    # One frame batch in flight for the stalled client, not twelve seconds of them.
    assert rss_after - rss_before < 16 * 1024, (rss_before, rss_after)


async def _until(client, seconds, done):
    """Frames until done(got) or `seconds`; what came."""
    got = {topic: [] for topic in client.topics.values()}
    deadline = time.monotonic() + seconds
    while not done(got) and time.monotonic() < deadline:
        more, _ = await client.collect(0.2)
        for topic, frames in more.items():
            got[topic].extend(frames)
    return got


def _request_frame(channel_id, request):
    return b"\x01" + struct.pack("<I", channel_id) + json.dumps(request).encode()


ADVERTISE_MOTION = json.dumps({"op": "advertise", "channels": [
    {"id": 1, "topic": "EDSP_MOTION_REQUEST", "encoding": "json", "schemaName": "edsp.motion_request_t"}]})


def test_an_operators_move_lands_and_one_out_of_reach_is_refused_with_the_planners_reason(served):
    async def body():
        op = await Client.open(served["port"], served["operator"])
        await op.subscribe(["EDSP_MOTION_REPLY", "EDSP_MOTION_STATUS", "EDSP_RIG_TRUTH", "EDSP_MOTION_REQUEST"])
        before = await _until(op, 5, lambda g: g["EDSP_RIG_TRUTH"])
        await op.ws.send(ADVERTISE_MOTION)
        await op.ws.send(_request_frame(1, {"request_id": 9001, "kind": 1, "pose": [0, 0, 5, 0, 0, 0]}))
        await op.ws.send(_request_frame(1, {"request_id": 9002, "kind": 1, "relative": 1,
                                            "pose": [0, 0, 0.005, 0, 0, 0]}))

        def landed(got):
            return any(m["request_id"] == 9002 and m["on_target"] for _, m in got["EDSP_MOTION_STATUS"])

        moving = await _until(op, 60, landed)
        after = await _until(op, 2, lambda g: len(g["EDSP_RIG_TRUTH"]) > 5)
        await op.ws.close()
        return op, before, moving, after

    op, before, moving, after = run(body())
    assert "clientPublish" in op.info["capabilities"] and op.info["supportedEncodings"] == ["json"]
    assert not [s for s in op.statuses if s.get("level") == 2], op.statuses
    replies = {m["request_id"]: m for _, m in moving["EDSP_MOTION_REPLY"]}
    assert not replies[9001]["accepted"] and replies[9001]["reason"], replies[9001]
    assert replies[9002]["accepted"], replies[9002]
    requests = [m for _, m in moving["EDSP_MOTION_REQUEST"] if m["request_id"] in (9001, 9002)]
    assert requests and all(m["client"] == "web:alice" for m in requests)
    status = [m for _, m in moving["EDSP_MOTION_STATUS"] if m["request_id"] == 9002 and m["on_target"]][-1]
    start, end = before["EDSP_RIG_TRUTH"][-1][1]["pose"], after["EDSP_RIG_TRUTH"][-1][1]["pose"]
    assert abs((end[2] - start[2]) - 0.005) < 5e-6, (start, end)
    assert max(abs(a - b) for a, b in zip(end[:3], status["pose_target"][:3])) < 5e-6, (end, status["pose_target"])


def test_a_viewer_cannot_send_a_request_and_nothing_moves(served):
    async def body():
        viewer = await Client.open(served["port"], served["viewer"])
        await viewer.subscribe(["EDSP_RIG_TRUTH", "EDSP_MOTION_REQUEST"])
        before = await _until(viewer, 5, lambda g: g["EDSP_RIG_TRUTH"])
        await viewer.ws.send(ADVERTISE_MOTION)
        await viewer.ws.send(_request_frame(1, {"request_id": 9101, "kind": 1, "relative": 1,
                                                "pose": [0, 0, 0.01, 0, 0, 0]}))
        after = await _until(viewer, 2.0, lambda g: False)
        await viewer.ws.close()
        return viewer, before, after

    viewer, before, after = run(body())
    assert viewer.info["capabilities"] == []
    errors = [s["message"] for s in viewer.statuses if s.get("level") == 2]
    assert len(errors) == 2 and all("viewer" in e for e in errors), errors
    assert not [m for _, m in after["EDSP_MOTION_REQUEST"] if m["request_id"] == 9101]
    p0, p1 = before["EDSP_RIG_TRUTH"][-1][1]["pose"], after["EDSP_RIG_TRUTH"][-1][1]["pose"]
    assert max(abs(a - b) for a, b in zip(p0, p1)) < 1e-6
