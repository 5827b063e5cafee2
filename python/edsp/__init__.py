"""edsp from Python: the kinematics on numpy arrays, a running group's
motion service and data recorder, LCM logs as numpy arrays, and the gap
diagnosis (docs/python.md).

    import edsp
    kin = edsp.Kinematics("config/huang2021.toml")
    lengths = kin.ik(poses)                      # (N, 6) -> (N, 6), PR-compensated
    rig = edsp.Platform("deploy/groups/sim.toml")
    rig.move([0.02, 0, 1.53, 0, 0, 0])           # waits until on target
"""
from __future__ import annotations

import enum
import math
import os
from typing import Optional, Sequence

from . import _edsp, gap
from ._data import CHANNELS, Recording, read_log, record_for

__all__ = ["Kinematics", "Platform", "Recording", "read_log", "gap", "CHANNELS", "PrMode", "WaitOutcome",
           "REPLY_CODES", "SetpointPhase", "EdspError", "RefusedError", "TimeoutError", "HaltedError", "FaultError",
           "Refused", "Timeout", "Halted", "Fault"]

# Made by the C++ module from its own tables (reply codes, wait outcomes,
# PR modes): raised by it as replies and waits end. Each has `.code`, the
# reply code's or the outcome's name. edsp.TimeoutError is also Python's.
EdspError = _edsp.EdspError
RefusedError = _edsp.RefusedError
TimeoutError = _edsp.TimeoutError  # noqa: A001 (is-a builtins.TimeoutError)
HaltedError = _edsp.HaltedError
FaultError = _edsp.FaultError
PrMode = _edsp.PrMode
WaitOutcome = _edsp.WaitOutcome
REPLY_CODES = _edsp.REPLY_CODES  # name -> the wire's code (reply_t.CODE_*)
# A setpoint's phase (EDSP_SETPOINT's `phase` column: hold, move, dwell,
# cueing), an int so that numpy columns compare with it.
SetpointPhase = enum.IntEnum("SetpointPhase", _edsp.SETPOINT_PHASES)
# The names of earlier releases.
Refused, Timeout, Halted, Fault = RefusedError, TimeoutError, HaltedError, FaultError


def _mode_text(mode) -> str:
    """A PR mode given as PrMode or as its name ("signed")."""
    if isinstance(mode, PrMode):
        return mode.name.lower()
    if not isinstance(mode, str):
        raise TypeError(f"pr_mode: want an edsp.PrMode or its name, got {type(mode).__name__}")
    return mode


def _timeout(timeout, timeout_s, default):
    """`timeout` in seconds, as threading and subprocess spell it; `timeout_s` its alias."""
    if timeout is not None and timeout_s is not None:
        raise TypeError("give timeout or timeout_s, not both")
    return timeout if timeout is not None else timeout_s if timeout_s is not None else default


