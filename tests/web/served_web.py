"""edsp-web beside a live sim group, for the tests that talk to it: tokens
for an operator (alice) and a viewer (bob), the server on a free port of
loopback, stopped with SIGINT and required to exit cleanly; another server
on the same group (a TLS one) with `server`, and a self-signed certificate
for it with `certificate`."""
import contextlib
import os
import re
import signal
import subprocess
import time

import live_group

SOURCE = os.environ["EDSP_SOURCE_DIR"]
BIN = os.environ["EDSP_BIN_DIR"]
WEB = os.path.join(BIN, "edsp-web")


@contextlib.contextmanager
def serve(work, extra=(), rig_args=(), stale_ms=live_group.STALL_TOLERANT_STALE_MS):
    """Yields {port, operator, viewer, group, pid, tokens, work} while the
    group (its rig with `rig_args`, its bridge and kinematics at `stale_ms`)
    and the server (with edsp-web's options `extra`) run."""
    tokens = str(work / "tokens.toml")

    def add(name, role):
        return subprocess.check_output([WEB, "token", "add", name, "--role", role, "--tokens", tokens],
                                       text=True, stderr=subprocess.DEVNULL).strip()

    operator, viewer = add("alice", "operator"), add("bob", "viewer")
    with live_group.sim_group(SOURCE, BIN, "web", rig_args=rig_args, stale_ms=stale_ms) as group:
        live_group.connect(group)
        with server(work / "web.err", group, tokens, extra) as (port, pid):
            yield {"port": port, "operator": operator, "viewer": viewer, "group": group, "pid": pid,
                   "tokens": tokens, "work": work}


@contextlib.contextmanager
def server(err_path, group, tokens, extra=()):
    """An edsp-web on `group`: yields (port, pid) once it serves."""
    with open(err_path, "w") as err:
        process = subprocess.Popen([WEB, "--group", group, "--port", "0", "--tokens", tokens, *extra], stderr=err)
    try:
        yield _port(process, err_path), process.pid
    finally:
        process.send_signal(signal.SIGINT)
        try:
            status = process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            raise
    assert status == 0, open(err_path).read()


def certificate(work, name="localhost"):
    """A self-signed certificate for `name` and 127.0.0.1, and its key: (cert, key) paths."""
    cert, key = str(work / f"{name}.crt"), str(work / f"{name}.key")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-keyout", key,
                    "-out", cert, "-subj", f"/CN={name}", "-addext", f"subjectAltName=DNS:{name},IP:127.0.0.1"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return cert, key


def _port(process, err_path):
    """The port edsp-web says it serves on, once it says so."""
    deadline = time.monotonic() + 30
    while True:
        match = re.search(r"on https?://127\.0\.0\.1:(\d+) ", open(err_path).read())
        if match:
            return int(match.group(1))
        if process.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError("edsp-web did not start: " + open(err_path).read())
        time.sleep(0.05)
