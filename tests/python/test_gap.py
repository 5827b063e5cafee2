"""edsp.gap against edsp-gap itself: on a measurement of the virtual rig
with effects (edsp-sim rig, offline), diagnose returns what
`edsp-gap diagnose --json` prints and the model `--save-model` writes;
the same measurement given as numpy arrays reaches the same verdicts;
evaluate agrees with `edsp-gap evaluate`. The model found, in
edsp.Kinematics, commands what the kinematics node commanded with it (the
node's leg commands in a run with the calibration applied). Data recorded
with the calibration reads against the nominal model or against it. Bad
data raises naming the column."""
import json
import os
import subprocess

import numpy as np
import pytest

import edsp

SOURCE = os.environ.get("EDSP_SOURCE_DIR", ".")
BIN = os.environ.get("EDSP_BIN_DIR", os.path.join(SOURCE, "build", "bin"))
CONFIG = os.path.join(SOURCE, "config", "huang2021-rig-effects.toml")


def rig_run(out, *extra):
    # At the calibration group's speeds (deploy/groups/calibrate.toml): the
    # motions in half the samples, so each diagnosis here takes seconds.
    subprocess.run([os.path.join(BIN, "edsp-sim"), "rig", "--config", CONFIG, "--out", str(out), "--stops", "3",
                    "--dwell-s", "0.2", "--tracker-noise-m", "5e-6", "--max-speed-m-s", "0.25",
                    "--max-speed-rad-s", "0.5", *extra], check=True, stdout=subprocess.DEVNULL)
    return str(out / "run.lcmlog"), str(out / "measurement.csv")


@pytest.fixture(scope="module")
def fit(tmp_path_factory):
    return rig_run(tmp_path_factory.mktemp("fit"), "--motions", "Lz,Lx,Rz,Ry,M1,M2")


@pytest.fixture(scope="module")
def held_out(tmp_path_factory):
    return rig_run(tmp_path_factory.mktemp("held"), "--motions", "Ly,Rx,M3", "--seed", "2")


def gap_cli(*args):
    return subprocess.run([os.path.join(BIN, "edsp-gap"), *args], check=True, capture_output=True,
                          text=True).stdout


def same(ours, theirs, path=""):
    """The same JSON, numbers to 1e-9 relative: the interpreter's process
    (numpy loaded) may round the fits' last bits differently."""
    if isinstance(theirs, dict):
        assert set(ours) == set(theirs), path
        for key in theirs:
            same(ours[key], theirs[key], f"{path}/{key}")
    elif isinstance(theirs, list):
        assert len(ours) == len(theirs), path
        for i, (a, b) in enumerate(zip(ours, theirs)):
            same(a, b, f"{path}[{i}]")
    elif isinstance(theirs, float):
        assert ours == pytest.approx(theirs, rel=1e-9, abs=1e-300), path
    else:
        assert ours == theirs, path


@pytest.fixture(scope="module")
def columns(fit):
    """The fit's CSV export as numpy's structured array (read once: numpy parses it slowly)."""
    return np.genfromtxt(fit[1], delimiter=",", names=True, dtype=None, encoding="utf-8", comments="#")


@pytest.fixture(scope="module")
def report(fit):
    return edsp.gap.diagnose(CONFIG, fit[0])


def test_diagnose_returns_what_edsp_gap_prints_and_saves(fit, report, tmp_path):
    model_path = tmp_path / "cli-model.json"
    printed = json.loads(gap_cli("diagnose", "--config", CONFIG, "--data", fit[0], "--json",
                                 "--save-model", str(model_path)))
    took = lambda r: {k: v for k, v in r.items() if k != "seconds"}  # noqa: E731  (how long it ran)
    same(took(report), took(printed))
    same(report.model, json.loads(model_path.read_text()))
    assert any(e["verdict"] == "identified" for e in report["effects"]), "the rig's effects are found"
    saved = edsp.gap.save_model(report, tmp_path / "model.json")
    assert json.loads(open(saved).read()) == report.model


def test_numpy_columns_reach_the_verdicts_of_the_csv_file(fit, columns, report):
    from_arrays = edsp.gap.diagnose(CONFIG, columns)
    from_file = edsp.gap.diagnose(CONFIG, fit[1])
    verdicts = lambda r: [(e["name"], e["verdict"]) for e in r["effects"]]  # noqa: E731
    assert verdicts(from_arrays) == verdicts(from_file)
    assert from_arrays["gap"]["rms_m"] == pytest.approx(from_file["gap"]["rms_m"], rel=1e-9)
    assert verdicts(from_file) == verdicts(report), "the log and its CSV export are one measurement"


def test_evaluate_agrees_with_edsp_gap(report, held_out, tmp_path):
    model = edsp.gap.save_model(report, tmp_path / "model.json")
    printed = json.loads(gap_cli("evaluate", "--config", CONFIG, "--model", model, "--data", held_out[0], "--json"))
    same(edsp.gap.evaluate(CONFIG, model, held_out[0]), printed)
    from_report = edsp.gap.evaluate(CONFIG, report, held_out[0])
    same(from_report["after"], printed["after"])
    assert printed["shrink"] > 0.5, "the model cuts the held-out gap"


