#!/usr/bin/python3
"""edsp-web under load, on the sim-web group (deploy/groups/sim-web.toml:
the sim group with edsp-web, as an operator runs it), each figure beside
its reference measured in the same run (docs/figures.md, "Browser panel"):

  clients   N foxglove.websocket.v1 clients (N = 1, 4, 16 by default) each
            subscribed to what the panel watches: a frame's age on
            arrival (the client's clock − the frame's receive time, when
            edsp-web took the message from the Bus; one host, one clock)
            on the 1 kHz channels, p50/p99; each client's frames per second
            per capped channel; edsp-web's CPU (/proc), and what each
            client adds to it beyond the run without clients;
  stack     the same group's 1 kHz path in each of those runs and in one
            without any client: the bridge's setpoint → command p99 and
            the missed cycles (the planner's deadline misses and the
            commands that never reached the bridge, as edsp-bench-stack
            counts them): what watching costs the rig. The group is
            partitioned as on a rig's controller (the hot path under
            SCHED_FIFO on CPU 1; root needed), or as shipped with
            --no-realtime;
  page      the panel in headless Chromium (the browser tests' flags), alone:
            its animation frames and the 3-D view's renders per second, from
            the browser's own counters (requestAnimationFrame's times,
            three.js's render count). Composited on the CPU
            (--disable-gpu-compositing): headless Chromium's default, a
            software GPU (SwiftShader), holds the panel at a quarter of that.

    deploy/edsp bench web [--json]     (in a private network namespace, as it must run)
Medians of the run; no target is asserted here.
"""
import argparse
import asyncio
import json
import os
import re
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np
import websockets

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import live_group  # noqa: E402

import edsp  # noqa: E402

SUBPROTOCOL = "foxglove.websocket.v1"
# What the panel subscribes to (web/panel/panel.js, WATCHED).
WATCHED = ["EDSP_CONFIG", "EDSP_PLATFORM_STATE", "EDSP_LEG_STATE", "EDSP_LEG_COMMAND", "EDSP_TRACKER",
           "EDSP_MOTION_STATUS", "EDSP_STATUS", "EDSP_FAULT", "EDSP_MOTION_REPLY", "EDSP_REPLY"]
FAST = ["EDSP_LEG_STATE", "EDSP_LEG_COMMAND"]  # 1 kHz on the Bus: a frame's age is edsp-web's delay, not the rate's
CAPPED = ["EDSP_PLATFORM_STATE", "EDSP_LEG_STATE", "EDSP_LEG_COMMAND", "EDSP_TRACKER", "EDSP_MOTION_STATUS"]
PORT = 8765


# As a rig's controller runs the hot path (deploy/groups/calibrate.toml,
# edsp-bench-stack): planner → kinematics → bridge on CPU 1 under SCHED_FIFO,
# each above the one feeding it; the rig and the logger on CPU 0; edsp-web
# an ordinary process wherever the scheduler puts it.
REALTIME = {"edsp-rig": (60, 0), "edsp-actuator-bridge": (85, 1), "edsp-kinematics": (80, 1), "edsp-logger": (0, 0),
            "edsp-planner": (70, 1)}


def partitioned(text):
    for command, (priority, cpu) in REALTIME.items():
        placement = (f"realtime_priority = {priority}\n" if priority else "") + f"cpus = [{cpu}]\n"
        text, n = re.subn(rf'(command = "{command}"\n)', rf"\1{placement}", text)
        if n != 1:
            raise RuntimeError(f"deploy/groups/sim-web.toml has no single member running {command}")
    return text


