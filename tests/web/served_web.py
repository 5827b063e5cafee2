"""edsp-web beside a live sim group, for the tests that talk to it: tokens
for an operator (alice) and a viewer (bob), the server on a free port of
loopback, stopped with SIGINT and required to exit cleanly."""
import contextlib
import os
import re
import signal
import subprocess
import time

import live_group

SOURCE = os.environ["EDSP_SOURCE_DIR"]
BIN = os.environ["EDSP_BIN_DIR"]


@contextlib.contextmanager
def serve(work):
    """Yields {port, operator, viewer, group, pid} while the group and the server run."""
    tokens = str(work / "tokens.toml")
    web = os.path.join(BIN, "edsp-web")

    def add(name, role):
        return subprocess.check_output([web, "token", "add", name, "--role", role, "--tokens", tokens],
                                       text=True, stderr=subprocess.DEVNULL).strip()

    operator, viewer = add("alice", "operator"), add("bob", "viewer")
    with live_group.sim_group(SOURCE, BIN, "web") as group:
        live_group.connect(group)
        err_path = str(work / "web.err")
        with open(err_path, "w") as err:
            server = subprocess.Popen([web, "--group", group, "--port", "0", "--tokens", tokens], stderr=err)
        try:
            port = _port(server, err_path)
            yield {"port": port, "operator": operator, "viewer": viewer, "group": group, "pid": server.pid}
        finally:
            server.send_signal(signal.SIGINT)
            try:
                status = server.wait(timeout=15)
            except subprocess.TimeoutExpired:
                server.kill()
                raise
        assert status == 0, open(err_path).read()


def _port(server, err_path):
    """The port edsp-web says it serves on, once it says so."""
    deadline = time.monotonic() + 30
    while True:
        match = re.search(r"on http://127\.0\.0\.1:(\d+) ", open(err_path).read())
        if match:
            return int(match.group(1))
        if server.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError("edsp-web did not start: " + open(err_path).read())
        time.sleep(0.05)
