"""edsp.Platform on a live sim group (started here by edsp-launch, inside
the private network namespace ctest gives this test): a script moves the
platform through a work frame about a pivot while recording the rig's
streams, and each move ends on target within 1 µm of where it was sent in
the rig's truth (recorded); refusals, a halt and
bad input raise the exceptions that name them; a group that is not
running raises Timeout instead of hanging."""
import math
import os
import time

import numpy as np
import pytest

import edsp
from live_group import connect, sim_group

SOURCE = os.environ.get("EDSP_SOURCE_DIR", ".")
BIN = os.environ.get("EDSP_BIN_DIR", os.path.join(SOURCE, "build", "bin"))
SESSION = 4711


@pytest.fixture(scope="module")
def group():
    # The rig's line in the shipped group already sets a noise-free tracker.
    with sim_group(SOURCE, BIN, "pytest", ["--session-id", str(SESSION), "--duration-s", "240"]) as path:
        yield path


def test_a_script_through_a_work_frame_lands_each_move_on_target(group, tmp_path):
    rig = connect(group)
    assert rig.session_id == SESSION
    assert rig.status()["state"] == "idle"
    rig.frame("fixture", [0.05, -0.02, 1.55, 0, 0, 0.3])
    rig.pivot([0, 0, 0.3])
    tolerance_m = 10e-6  # the status' measured pose: forward kinematics of the encoders
    truth_tolerance_m, hold_s, settle_s = 1e-6, 0.2, 0.02
    settled = []  # (target, from, to): the platform holds the target in between (receive clock, µs)
    began = time.monotonic()
    with rig.recorder(["EDSP_RIG_TRUTH", "EDSP_TRACKER", "EDSP_LEG_STATE", "EDSP_MOTION_STATUS"]) as rec:
        for pose, frame, relative in [([0, 0, 0, 0, 0, 0], "fixture", False),
                                      ([0, 0, 0, 0.02, 0, 0], "fixture", True),
                                      ([0, 0.02, -0.01, 0, 0, 0], "fixture", True),
                                      ([-0.01, 0.01, 0, 0, 0, 0.02], "home", False),
                                      ([0.0, 0.0, 1.511, 0, 0, 0], None, False)]:
            rig.move(pose, frame=frame, relative=relative, timeout_s=60)
            s = rig.status()
            assert s["on_target"], s
            assert s["measured_valid"]
            target, measured = np.array(s["pose_target"]), np.array(s["pose_measured"])
            assert np.abs(measured[:3] - target[:3]).max() < tolerance_m, (pose, measured - target)
            start = time.time_ns() // 1000 + int(settle_s * 1e6)
            time.sleep(hold_s)
            settled.append((target, start, time.time_ns() // 1000))
    elapsed_s = time.monotonic() - began
    assert rig.wait(timeout=10) == edsp.WaitOutcome.ON_TARGET  # nothing runs: it holds the last target
    rig.jog("z", 0.002, timeout_s=30)  # either spelling of the limit, as move's
    assert abs(rig.status()["pose_commanded"][2] - 1.513) < 1e-12
    rig.jog("z", -0.002, timeout=30)
    final = rig.status()
    assert np.abs(np.array(final["pose_commanded"]) - [0, 0, 1.511, 0, 0, 0]).max() < 1e-12
    assert final["frame"] == "base" and list(final["pivot"]) == [0, 0, 0.3]

    # The recording, at full rate: the rig's 1 kHz streams over the whole script.
    data = rec.data
    for channel in ("EDSP_RIG_TRUTH", "EDSP_TRACKER", "EDSP_LEG_STATE"):
        assert len(data[channel]) > 0.5 * 1000 * elapsed_s, (channel, len(data[channel]), elapsed_s)
    assert len(data["EDSP_MOTION_STATUS"]) > 0.5 * 50 * elapsed_s
    # Each on-target pose against the rig's truth (tracker noise 0), not the
    # controller's own measurement: where the platform really stood. Chosen
    # by the rig's own stamps (the recorder may read a batch late).
    truth = data["EDSP_RIG_TRUTH"]
    for target, start, end in settled:
        held = truth[(truth["utime"] >= start) & (truth["utime"] <= end)]
        # Enough of the rig's cycles to judge where it stood, and the
        # recorder kept most of what the rig published in the window (by the
        # rig's seq: a host that stalls the rig itself shortens the window's
        # cycles, not the recorder's share of them).
        assert len(held) >= 10, len(held)
        assert len(held) > 0.5 * (held["seq"][-1] - held["seq"][0] + 1), (len(held), held["seq"][[0, -1]])
        error = np.abs(held["pose"] - target)
        assert error[:, :3].max() < truth_tolerance_m, (target, error[:, :3].max())
        assert error[:, 3:].max() < truth_tolerance_m, (target, error[:, 3:].max())
    legs = data["EDSP_LEG_STATE"]
    assert legs["encoder_length_m"].shape[1:] == (6,) and np.all(legs["drive_status"] == 1)
    # Saved as an LCM log, it reads back the same (edsp-gap, edsp-log and lcm-logplayer take it).
    back = edsp.read_log(rec.save(tmp_path / "script.lcmlog"))
    for channel, table in data.items():
        assert np.array_equal(back[channel]["utime"], table["utime"]), channel
    assert np.array_equal(back["EDSP_RIG_TRUTH"]["pose"], truth["pose"])


def test_record_for_a_time_and_its_bad_arguments(group):
    rig = connect(group)
    began = time.monotonic()
    data = rig.record("EDSP_TRACKER", seconds=0.3)
    assert time.monotonic() - began < 5
    assert set(data) == {"EDSP_TRACKER"} and len(data["EDSP_TRACKER"]) > 50
    flag = []
    data = rig.record(["EDSP_LEG_STATE"], until=lambda: flag.append(1) or len(flag) > 20)
    assert len(data["EDSP_LEG_STATE"]) > 0
    with pytest.raises(ValueError, match="give seconds, until"):
        rig.record("EDSP_TRACKER")
    with pytest.raises(ValueError, match="seconds = -1"):
        rig.record("EDSP_TRACKER", seconds=-1)
    with pytest.raises(TypeError, match="channel names"):
        rig.record([1], seconds=0.1)


def test_refusals_halts_and_bad_input_raise_what_names_them(group):
    rig = connect(group)
    with pytest.raises(edsp.RefusedError, match="outside the workspace") as outside:
        rig.check([0, 0, 3.0, 0, 0, 0])
    assert outside.value.code == "out_of_limits"
    with pytest.raises(edsp.Refused, match='unknown frame "nowhere"') as unknown:
        rig.move([0] * 6, frame="nowhere")
    assert unknown.value.code == "invalid" and isinstance(unknown.value, edsp.EdspError)
    with pytest.raises(edsp.Refused, match="speed_max_m_s"):
        rig.move([0.01, 0, 1.5, 0, 0, 0], speed_m_s=1000)
    with pytest.raises(ValueError, match=r"pose\[0\] = nan"):
        rig.move([math.nan, 0, 1.5, 0, 0, 0])
    with pytest.raises(ValueError, match="six numbers"):
        rig.move([0, 0, 1.5])
    with pytest.raises(TypeError, match="got a str"):
        rig.move("123456")
    with pytest.raises(ValueError, match="speed_m_s"):
        rig.move([0.01, 0, 1.5, 0, 0, 0], speed_m_s=-1)
    reply = rig.move([0.2, 0, 1.5, 0, 0, 0], wait=False)
    assert reply["accepted"] and reply["code"] == "done" and reply["duration_s"] > 1.0
    time.sleep(0.5)
    rig.halt()
    with pytest.raises(edsp.HaltedError) as halted:
        rig.wait(timeout=30)
    assert halted.value.code == "halted"
    with pytest.raises(TypeError, match="timeout or timeout_s"):
        rig.wait(timeout=1, timeout_s=1)
    assert rig.status()["last_end"] == "halted"


def test_the_operators_requests_are_confirmed_or_refused_by_the_node(group):
    rig = connect(group)
    assert "none" in rig.pr_mode(edsp.PrMode.NONE)
    assert "signed" in rig.pr_mode("signed")
    assert [m.name for m in edsp.PrMode.__members__.values()] == ["NONE", "UNSIGNED", "SIGNED", "ASIN"]
    with pytest.raises(ValueError, match="sideways"):
        rig.pr_mode("sideways")
    assert "was not latched" in rig.arm()
    with pytest.raises(FileNotFoundError):
        rig.calibration("/no/such/model.json")
    bad = os.path.join(os.path.dirname(group), "not_a_model.json")
    with open(bad, "w", encoding="utf-8") as f:
        f.write("{}")
    with pytest.raises(edsp.Refused) as refused:
        rig.calibration(bad)
    assert refused.value.code == "invalid"
    # Another group's request is refused by its code, not matched by its words.
    other = edsp.Platform(group, session_id=rig.session_id + 1, answer_timeout_s=5)
    with pytest.raises(edsp.RefusedError) as foreign:
        other.arm()
    assert foreign.value.code == "other_session"
    with pytest.raises(edsp.RefusedError) as foreign_move:
        other.check([0, 0, 1.5, 0, 0, 0])
    assert foreign_move.value.code == "other_session"


def test_a_group_that_is_not_running_raises_timeout_without_hanging():
    began = time.monotonic()
    with pytest.raises(TimeoutError, match="no leg commands or setpoints") as none:  # Python's own, too
        edsp.Platform(lcm_url="udpm://239.255.76.99:7699?ttl=0", answer_timeout_s=0.5)
    assert isinstance(none.value, edsp.TimeoutError) and none.value.code == "no_session"
    assert time.monotonic() - began < 10
