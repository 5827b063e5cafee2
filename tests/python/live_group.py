"""A live sim group for a test or a benchmark: the shipped group file
(deploy/groups/sim.toml) with a shared-memory prefix of its own and an
absolute config path, started by edsp-launch and stopped in order; and the
group's Platform once it measures its pose and its bridge follows. Run it
inside a private network namespace (ctest and `deploy/edsp bench` make one)."""
import contextlib
import ctypes
import os
import signal
import subprocess
import tempfile
import time

import edsp

PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
# The bridge's and the kinematics' stale limit for tests of behaviour, not
# of holding (tests/deploy/sim_group_harness.h's kStallTolerantStaleMs): a
# CPU quota or a busy host takes the whole group away for 50 ms and more,
# and the shipped 50 ms then latches a hold, correct but not what they test.
STALL_TOLERANT_STALE_MS = 250


def _die_with_parent():
    """In the launcher's child: SIGINT when the test process dies, however it
    dies, so the launcher stops the group instead of running on orphaned."""
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGINT)


@contextlib.contextmanager
def sim_group(source, bin_dir, tag, launch_args=(), rig_args=(), stale_ms=STALL_TOLERANT_STALE_MS):
    """Yields the group file's path while the group runs; `rig_args` after the rig's own;
    the bridge and kinematics at `stale_ms` (None: as shipped, for a test of the hold)."""
    work = tempfile.mkdtemp(prefix=f"edsp_{tag}_")
    bin_dir = os.path.abspath(bin_dir)  # the group runs in `work`
    with open(os.path.join(source, "deploy", "groups", "sim.toml"), encoding="utf-8") as f:
        text = f.read()
    text = text.replace('shm_prefix = "edsp.sim"', f'shm_prefix = "edsp.{tag}.{os.getpid()}"')
    text = text.replace('config = "config/', f'config = "{os.path.abspath(source)}/config/')
    stale = f'"--stale-ms", "{stale_ms}"'
    for member, args in (('command = "edsp-actuator-bridge"\n', f'args = [{stale}]\n'),
                         ('args = ["--pr-mode", "signed"', f', {stale}')):
        if text.count(member) != 1:
            raise RuntimeError(f"deploy/groups/sim.toml no longer has the line this edits: {member!r}")
        if stale_ms is not None:
            text = text.replace(member, member + args)
    if rig_args:
        rig = 'args = ["--tracker-noise-m", "0"'
        if text.count(rig) != 1:
            raise RuntimeError("deploy/groups/sim.toml's rig no longer starts with the args this edits")
        text = text.replace(rig, rig + "".join(f', "{a}"' for a in rig_args))
    path = os.path.join(work, "group.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    with launched(path, bin_dir, work, launch_args):
        yield path


@contextlib.contextmanager
def launched(path, bin_dir, work, launch_args=()):
    """edsp-launch running the group file `path` in `work` (its stderr in
    work/launch.err), stopped in order at the end; yields the process."""
    with open(os.path.join(work, "launch.err"), "w") as err:
        launch = subprocess.Popen([os.path.join(bin_dir, "edsp-launch"), path, "--bin-dir", bin_dir, *launch_args],
                                  cwd=work, stdout=subprocess.DEVNULL, stderr=err, preexec_fn=_die_with_parent)
    try:
        yield launch
    finally:
        launch.send_signal(signal.SIGINT)
        try:
            launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            launch.kill()


def connect(group, deadline_s=60.0):
    """The group's Platform, however long the machine takes to start it: its
    planner's setpoints (the session), a measured pose (the encoders through
    the kinematics), and a bridge that follows (past its start-up hold)."""
    deadline = time.monotonic() + deadline_s
    while True:
        try:
            rig = edsp.Platform(group, answer_timeout_s=5)
            break
        except edsp.Timeout:
            if time.monotonic() > deadline:
                raise
    while True:
        status = rig.status()
        if status["measured_valid"] and not status["reason"].startswith("the actuator bridge does"):
            return rig
        if time.monotonic() > deadline:
            raise edsp.Timeout(f"the group never measured its pose with its bridge following: {status['reason']}")
        time.sleep(0.05)