class Kinematics:
    """Inverse and forward kinematics of the platform a config file describes,
    with a calibration in force if given (an edsp-gap model file, as the
    kinematics node applies it).

    ik(poses, pr_mode="signed", times_s=None) -> leg lengths to command, (N, 6) m
    compensate(poses, pr_mode="signed", times_s=None) -> what ik subtracts from
        the geometric leg lengths: the PR length error and the calibration's
        correction, (N, 6) m
    pr_twist(poses)             -> each leg's signed screw twist, (N, 6) rad
    fk(lengths, with_pr=True)   -> poses, (N, 6): x y z (m), roll pitch yaw (rad)
    check(poses)                -> per pose None, or the workspace limit it crosses
    Poses are the pose of {M} in {B}, as on EDSP_SETPOINT. Arrays of shape
    (N, 6) or (6,); anything else, or a non-finite value, raises ValueError
    or TypeError naming the argument. With a calibration, `times_s` makes
    the rows a trajectory (its rates and history, as the node follows a
    setpoint stream); without, each pose is taken at rest. The loops run
    without the GIL.
    """

    def __init__(self, config, calibration=None, apply_ambiguous: bool = False):
        if not isinstance(config, (str, os.PathLike)):
            raise TypeError(f"config: want a path to a platform TOML file, got {type(config).__name__}")
        if calibration is not None and not isinstance(calibration, (str, os.PathLike)):
            raise TypeError(f"calibration: want an edsp-gap model file, got {type(calibration).__name__}")
        for name, path in (("config", config), ("calibration", calibration)):
            if path is not None and not os.path.isfile(path):
                raise FileNotFoundError(f"{name}: {os.fspath(path)} does not exist")
        try:
            self._k = _edsp.Kinematics(os.fspath(config), os.fspath(calibration) if calibration else "",
                                       bool(apply_ambiguous))
        except RuntimeError as e:
            raise ValueError(str(e)) from None

    def ik(self, poses, pr_mode="signed", times_s=None):
        return self._k.ik(poses, _mode_text(pr_mode), times_s)

    def compensate(self, poses, pr_mode="signed", times_s=None):
        return self._k.compensate(poses, _mode_text(pr_mode), times_s)

    def pr_twist(self, poses):
        return self._k.pr_twist(poses)

    def fk(self, lengths, with_pr: bool = True):
        return self._k.fk(lengths, with_pr)

    def check(self, poses):
        return self._k.check(poses)

    @property
    def home(self):
        return self._k.home()

    @property
    def calibration(self) -> str:
        """The calibration in force: what it applies and what not ("" for none)."""
        return self._k.calibration()


def _six(name: str, values) -> list:
    if isinstance(values, (str, bytes)):
        raise TypeError(f"{name}: want six numbers x, y, z (m), roll, pitch, yaw (rad), got a {type(values).__name__}")
    try:
        out = [float(v) for v in values]
    except TypeError:
        raise TypeError(f"{name}: want six numbers x, y, z (m), roll, pitch, yaw (rad)") from None
    if len(out) != 6:
        raise ValueError(f"{name}: want six numbers x, y, z (m), roll, pitch, yaw (rad), got {len(out)}")
    for k, v in enumerate(out):
        if not math.isfinite(v):
            raise ValueError(f"{name}[{k}] = {v}: every value must be finite")
    return out


# A jog's axes, in the order of a pose (the planner's, motion_request_checks.h).
_JOG_AXES = _edsp.JOG_AXES


def _speed(name: str, value: Optional[float]) -> float:
    if value is None:
        return 0.0
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} = {value}: want a positive finite speed (or None for the default)")
    return v


