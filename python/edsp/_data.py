"""Messages as numpy structured arrays: edsp.read_log and the recordings of
Platform.record (docs/python.md). The decoding runs in C++ (_edsp), into
one structured array per channel: a field per message field (arrays keep
their shape: pose is (6,), base_joints_m (6, 3)), text as Python str, and
`receive_utime` first, when the message came (the log's event stamp, or
the recorder's clock). Here: the arguments, the warnings, the recorder."""
from __future__ import annotations

import os
import threading
import time
import warnings
from typing import Callable, Dict, Iterable, Optional, Union

import numpy as np

from . import _edsp

#: Every edsp channel and its message type (lcmtypes/include/edsp/channels.h).
CHANNELS: Dict[str, str] = dict(_edsp.CHANNELS)


def _structured(table) -> np.ndarray:
    return table[2]  # (type, skipped, array): built in C++ in its final layout


def _channel_list(channels, what: str) -> Optional[list]:
    if channels is None:
        return None
    if isinstance(channels, str):
        channels = [channels]
    out = []
    for c in channels:
        if not isinstance(c, str) or not c:
            raise TypeError(f"{what}: want channel names (str), got {c!r}")
        out.append(c)
    return out


def _tables(tables: dict, asked: Optional[list], what: str) -> Dict[str, np.ndarray]:
    out = {channel: _structured(table) for channel, table in tables.items()}
    skipped = {channel: table[1] for channel, table in tables.items() if table[1]}
    if skipped:
        warnings.warn(f"{what}: messages of another type or damaged, not kept: {skipped}", stacklevel=3)
    for channel in asked or []:
        if channel not in out and channel in CHANNELS:
            out[channel] = _structured(_edsp.empty_table(CHANNELS[channel]))  # asked for, none came
    return out


def read_log(path: Union[str, os.PathLike], channels: Optional[Iterable[str]] = None) -> Dict[str, np.ndarray]:
    """Every message of an LCM log (edsp-logger's, lcm-logger's) as a dict
    channel -> numpy structured array, one row per message.

    `channels`: names to read (default: all). A name that is neither an edsp
    channel nor in the log raises ValueError naming it; an edsp channel the
    log does not hold is an empty array of its type. Channels of foreign
    types are left out with a warning naming them; a log that ends in
    damage gives every message before it, with a warning saying where."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"read_log: {path} does not exist")
    asked = _channel_list(channels, "channels")
    try:
        tables, info = _edsp.read_log(path, asked)
    except RuntimeError as e:
        raise ValueError(f"read_log: {e}") from None
    if info["unknown"]:
        warnings.warn(f"read_log {path}: channels edsp cannot decode, left out: {dict(info['unknown'])}", stacklevel=2)
    if info["damaged"]:
        warnings.warn(f"read_log {path}: damaged at byte {info['damage_offset']}; "
                      "every message before it is read", stacklevel=2)
    unknown = [c for c in asked or [] if c not in tables and c not in CHANNELS and c not in info["unknown"]]
    if unknown:
        raise ValueError(f"read_log {path}: no channel {', '.join(unknown)} in the log, and not an edsp channel "
                         f"(edsp's: {', '.join(CHANNELS)})")
    return _tables(tables, asked, f"read_log {path}")


class Recording:
    """What a running group publishes on some channels, recorded from the
    moment it is made (Platform.recorder) until stop(); as a context
    manager, until the with-block ends.

        with rig.recorder(["EDSP_TRACKER", "EDSP_LEG_STATE"]) as rec:
            rig.move(...)
        rec.data["EDSP_TRACKER"]["point_m"]      # (N, 3)
        rec.save("run.lcmlog")                   # for edsp-gap, edsp-log, lcm-logplayer
    """

    #: Message bytes kept at most (memory use is some 1.5 times that);
    #: messages beyond are counted in stats()["dropped"].
    MAX_BYTES = 2 << 30

    def __init__(self, group_file: str, lcm_url: str, channels: Optional[Iterable[str]]):
        asked = _channel_list(channels, "channels")
        if asked is None:
            asked = list(CHANNELS)
        elif not asked:
            raise ValueError("channels: want at least one channel name (None records every edsp channel)")
        foreign = [c for c in asked if c not in CHANNELS]
        if foreign:
            raise ValueError(f"channels: {', '.join(foreign)}: not an edsp channel (edsp's: {', '.join(CHANNELS)})")
        self._asked = asked
        self._r = _edsp.Recording(group_file, lcm_url, asked, Recording.MAX_BYTES)
        self._stopped = False
        self._data: Optional[Dict[str, np.ndarray]] = None

    def stop(self) -> None:
        """Ends the recording (what came is kept); warns of anything lost."""
        if self._stopped:
            return
        self._r.stop()
        self._stopped = True
        stats = self._r.stats()
        if stats["error"]:
            warnings.warn(f"recording: the bus failed ({stats['error']}); what came before is kept", stacklevel=2)
        if stats["dropped"]:
            warnings.warn(f"recording: {stats['dropped']} messages past {Recording.MAX_BYTES} bytes dropped",
                          stacklevel=2)
        if stats["overruns"]:
            warnings.warn(f"recording: {stats['overruns']} messages lost on shared-memory rings (read too late)",
                          stacklevel=2)

    @property
    def data(self) -> Dict[str, np.ndarray]:
        """What was recorded (stopping it first): a dict channel -> structured array."""
        self.stop()
        if self._data is None:
            self._data = _tables(self._r.columns(), self._asked, "recording")
        return self._data

    def stats(self) -> dict:
        """messages, bytes, dropped (past the memory bound), overruns (lost on a
        shared-memory ring), error (the bus's, if it failed)."""
        return self._r.stats()

    def save(self, path: Union[str, os.PathLike]) -> str:
        """Writes what was recorded as an LCM log (replacing the file); returns its path."""
        path = os.fspath(path)
        try:
            self._r.save(path)
        except RuntimeError as e:
            raise OSError(str(e)) from None
        return path

    def __enter__(self) -> "Recording":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()


def record_for(recording: Recording, seconds: Optional[float], until) -> Dict[str, np.ndarray]:
    """Platform.record's wait: `seconds`, or until `until` (a callable
    returning true, or a threading.Event) is set, whichever comes first.
    Ctrl-C ends it early: what came is returned, with a warning."""
    if seconds is None and until is None:
        raise ValueError("record: give seconds, until, or both (or use recorder() as a with-block)")
    if seconds is not None and (not np.isfinite(seconds) or seconds <= 0):
        raise ValueError(f"record: seconds = {seconds!r}: want a positive finite duration")
    done: Callable[[], bool]
    if until is None:
        done = lambda: False  # noqa: E731
    elif isinstance(until, threading.Event):
        done = until.is_set
    elif callable(until):
        done = until
    else:
        raise TypeError(f"record: until = {until!r}: want a callable or a threading.Event")
    end = time.monotonic() + seconds if seconds is not None else float("inf")
    try:
        while time.monotonic() < end and not done():
            time.sleep(min(0.01, max(0.0, end - time.monotonic())))
    except KeyboardInterrupt:
        warnings.warn("record: interrupted; returning what came until then", stacklevel=2)
    return recording.data