def test_kinematics_with_the_calibration_commands_what_the_node_did(report, tmp_path):
    model = edsp.gap.save_model(report, tmp_path / "model.json")
    log, _ = rig_run(tmp_path / "applied", "--motions", "Lz,Rz", "--calibration", model)
    data = edsp.read_log(log, channels=["EDSP_SETPOINT", "EDSP_LEG_COMMAND"])
    setpoints, commands = data["EDSP_SETPOINT"], data["EDSP_LEG_COMMAND"]
    # Each command answers one setpoint (its utime); both streams are the node's whole run.
    index = {int(u): i for i, u in enumerate(setpoints["utime"])}
    rows = np.array([index[int(u)] for u in commands["setpoint_utime"]])
    poses, times = setpoints["pose"][rows], setpoints["utime"][rows] * 1e-6
    kin = edsp.Kinematics(CONFIG, calibration=model)
    assert "applies" in kin.calibration
    nominal = edsp.Kinematics(CONFIG).ik(poses)
    calibrated = kin.ik(poses, times_s=times)
    node = commands["command_length_m"]
    correction = np.abs(node - nominal).max()
    assert correction > 2e-5, "the calibration changes the commands by tens of µm"
    # The node takes the setpoint's rates, Python differences the poses:
    # the same correction to within a small part of it.
    assert np.abs(calibrated - node).max() < 0.05 * correction


def test_bad_data_and_options_are_named(fit, columns):
    no_run = {name: columns[name] for name in columns.dtype.names if name != "run"}
    with pytest.raises(ValueError, match="run"):
        edsp.gap.diagnose(CONFIG, no_run)
    bad = {name: columns[name].copy() for name in columns.dtype.names}
    bad["point_x_m"][7] = np.nan
    with pytest.raises(ValueError, match="point_x_m"):
        edsp.gap.diagnose(CONFIG, bad)
    with pytest.raises(TypeError, match="unknown option max_rate"):
        edsp.gap.diagnose(CONFIG, fit[0], max_rate=5)
    with pytest.raises(ValueError, match="max_rate_hz"):
        edsp.gap.diagnose(CONFIG, fit[0], max_rate_hz=-1)
    with pytest.raises(FileNotFoundError, match="nowhere.csv"):
        edsp.gap.diagnose(CONFIG, "nowhere.csv")
    with pytest.raises(TypeError, match="structured array"):
        edsp.gap.diagnose(CONFIG, np.zeros((10, 3)))
    with pytest.raises(FileNotFoundError, match="config: nowhere.toml"):
        edsp.gap.diagnose("nowhere.toml", fit[0])


def test_a_yaw_through_pi_is_one_motion_to_the_calibration(report, tmp_path):
    # The same trajectory with its yaw written unwrapped (π − 0.04 → π + 0.04)
    # and wrapped (… → −π + 0.04): one motion, so one correction. A rate
    # taken across the wrap without unwrapping would be 2π per sample.
    # The found model, with a servo lag of 2 ms on every leg: a correction ∝ the legs' rates.
    model = dict(report.model)
    model["effects"] = [e for e in model["effects"] if e["name"] != "servo_lag"] + [
        {"name": "servo_lag", "theta": [2e-3] * 6 + [0.0] * 7, "verdict": "identified", "apply": True}]
    kin = edsp.Kinematics(CONFIG, calibration=edsp.gap.save_model(model, tmp_path / "model.json"))
    assert "servo_lag" in kin.calibration.split("not applied")[0]
    times = np.arange(200) * 1e-3
    yaw = np.pi - 0.04 + 0.4 * times
    unwrapped = np.tile(kin.home, (len(times), 1))
    unwrapped[:, 5] = yaw
    wrapped = unwrapped.copy()
    wrapped[:, 5] = np.arctan2(np.sin(yaw), np.cos(yaw))
    assert wrapped[:, 5].min() < 0 < wrapped[:, 5].max()
    along = kin.compensate(unwrapped, times_s=times)
    assert np.abs(along - kin.compensate(unwrapped)).max() > 1e-7, "the motion's rates change the correction"
    assert np.abs(kin.compensate(wrapped, times_s=times) - along).max() < 1e-9


def test_data_recorded_with_the_calibration_reads_against_nominal_or_the_calibration(report, tmp_path):
    model = edsp.gap.save_model(report, tmp_path / "model.json")
    log, _ = rig_run(tmp_path / "calibrated", "--motions", "Ly,Rx,M3", "--seed", "2", "--calibration", model)
    nominal = edsp.gap.diagnose(CONFIG, log)
    left = edsp.gap.diagnose(CONFIG, log, against="calibration")
    assert nominal["recorded_correction"]["against"] == "nominal"
    assert left["recorded_correction"]["against"] == "calibration"
    assert nominal["recorded_correction"]["rms_m"] > 10e-6
    assert left["gap"]["rms_m"] < 0.5 * nominal["gap"]["rms_m"]
    assert nominal.model is not None and left.model is None
    with pytest.raises(ValueError, match="against='nominal'"):
        edsp.gap.save_model(left, tmp_path / "increments.json")
    with pytest.raises(ValueError, match="model: this diagnosis ran against the calibration"):
        edsp.gap.evaluate(CONFIG, left, log)
    with pytest.raises(ValueError, match="against"):
        edsp.gap.diagnose(CONFIG, log, against="factory")
    took = lambda r: {k: v for k, v in r.items() if k != "seconds"}  # noqa: E731  (how long it ran)
    same(took(nominal), took(json.loads(gap_cli("diagnose", "--config", CONFIG, "--data", log, "--json"))))