class Platform:
    """A running group's platform, through the planner's motion service.

    The same requests and semantics as edsp-ctl (docs/operating.md): every
    method raises RefusedError with the node's reason (its .code says why),
    TimeoutError, HaltedError or FaultError; none waits longer than its
    timeout (seconds; `timeout=`, or `timeout_s=` as before).
    """

    def __init__(self, group_file: Optional[str] = None, session_id: Optional[int] = None,
                 lcm_url: str = "", answer_timeout_s: float = 2.0, client: str = "python"):
        if group_file is not None and not os.path.isfile(group_file):
            raise FileNotFoundError(f"group_file: {group_file} does not exist")
        self._group_file, self._lcm_url = group_file or "", lcm_url
        if session_id is not None:
            if isinstance(session_id, bool) or not hasattr(session_id, "__index__") or session_id.__index__() < 0:
                raise ValueError(f"session_id = {session_id!r}: want a non-negative int, or None to find it")
            session_id = session_id.__index__()
        try:
            # No group (or several) on the bus raises TimeoutError itself.
            self._c = _edsp.Client(group_file or "", lcm_url, session_id, float(answer_timeout_s), client)
        except RuntimeError as e:  # a malformed group file, a bus that cannot open
            raise EdspError(str(e)) from None

    @property
    def session_id(self) -> int:
        return self._c.session_id

    def recorder(self, channels=None) -> Recording:
        """Starts recording `channels` (edsp channel names; None: every one)
        at full rate, on the routes the group gives them; stop() or the end
        of a with-block ends it. See Recording."""
        try:
            return Recording(self._group_file, self._lcm_url, channels)
        except RuntimeError as e:
            raise EdspError(f"recorder: {e}") from None

    def record(self, channels, seconds: Optional[float] = None, until=None) -> dict:
        """Records `channels` for `seconds`, or until `until` (a callable
        returning true, or a threading.Event): a dict channel -> numpy
        structured array, every field of every message, receive_utime first."""
        return record_for(self.recorder(channels), seconds, until)

    def _send(self, kind, pose=(), relative=False, frame="", point=(), speed_m_s=0.0, speed_rad_s=0.0,
              accel_m_s2=0.0, accel_rad_s2=0.0, motions="", csv_text="", csv_origin=""):
        # Raises the exception of the reply's code, or TimeoutError.
        try:
            return self._c.send(kind, list(pose), relative, frame or "", list(point), speed_m_s, speed_rad_s,
                                accel_m_s2, accel_rad_s2, motions, csv_text, csv_origin)
        except EdspError:
            raise
        except RuntimeError as e:
            raise EdspError(str(e)) from None

    def _wait(self, request_id: int, timeout: Optional[float], reply: dict) -> dict:
        limit = timeout if timeout is not None else reply["start_delay_s"] + reply["duration_s"] + 30.0
        self._c.wait(request_id, float(limit))  # raises HaltedError, FaultError or TimeoutError
        return reply

    def move(self, pose: Sequence[float], frame: Optional[str] = None, relative: bool = False,
             speed_m_s: Optional[float] = None, speed_rad_s: Optional[float] = None, wait: bool = True,
             timeout: Optional[float] = None, timeout_s: Optional[float] = None) -> dict:
        """Move to `pose` (in `frame`, about the pivot); returns the reply.
        `timeout` (s): how long to wait for on-target (default: the motion's
        duration and 30 s beside)."""
        limit = _timeout(timeout, timeout_s, None)
        reply = self._send(_edsp.KIND_MOVE, _six("pose", pose), relative, frame or "",
                           speed_m_s=_speed("speed_m_s", speed_m_s), speed_rad_s=_speed("speed_rad_s", speed_rad_s))
        return self._wait(reply["request_id"], limit, reply) if wait else reply

    def check(self, pose: Sequence[float], frame: Optional[str] = None, relative: bool = False,
              speed_m_s: Optional[float] = None, speed_rad_s: Optional[float] = None) -> dict:
        """Whether a move would run (raises RefusedError naming why not); nothing moves."""
        return self._send(_edsp.KIND_CHECK, _six("pose", pose), relative, frame or "",
                          speed_m_s=_speed("speed_m_s", speed_m_s), speed_rad_s=_speed("speed_rad_s", speed_rad_s))

    def jog(self, axis: str, step: float, frame: Optional[str] = None, speed_m_s: Optional[float] = None,
            speed_rad_s: Optional[float] = None, wait: bool = True, timeout: Optional[float] = None,
            timeout_s: Optional[float] = None) -> dict:
        """A small relative move of the last target by `step` along one `axis`
        of `frame` ("x", "y", "z" in m; "roll", "pitch", "yaw" in rad, about
        the pivot), as move(..., relative=True). The planner refuses
        (RefusedError, code "invalid") a step that is zero, not finite or
        beyond 0.01 (10 mm, 10 mrad)."""
        limit = _timeout(timeout, timeout_s, None)
        if axis not in _JOG_AXES:
            raise ValueError(f"jog: axis {axis!r}: want one of {', '.join(_JOG_AXES)}")
        pose = [0.0] * 6
        pose[_JOG_AXES.index(axis)] = float(step)
        reply = self._send(_edsp.KIND_JOG, pose, True, frame or "",
                           speed_m_s=_speed("speed_m_s", speed_m_s), speed_rad_s=_speed("speed_rad_s", speed_rad_s))
        return self._wait(reply["request_id"], limit, reply) if wait else reply

    def run(self, motions: Optional[str] = None, csv: Optional[str] = None, wait: bool = True,
            timeout: Optional[float] = None, timeout_s: Optional[float] = None) -> dict:
        """Run named motions ("Lz,Rz") or a trajectory CSV file."""
        limit = _timeout(timeout, timeout_s, None)
        if (motions is None) == (csv is None):
            raise ValueError("run: give motions or csv, not both")
        text = ""
        if csv is not None:
            with open(csv, encoding="utf-8") as f:
                text = f.read()
        reply = self._send(_edsp.KIND_RUN, motions=motions or "", csv_text=text, csv_origin=csv or "")
        return self._wait(reply["request_id"], limit, reply) if wait else reply

    def halt(self) -> dict:
        return self._send(_edsp.KIND_HALT)

    def stop(self) -> dict:
        return self._send(_edsp.KIND_STOP)

    def wait(self, timeout: Optional[float] = None, timeout_s: Optional[float] = None) -> "WaitOutcome":
        """Until whatever runs is on target, at most `timeout` s (default 60):
        WaitOutcome.ON_TARGET, else raises HaltedError, FaultError, TimeoutError."""
        return self._c.wait(0, float(_timeout(timeout, timeout_s, 60.0)))

    def status(self, timeout: Optional[float] = None, timeout_s: Optional[float] = None) -> dict:
        limit = _timeout(timeout, timeout_s, 2.0)
        s = self._c.status(float(limit))
        if s is None:
            error = TimeoutError(f"no EDSP_MOTION_STATUS within {limit} s (is the planner running?)")
            error.code = "timeout"
            raise error
        return s

    def frame(self, name: str, pose: Sequence[float]) -> dict:
        if not isinstance(name, str) or not name:
            raise ValueError(f"frame name {name!r}: want a non-empty string")
        return self._send(_edsp.KIND_FRAME, _six("pose", pose), frame=name)

    @staticmethod
    def _operator(request, *args) -> dict:
        """An operator's request: the node's reply, or the exception of its code."""
        try:
            return request(*args)
        except EdspError:
            raise
        except RuntimeError as e:  # the request could not be sent
            raise EdspError(str(e)) from None

    def arm(self) -> str:
        """Re-arm the actuator bridge after it latched a hold; returns its reply's words
        (FaultError if the drives could not be enabled)."""
        return self._operator(self._c.arm)["reason"]

    def pr_mode(self, mode) -> str:
        """Switch the PR compensation live (an edsp.PrMode, or its name: none,
        unsigned, signed, asin), blended over 0.5 s; returns the node's words."""
        return self._operator(self._c.pr_mode, _mode_text(mode))["reason"]

    def calibration(self, model: Optional[str], apply_ambiguous: bool = False) -> str:
        """Switch the kinematics' calibration live to the edsp-gap model file
        `model` (None: off), blended over 1 s; returns the node's reply's words."""
        text, origin = "", "off"
        if model is not None:
            with open(model, encoding="utf-8") as f:
                text = f.read()
            if not text:
                raise ValueError(f"calibration {model}: the file is empty (None switches the calibration off)")
            origin = os.fspath(model)
        return self._operator(self._c.calibration, text, origin, bool(apply_ambiguous))["reason"]

    def pivot(self, point: Sequence[float]) -> dict:
        if isinstance(point, (str, bytes)):
            raise TypeError(f"point: want three numbers x, y, z (m) in {{M}}, got a {type(point).__name__}")
        p = [float(v) for v in point]
        if len(p) != 3 or not all(math.isfinite(v) for v in p):
            raise ValueError(f"point {point!r}: want three finite numbers x, y, z (m) in {{M}}")
        return self._send(_edsp.KIND_PIVOT, point=p)
