#!/usr/bin/python3
"""The Python package's throughput, each figure beside its reference measured
in the same run (docs/python.md, "Benchmarks"):

  ik        edsp.Kinematics.ik on N poses (signed PR) against the C++ loop
            (edsp-bench-kinematics' BM_InverseKinematicsPrCompensation,
            signed): poses/s and their ratio;
  read_log  edsp.read_log of a log of M minutes of the rig's 1 kHz streams
            against decoding it message by message in pure Python, one
            precompiled struct per run of fixed fields (tests/python/lcm_pure.py
            Decoder): seconds and their ratio;
  move      (--live) Platform.move(wait=False) on a live sim group, against
            the same request sent by the C++ client under it: p50, p90 and
            what Python adds.

    PYTHONPATH=build/python /usr/bin/python3 bench/python/bench_python.py [--json]
    deploy/edsp bench python [--json]       (the live part in a private network namespace)
Medians of repeated runs; no target is asserted here.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import lcm_pure  # noqa: E402
import live_group  # noqa: E402

import edsp  # noqa: E402

CONFIG = os.path.join(ROOT, "config", "huang2021.toml")


def median_time(f, repeats):
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        f()
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def bench_ik(bin_dir, poses_n, repeats):
    kin = edsp.Kinematics(CONFIG)
    rng = np.random.default_rng(7)
    poses = np.tile(kin.home, (poses_n, 1))
    poses[:, :3] += rng.uniform(-0.1, 0.1, (poses_n, 3))
    poses[:, 3:] += rng.uniform(-0.1, 0.1, (poses_n, 3))
    python_s = median_time(lambda: kin.ik(poses), repeats)
    run = subprocess.run([os.path.join(bin_dir, "edsp-bench-kinematics"),
                          "--benchmark_filter=BM_InverseKinematicsPrCompensation", "--benchmark_format=json",
                          f"--benchmark_repetitions={max(repeats, 2)}", "--benchmark_report_aggregates_only=true"],  # a median needs two
                         check=True, capture_output=True, text=True)
    rows = json.loads(run.stdout)["benchmarks"]
    cpp = [b for b in rows if b.get("label") == "signed" and b.get("aggregate_name") == "median"]
    cpp_rate = cpp[0]["items_per_second"]
    python_rate = poses_n / python_s
    return {"poses": poses_n, "python_poses_per_s": python_rate, "cpp_poses_per_s": cpp_rate,
            "ratio": python_rate / cpp_rate}


def synthetic_log(bin_dir, minutes, out_dir):
    """The rig's streams (edsp-sim rig, offline) repeated, stamps moved on,
    until the 1 kHz channels span `minutes`."""
    subprocess.run([os.path.join(bin_dir, "edsp-sim"), "rig", "--config",
                    os.path.join(ROOT, "config", "huang2021-rig-effects.toml"), "--out", out_dir,
                    "--motions", "Lz", "--stops", "2", "--dwell-s", "0.2"], check=True, stdout=subprocess.DEVNULL)
    events = list(lcm_pure.log_events(os.path.join(out_dir, "run.lcmlog")))
    span = events[-1][1] - events[0][1] + 1000
    wanted = minutes * 60e6
    out, shift = [], 0
    while shift < wanted:
        out.extend((c, u + shift, d) for c, u, d in events if u + shift - events[0][1] < wanted)
        shift += span
    path = os.path.join(out_dir, "long.lcmlog")
    lcm_pure.write_log(path, out)
    return path, len(out)


def bench_read_log(bin_dir, minutes, repeats):
    with tempfile.TemporaryDirectory(prefix="edsp_bench_log_") as out:
        path, messages = synthetic_log(bin_dir, minutes, out)
        edsp_s = median_time(lambda: edsp.read_log(path), repeats)
        types = lcm_pure.parse_lcm_types(os.path.join(ROOT, "lcmtypes"))
        decoders = {channel: lcm_pure.Decoder(types[t]) for channel, t in edsp.CHANNELS.items()}

        def pure():
            for channel, _utime, data in lcm_pure.log_events(path):
                decoders[channel](data)
        pure_s = median_time(pure, 1)  # minutes of pure Python: once
        return {"minutes": minutes, "messages": messages, "bytes": os.path.getsize(path),
                "read_log_s": edsp_s, "pure_python_s": pure_s, "speedup": pure_s / edsp_s}


def bench_move(bin_dir, moves):
    """Platform.move(wait=False) against the client call under it, on a live
    sim group started here (run it in a private network namespace)."""
    with live_group.sim_group(ROOT, bin_dir, "bench_py") as group:
        rig = live_group.connect(group)
        home = list(rig.status()["pose_commanded"])
        python_ms, client_ms = [], []
        for k in range(moves):
            target = list(home)
            target[0] += 0.0005 if k % 2 == 0 else 0.0
            began = time.perf_counter()
            rig.move(target, wait=False)
            python_ms.append(1e3 * (time.perf_counter() - began))
            rig.wait(timeout_s=30)
            target[0] = home[0] + (0.0005 if k % 2 == 1 else 0.0)
            began = time.perf_counter()
            reply = rig._c.send(edsp._edsp.KIND_MOVE, target, False, "", [], 0.0, 0.0, 0.0, 0.0, "", "", "")
            client_ms.append(1e3 * (time.perf_counter() - began))
            assert reply and reply["accepted"], reply
            rig.wait(timeout_s=30)
        q = lambda v, p: float(np.percentile(v, p))  # noqa: E731
        return {"moves": moves, "python_p50_ms": q(python_ms, 50), "python_p90_ms": q(python_ms, 90),
                "client_p50_ms": q(client_ms, 50), "client_p90_ms": q(client_ms, 90),
                "python_adds_p50_ms": q(python_ms, 50) - q(client_ms, 50)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--poses", type=int, default=1_000_000)
    parser.add_argument("--log-minutes", type=float, default=10.0)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--live", action="store_true", help="also time Platform.move on a live sim group")
    parser.add_argument("--moves", type=int, default=40)
    parser.add_argument("--bin-dir", default=os.path.join(ROOT, "build", "bin"))
    args = parser.parse_args()
    if args.poses < 1 or args.log_minutes <= 0 or args.repeats < 1 or args.moves < 1:
        parser.error("--poses, --log-minutes, --repeats and --moves must be positive")
    report = {"ik": bench_ik(args.bin_dir, args.poses, args.repeats),
              "read_log": bench_read_log(args.bin_dir, args.log_minutes, min(args.repeats, 3))}
    if args.live:
        report["move"] = bench_move(args.bin_dir, args.moves)
    if args.json:
        print(json.dumps(report, indent=2))
        return
    ik, log = report["ik"], report["read_log"]
    print(f"ik: {ik['python_poses_per_s'] / 1e6:.2f} M poses/s from Python, {ik['cpp_poses_per_s'] / 1e6:.2f} M "
          f"in C++: {ik['ratio']:.2f}x")
    print(f"read_log: {log['messages']} messages ({log['minutes']} min) in {log['read_log_s']:.2f} s, pure Python "
          f"{log['pure_python_s']:.1f} s: {log['speedup']:.1f}x faster")
    if "move" in report:
        m = report["move"]
        print(f"move(wait=False): p50 {m['python_p50_ms']:.3f} ms, the client's request {m['client_p50_ms']:.3f} ms: "
              f"Python adds {m['python_adds_p50_ms']:.3f} ms")


if __name__ == "__main__":
    main()
