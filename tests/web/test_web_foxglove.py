"""edsp-web through Foxglove's own client library of the protocol
(@foxglove/ws-protocol, installed from npm by `deploy/edsp deps` into
EDSP_NPM_DIR): the library Foxglove and Lichtblick connect with, driven
by tests/web/foxglove_client/check_edsp_web.js beside a live sim group.
What such a tool needs of the server: its info and every channel's schema
as a JSON schema, messages that decode by their advertised encoding and fit
their schema, at the cap, an operator's request answered, a viewer's
refused."""
import json
import os
import subprocess

import pytest

import served_web

SOURCE = os.environ["EDSP_SOURCE_DIR"]
NPM_DIR = os.environ.get("EDSP_NPM_DIR", "")
SCRIPT = os.path.join(SOURCE, "tests", "web", "foxglove_client", "check_edsp_web.js")
# Not a skip: a suite that cannot run this test must say so (deploy/edsp deps installs it).
assert os.path.isdir(os.path.join(NPM_DIR, "node_modules", "@foxglove", "ws-protocol")), \
    f"@foxglove/ws-protocol is not installed in EDSP_NPM_DIR={NPM_DIR!r} (deploy/edsp deps installs it)"


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    with served_web.serve(tmp_path_factory.mktemp("web")) as server:
        yield server


def test_foxgloves_client_library_reads_every_channel_and_an_operator_is_answered(served):
    run = subprocess.run(["node", SCRIPT, f"ws://127.0.0.1:{served['port']}", served["operator"], served["viewer"]],
                         capture_output=True, text=True, timeout=120,
                         env={**os.environ, "NODE_PATH": os.path.join(NPM_DIR, "node_modules")})
    assert run.returncode == 0, run.stderr
    seen = json.loads(run.stdout)
    operator, viewer = seen["operator"], seen["viewer"]
    assert operator["name"] == "edsp-web" and "clientPublish" in operator["capabilities"], operator
    text = open(os.path.join(SOURCE, "docs", "interfaces.md"), encoding="utf-8").read()
    assert operator["channels"] == text.count("\n| `EDSP_"), operator  # every channel of the table
    seconds = operator["seconds"]
    for topic in ("EDSP_PLATFORM_STATE", "EDSP_LEG_STATE", "EDSP_MOTION_STATUS"):
        # at the 30 Hz cap, and not starved: a third of it at least (test_web_live.py says why)
        assert 10 * seconds <= operator["counts"][topic] <= 31 * seconds, (topic, operator["counts"])
    assert operator["reply"]["accepted"], operator["reply"]
    assert "clientPublish" not in viewer["capabilities"], viewer
    assert "viewer" in viewer["refusal"] or "operator" in viewer["refusal"], viewer