def group_file(work, realtime):
    """sim-web with a shared-memory prefix of its own, an absolute config,
    the bridge's latency report and edsp-web's port fixed; `realtime`:
    partitioned as a rig's controller runs it."""
    with open(os.path.join(ROOT, "deploy", "groups", "sim-web.toml"), encoding="utf-8") as f:
        text = f.read()
    text = text.replace('shm_prefix = "edsp.sim-web"', f'shm_prefix = "edsp.bench-web.{os.getpid()}"')
    text = text.replace('config = "config/', f'config = "{ROOT}/config/')
    text, bridge = re.subn(r'(command = "edsp-actuator-bridge"\n)',
                           rf'\1args = ["--latency-report", "{work}/latency.json"]\n', text)
    text, web = re.subn(r'args = \["--public-view"\]', f'args = ["--public-view", "--port", "{PORT}"]', text)
    if bridge != 1 or web != 1:
        raise RuntimeError("deploy/groups/sim-web.toml no longer has the members this benchmark edits")
    if realtime:
        text = partitioned(text)
    path = os.path.join(work, "group.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def process_cpu_s(pid):
    """User + system CPU seconds of a process so far."""
    with open(f"/proc/{pid}/stat", encoding="ascii") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def member_pid(program, group):
    out = subprocess.run(["pgrep", "-f", f"{program} .*{group}"], capture_output=True, text=True).stdout.split()
    if not out:
        raise RuntimeError(f"no {program} of {group} runs (its launch.err says why)")
    return int(out[0])


async def watch(seconds, topics):
    """One client: {topic: [age ms]} and {topic: frames}, for `seconds`."""
    async with websockets.connect(f"ws://127.0.0.1:{PORT}/", subprotocols=[SUBPROTOCOL], max_size=1 << 24) as ws:
        channels = {}
        while not channels:  # serverInfo, then advertise
            message = json.loads(await ws.recv())
            if message.get("op") == "advertise":
                channels = {c["topic"]: c["id"] for c in message["channels"]}
        subscriptions = [{"id": k + 1, "channelId": channels[t]} for k, t in enumerate(topics)]
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))
        ages = {t: [] for t in topics}
        frames = {t: 0 for t in topics}
        end = time.monotonic() + seconds
        while (left := end - time.monotonic()) > 0:
            try:
                frame = await asyncio.wait_for(ws.recv(), timeout=left)
            except asyncio.TimeoutError:
                break
            if isinstance(frame, bytes) and frame[0] == 0x01:
                arrived_ns = time.time_ns()
                sid, received_ns = struct.unpack_from("<IQ", frame, 1)
                topic = topics[sid - 1]
                frames[topic] += 1
                ages[topic].append((arrived_ns - received_ns) / 1e6)
        return ages, frames


async def watch_all(clients, seconds):
    return await asyncio.gather(*(watch(seconds, WATCHED) for _ in range(clients)))


def stack_figures(work):
    """The bridge's latency report and the planner's deadline misses (its last EDSP_STATUS)."""
    with open(os.path.join(work, "latency.json"), encoding="utf-8") as f:
        report = json.load(f)
    logs = [os.path.join(work, n) for n in os.listdir(work) if n.endswith(".lcmlog")]
    status = edsp.read_log(logs[0], ["EDSP_STATUS"])["EDSP_STATUS"] if logs else None
    planner_misses = 0
    if status is not None and len(status):
        nodes = status["node"].astype(str)
        rows = status[nodes == "planner"]
        planner_misses = int(rows["deadline_misses"][-1]) if len(rows) else 0
    return {"p50_us": report["p50_us"], "p99_us": report["p99_us"], "max_us": report["max_us"],
            "missed_cycles": planner_misses + int(report["command_seq_gaps"])}


