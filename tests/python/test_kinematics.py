"""edsp.Kinematics on numpy arrays: forward kinematics undoes inverse
kinematics (two different algorithms: closed form against Newton), PR
compensation changes the lengths by the twist's amount, the workspace check
names the limit, and bad input raises naming the argument."""
import math
import os

import numpy as np
import pytest

import edsp

CONFIG = os.path.join(os.environ.get("EDSP_SOURCE_DIR", "."), "config", "huang2021.toml")


@pytest.fixture(scope="module")
def kin():
    return edsp.Kinematics(CONFIG)


def random_poses(kin, n, seed=20261127):
    rng = np.random.default_rng(seed)
    poses = np.tile(kin.home, (n, 1))
    poses[:, :3] += rng.uniform(-0.3, 0.3, (n, 3))
    poses[:, 3:] += rng.uniform(-0.3, 0.3, (n, 3))
    inside = np.array([c is None for c in kin.check(poses)])
    return poses[inside]


def test_forward_kinematics_undoes_inverse_kinematics(kin):
    poses = random_poses(kin, 500)
    assert len(poses) > 300
    for mode, with_pr in (("signed", True), ("none", False)):
        back = kin.fk(kin.ik(poses, pr_mode=mode), with_pr=with_pr)
        assert np.abs(back - poses).max() < 1e-9, mode


def test_compensation_moves_the_legs_by_the_passive_rotation(kin):
    poses = random_poses(kin, 50)
    nominal, signed = kin.ik(poses, pr_mode="none"), kin.ik(poses, pr_mode="signed")
    difference = np.abs(signed - nominal)
    assert difference.max() > 1e-5, "a yaw twists the screws: compensation changes the lengths"
    assert difference.max() < 0.01, "by a fraction of a lead, never by a leg's stroke"
    at_home = kin.ik(kin.home, pr_mode="signed") - kin.ik(kin.home, pr_mode="none")
    assert np.abs(at_home).max() < 1e-12


def test_a_single_pose_and_a_list_are_rows(kin):
    one = kin.ik(list(kin.home))
    assert one.shape == (1, 6)
    assert np.allclose(one, kin.ik(np.array([kin.home])))


def test_the_workspace_check_names_the_limit(kin):
    far = kin.home.copy()
    far[2] = 3.0
    result = kin.check(np.array([kin.home, far]))
    assert result[0] is None
    assert "exceeds leg_max_m" in result[1]


@pytest.mark.parametrize("bad, error, names", [
    (np.zeros((3, 5)), ValueError, "shape (N, 6)"),
    ([[0, 0, math.nan, 0, 0, 0]], ValueError, "row 0 column 2"),
    ([[0, 0, math.inf, 0, 0, 0]], ValueError, "finite"),
    (np.array([["a"] * 6]), TypeError, "numbers"),
    ("abc", TypeError, "numbers"),
    (None, TypeError, "poses"),
])
def test_bad_poses_raise_naming_the_argument(kin, bad, error, names):
    with pytest.raises(error, match="poses"):
        kin.ik(bad)
    with pytest.raises(error) as caught:
        kin.ik(bad)
    assert names in str(caught.value)


def test_unknown_pr_mode_and_missing_config_are_named(kin):
    with pytest.raises(ValueError, match="pr_mode sideways"):
        kin.ik(kin.home, pr_mode="sideways")
    with pytest.raises(Exception, match="no_such.toml"):
        edsp.Kinematics("no_such.toml")


def test_unreachable_lengths_raise_naming_the_row(kin):
    lengths = kin.ik(np.array([kin.home, kin.home]))
    lengths[1] = [0.5, 5.0, 0.5, 5.0, 0.5, 5.0]
    with pytest.raises(ValueError, match="lengths row 1"):
        kin.fk(lengths)


def test_compensate_is_what_ik_subtracts_and_follows_the_twist(kin):
    import tomllib
    with open(CONFIG, "rb") as f:
        drive = tomllib.load(f)["drive"]
    poses = random_poses(kin, 200)
    geometric = kin.ik(poses, pr_mode="none")
    assert np.abs(kin.compensate(poses, pr_mode="none")).max() == 0.0
    for mode in ("signed", "unsigned", "asin"):
        assert np.allclose(kin.ik(poses, pr_mode=mode), geometric - kin.compensate(poses, pr_mode=mode), atol=1e-13)
    # The signed PR length error: the screw's twist from home, one lead per turn.
    twist = kin.pr_twist(poses) - kin.pr_twist(kin.home)
    wrapped = np.arctan2(np.sin(twist), np.cos(twist))
    assert np.abs(wrapped).max() > 1e-3, "the draws twist the legs"
    expected = drive["pr_sign"] * drive["lead_m"] / (2 * math.pi) * wrapped
    assert np.allclose(kin.compensate(poses, pr_mode="signed"), expected, atol=1e-14)


def test_a_pure_yaw_twists_the_legs_as_the_platform_is_symmetric(kin):
    # The platform has three-fold symmetry about z: a yaw turns legs 1, 3, 5
    # alike and 2, 4, 6 alike, every screw the same way.
    yawed = kin.home.copy()
    yawed[5] = 0.2
    twist = kin.pr_twist(yawed)[0] - kin.pr_twist(kin.home)[0]
    assert np.ptp(twist[0::2]) < 1e-12 and np.ptp(twist[1::2]) < 1e-12
    assert np.all(twist > 1e-3)


def test_times_and_calibration_arguments_are_checked(kin, tmp_path):
    with pytest.raises(ValueError, match="times_s: row 1"):
        kin.ik(np.array([kin.home, kin.home]), times_s=[0.0, 0.0])
    with pytest.raises(ValueError, match="times_s: want 2 times"):
        kin.ik(np.array([kin.home, kin.home]), times_s=[0.0])
    with pytest.raises(FileNotFoundError, match="calibration: nowhere.json"):
        edsp.Kinematics(CONFIG, calibration="nowhere.json")
    broken = tmp_path / "model.json"
    broken.write_text('{"format": "edsp-gap-model/1", "effects": [{"name": "leg_offset", "params": [1.0]}]}')
    with pytest.raises(ValueError, match="model.json"):
        edsp.Kinematics(CONFIG, calibration=broken)
    assert edsp.Kinematics(CONFIG).calibration == ""
