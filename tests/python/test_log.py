"""edsp.read_log against an independent decoder: a log of the virtual rig
(edsp-sim rig, offline) read by edsp and by pure Python from the .lcm files
(lcm_pure.py) gives the same value in every field of every message; a
foreign channel, a truncated packet and a damaged tail are named and left
out while every message before them is read; bad arguments raise naming
them."""
import os
import struct
import subprocess
import warnings

import numpy as np
import pytest

import edsp
import lcm_pure

SOURCE = os.environ.get("EDSP_SOURCE_DIR", ".")
BIN = os.environ.get("EDSP_BIN_DIR", os.path.join(SOURCE, "build", "bin"))
TYPES = lcm_pure.parse_lcm_types(os.path.join(SOURCE, "lcmtypes"))


@pytest.fixture(scope="module")
def rig_log(tmp_path_factory):
    out = tmp_path_factory.mktemp("rig")
    subprocess.run([os.path.join(BIN, "edsp-sim"), "rig", "--config",
                    os.path.join(SOURCE, "config", "huang2021-rig-effects.toml"), "--out", str(out),
                    "--motions", "Lz,Rz", "--stops", "2", "--dwell-s", "0.1", "--tracker-noise-m", "5e-6"],
                   check=True, stdout=subprocess.DEVNULL)
    return str(out / "run.lcmlog")


def pure_tables(path):
    """channel -> (receive stamps, [decoded dicts]) by the pure-Python decoder
    (both of its readings, held to each other)."""
    tables = {}
    for channel, utime, data in lcm_pure.log_events(path):
        fields = TYPES[edsp.CHANNELS[channel]]
        stamps, rows = tables.setdefault(channel, ([], []))
        stamps.append(utime)
        rows.append(lcm_pure.decode(data, fields))
        assert lcm_pure.Decoder(fields)(data) == rows[-1], channel
    return tables


def test_every_field_of_every_message_matches_an_independent_decoder(rig_log):
    data = edsp.read_log(rig_log)
    expected = pure_tables(rig_log)
    assert set(data) == set(expected)
    assert {"EDSP_SETPOINT", "EDSP_LEG_COMMAND", "EDSP_LEG_STATE", "EDSP_TRACKER", "EDSP_CONFIG"} <= set(data)
    for channel, (stamps, rows) in expected.items():
        table = data[channel]
        assert len(table) == len(rows), channel
        assert np.array_equal(table["receive_utime"], stamps), channel
        fields = TYPES[edsp.CHANNELS[channel]]
        assert table.dtype.names == ("receive_utime",) + tuple(name for name, _, _ in fields), channel
        for name, lcm_type, dims in fields:
            column = table[name]
            assert column.shape == (len(rows),) + dims, (channel, name)
            want = [row[name] for row in rows]
            if lcm_type == "string":
                assert list(column) == want, (channel, name)
            else:  # exact: both decode the same bytes
                assert np.array_equal(column, np.array(want, dtype=column.dtype)), (channel, name)



def test_setpoints_say_by_their_phase_where_they_dwell(rig_log):
    """The phase names what a setpoint does (edsp.SetpointPhase, from the
    C++ table); the paper motions' labels agree with it."""
    assert [p.name for p in edsp.SetpointPhase] == ["HOLD", "MOVE", "DWELL", "CUEING"]
    assert [int(p) for p in edsp.SetpointPhase] == [0, 1, 2, 3]  # pose_setpoint_t.PHASE_*
    setpoints = edsp.read_log(rig_log, ["EDSP_SETPOINT"])["EDSP_SETPOINT"]
    dwelling = setpoints["phase"] == edsp.SetpointPhase.DWELL
    moving = setpoints["phase"] == edsp.SetpointPhase.MOVE
    assert dwelling.any() and moving.any()
    assert all("/dwell" in label for label in setpoints["trajectory"][dwelling])
    assert not any("/dwell" in label for label in setpoints["trajectory"][moving])
    assert not np.abs(setpoints["velocity"][dwelling]).any()

def test_a_channel_filter_and_an_edsp_channel_the_log_lacks(rig_log):
    data = edsp.read_log(rig_log, channels=["EDSP_TRACKER", "EDSP_MOTION_REPLY"])
    assert set(data) == {"EDSP_TRACKER", "EDSP_MOTION_REPLY"}
    assert len(data["EDSP_TRACKER"]) > 100
    reply = data["EDSP_MOTION_REPLY"]
    assert len(reply) == 0 and "reason" in reply.dtype.names and "accepted" in reply.dtype.names
    assert data["EDSP_TRACKER"]["point_m"].shape[1:] == (3,)


def test_foreign_truncated_and_damaged_input_is_named_and_the_rest_read(rig_log, tmp_path):
    events = list(lcm_pure.log_events(rig_log))
    tracker = [e for e in events if e[0] == "EDSP_TRACKER"]
    foreign = ("OTHER_SENSOR", 5, struct.pack(">q", 0x1234567890) + b"\x00" * 40)
    truncated = ("EDSP_TRACKER", 6, tracker[0][2][:20])
    mixed = [events[0], foreign, truncated] + events[1:]
    path = tmp_path / "mixed.lcmlog"
    lcm_pure.write_log(str(path), mixed)
    with open(path, "ab") as f:
        f.write(struct.pack(">I", 0xEDA1DA01) + b"\x01\x02")  # a torn last event
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        data = edsp.read_log(path)
    said = " ".join(str(w.message) for w in caught)
    assert "OTHER_SENSOR" in said, said
    assert "damaged at byte" in said, said
    assert "EDSP_TRACKER" in said, "the truncated packet is counted on its channel: " + said
    assert "OTHER_SENSOR" not in data
    assert len(data["EDSP_TRACKER"]) == len(tracker), "every whole tracker message is read"


def test_bad_arguments_are_named(rig_log, tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.lcmlog"):
        edsp.read_log(tmp_path / "nowhere.lcmlog")
    with pytest.raises(ValueError, match="NO_SUCH_CHANNEL"):
        edsp.read_log(rig_log, channels=["NO_SUCH_CHANNEL"])
    with pytest.raises(TypeError, match="channel names"):
        edsp.read_log(rig_log, channels=[3])
    not_a_log = tmp_path / "text.lcmlog"
    not_a_log.write_text("time_s,run\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert edsp.read_log(not_a_log) == {}
    assert any("damaged at byte 0" in str(w.message) for w in caught)