def page_figures(seconds, work):
    """The panel in headless Chromium: animation frames and 3-D renders per second."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    for arg in ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,1000",
                "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-compositing",
                "--no-first-run", f"--user-data-dir={work}/chromium"]:
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    try:
        driver.get(f"http://127.0.0.1:{PORT}/")
        deadline = time.monotonic() + 60
        while not driver.execute_script("return typeof view3d !== 'undefined' && view3d.rendered()"):
            if time.monotonic() > deadline:
                raise RuntimeError("the panel never drew its 3-D view")
            time.sleep(0.1)
        counted = driver.execute_async_script("""
            const [seconds, done] = arguments;
            const times = [], renders0 = view3d.renders(), t0 = performance.now();
            function tick(now) {
              times.push(now);
              if (now - t0 < seconds * 1000) requestAnimationFrame(tick);
              else done({times, renders: view3d.renders() - renders0, elapsed_ms: now - t0});
            }
            requestAnimationFrame(tick);""", seconds)
    finally:
        driver.quit()
    intervals = np.diff(counted["times"])
    elapsed_s = counted["elapsed_ms"] / 1e3
    return {"seconds": elapsed_s, "animation_frames_per_s": len(intervals) / elapsed_s,
            "frame_interval_p50_ms": float(np.percentile(intervals, 50)),
            "frame_interval_p99_ms": float(np.percentile(intervals, 99)),
            "view_renders_per_s": counted["renders"] / elapsed_s}


def run_group(bin_dir, seconds, realtime, clients=0, page=False):
    """One run of the group for `seconds` of watching (0 clients: none)."""
    work = tempfile.mkdtemp(prefix="edsp_bench_web_")
    group = group_file(work, realtime)
    result = {"clients": clients}
    with live_group.launched(group, bin_dir, work):
        live_group.connect(group)  # up, measuring, its bridge following
        pid = member_pid("edsp-web", group)
        # what the launcher got: SCHED_FIFO needs root outside a user namespace
        result["realtime_applied"] = os.sched_getscheduler(member_pid("edsp-actuator-bridge", group)) == os.SCHED_FIFO
        time.sleep(1.0)  # past the start-up's burst
        cpu0, began = process_cpu_s(pid), time.monotonic()
        if clients:
            watched = asyncio.run(watch_all(clients, seconds))
            elapsed = time.monotonic() - began
            fast = [a for ages, _ in watched for t in FAST for a in ages[t]]
            rates = [frames[t] / elapsed for _, frames in watched for t in CAPPED]
            result.update({"frames": sum(sum(f.values()) for _, f in watched),
                           "age_p50_ms": float(np.percentile(fast, 50)), "age_p99_ms": float(np.percentile(fast, 99)),
                           "age_max_ms": float(np.max(fast)), "capped_rate_hz_median": statistics.median(rates),
                           "capped_rate_hz_min": min(rates)})
        elif page:
            result["page"] = page_figures(seconds, work)
            elapsed = time.monotonic() - began
        else:
            time.sleep(seconds)
            elapsed = time.monotonic() - began
        result["web_cpu_share"] = (process_cpu_s(pid) - cpu0) / elapsed  # of one core
    result["stack"] = stack_figures(work)
    shutil.rmtree(work, ignore_errors=True)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--seconds", type=float, default=20.0, help="of watching in each run")
    parser.add_argument("--clients", default="1,4,16", help="client counts, one run each")
    parser.add_argument("--no-page", action="store_true", help="leave the browser out")
    parser.add_argument("--no-realtime", action="store_true",
                        help="run the group as shipped (ordinary processes), not partitioned as on a rig")
    parser.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    args = parser.parse_args()
    counts = [int(c) for c in args.clients.split(",") if c]
    if args.seconds <= 0 or not counts or min(counts) < 1:
        parser.error("--seconds must be positive and --clients a list of positive counts")
    bin_dir = os.path.abspath(args.bin_dir)
    realtime = not args.no_realtime
    report = {"seconds": args.seconds, "realtime": realtime,
              "without_clients": run_group(bin_dir, args.seconds, realtime)}
    report["runs"] = [run_group(bin_dir, args.seconds, realtime, clients=n) for n in counts]
    if not args.no_page:
        report["page"] = run_group(bin_dir, args.seconds, realtime, page=True)["page"]
    base = report["without_clients"]["stack"]
    for r in report["runs"]:  # what each client adds to edsp-web's own reading of the Bus
        r["web_cpu_share_per_client"] = (r["web_cpu_share"] - report["without_clients"]["web_cpu_share"]) / r["clients"]
    most = max(report["runs"], key=lambda r: r["clients"])
    report["stack_p99_ratio"] = most["stack"]["p99_us"] / base["p99_us"]  # with the most clients / without
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"without clients: stack p99 {base['p99_us']:.0f} us, missed {base['missed_cycles']}, "
          f"edsp-web {100 * report['without_clients']['web_cpu_share']:.1f}% of a core")
    for r in report["runs"]:
        print(f"{r['clients']:>3} clients: age p50 {r['age_p50_ms']:.2f} ms, p99 {r['age_p99_ms']:.2f} ms, "
              f"{r['capped_rate_hz_median']:.1f} frames/s per capped channel (min {r['capped_rate_hz_min']:.1f}), "
              f"edsp-web {100 * r['web_cpu_share_per_client']:.2f}% of a core per client; "
              f"stack p99 {r['stack']['p99_us']:.0f} us, missed {r['stack']['missed_cycles']}")
    if "page" in report:
        p = report["page"]
        print(f"page: {p['animation_frames_per_s']:.1f} animation frames/s (interval p99 "
              f"{p['frame_interval_p99_ms']:.1f} ms), 3-D view {p['view_renders_per_s']:.1f} renders/s")


if __name__ == "__main__":
    main()
