"""The sim-to-real gap from Python: edsp-gap's diagnose and evaluate
(docs/diagnosis.md), on measurement files or on numpy data.

    report = edsp.gap.diagnose("config/huang2021-rig-effects.toml", "fit.lcmlog")
    report["conclusion"]                         # the dict of `edsp-gap diagnose --json`
    edsp.gap.save_model(report, "model.json")     # what `--save-model` writes
    edsp.gap.evaluate(config, "model.json", "held_out.lcmlog")["shrink"]

`data` is a path (a measurement CSV of interfaces.md §3, or an edsp LCM
log), a list of them, or arrays: a dict of columns or a numpy structured
array with the CSV's column names (`run`, `time_s`, `pose_cmd_x_m` …), or
a list mixing all of these.
"""
from __future__ import annotations

import io
import json
import os
from typing import Any, Dict, List, Tuple, Union

import numpy as np

from . import _edsp

__all__ = ["diagnose", "evaluate", "save_model", "GapReport"]

_OPTIONS = ("max_rate_hz", "thermal_time_constant_s", "structural_mode_hz", "structural_mode_damping")


class GapReport(dict):
    """The report of `edsp-gap diagnose --json`, with `.model`: the
    edsp-gap-model/1 JSON that `--save-model` writes (for save_model,
    evaluate, and Platform.calibration); None for a diagnosis against the
    calibration that data carrying its correction was recorded with."""

    def __init__(self, report: dict, model: dict):
        super().__init__(report)
        self.model = model


def _columns(data, index: int) -> Tuple[str, str]:
    """Array data as measurement CSV text (one parser for files and arrays)."""
    if isinstance(data, np.ndarray):
        if data.dtype.names is None:
            raise TypeError(f"data[{index}]: a numpy array needs named columns (a structured array), "
                            f"got dtype {data.dtype}")
        columns = {name: data[name] for name in data.dtype.names}
    else:
        columns = dict(data)
    if not columns:
        raise ValueError(f"data[{index}]: no columns")
    rows = None
    cells: List[List[str]] = []
    names = []
    for name, values in columns.items():
        values = np.asarray(values)
        if values.ndim != 1:
            raise ValueError(f"data[{index}] column {name}: want one value per row, got shape {values.shape}")
        if rows is None:
            rows = len(values)
        elif len(values) != rows:
            raise ValueError(f"data[{index}] column {name}: {len(values)} rows, the others have {rows}")
        if values.dtype.kind in "fiub":
            cells.append([repr(float(v)) if values.dtype.kind == "f" else str(int(v)) for v in values])
        else:
            text = [str(v) for v in values]
            for row, v in enumerate(text):
                if any(c in v for c in ',"\n'):
                    raise ValueError(f"data[{index}] column {name} row {row}: {v!r} holds a comma, quote or newline")
            cells.append(text)
        names.append(str(name))
    out = io.StringIO()
    out.write(",".join(names) + "\n")
    for row in zip(*cells):
        out.write(",".join(row) + "\n")
    return f"data[{index}] (arrays; CSV line 2 is row 0)", out.getvalue()


def _sources(data) -> Tuple[List[str], List[Tuple[str, str]]]:
    items = data if isinstance(data, list) else [data]
    if not items:
        raise ValueError("data: empty (give a file path, a list of them, or arrays)")
    paths, texts = [], []
    for index, item in enumerate(items):
        if isinstance(item, (str, os.PathLike)):
            path = os.fspath(item)
            if not os.path.isfile(path):
                raise FileNotFoundError(f"data[{index}]: {path} does not exist")
            paths.append(path)
        elif isinstance(item, (dict, np.ndarray)):
            texts.append(_columns(item, index))
        else:
            raise TypeError(f"data[{index}]: want a path, a dict of columns or a structured array, "
                            f"got {type(item).__name__}")
    return paths, texts


def _config(config) -> str:
    if not isinstance(config, (str, os.PathLike)):
        raise TypeError(f"config: want a path to a platform TOML file, got {type(config).__name__}")
    if not os.path.isfile(config):
        raise FileNotFoundError(f"config: {os.fspath(config)} does not exist")
    return os.fspath(config)


def diagnose(config, data, against: str = "nominal", **options: Any) -> GapReport:
    """`edsp-gap diagnose --json`: which unmodelled effects the data shows.
    Options as edsp-gap's: max_rate_hz, thermal_time_constant_s,
    structural_mode_hz, structural_mode_damping; `against` data recorded
    with a calibration in force: "nominal" (the rig's whole effects; the
    model replaces that calibration) or "calibration" (what it leaves; on
    data carrying a correction `.model` is then None: increments are no
    calibration to apply)."""
    if against not in ("nominal", "calibration"):
        raise ValueError(f"diagnose: against = {against!r}: use 'nominal' or 'calibration'")
    unknown = sorted(set(options) - set(_OPTIONS))
    if unknown:
        raise TypeError(f"diagnose: unknown option {', '.join(unknown)} (known: {', '.join(_OPTIONS)})")
    knobs = {}
    for name in _OPTIONS:
        value = options.get(name)
        if value is not None:
            value = float(value)
            if not np.isfinite(value) or value <= 0:
                raise ValueError(f"diagnose: {name} = {options[name]!r}: want a positive finite number")
        knobs[name] = value
    paths, texts = _sources(data)
    report, model = _edsp.gap_diagnose(_config(config), paths, texts, **knobs,
                                       against_calibration=against == "calibration")
    return GapReport(json.loads(report), json.loads(model) if model else None)


_INCREMENTS = ("this diagnosis ran against the calibration the data was recorded with: its effects are what that "
               "calibration leaves, and applied alone they would replace it; diagnose with against='nominal' (the "
               "default) for the rig's whole calibration")


def _model(model) -> Tuple[str, str]:
    if isinstance(model, GapReport):
        if model.model is None:
            raise ValueError("model: " + _INCREMENTS)
        return json.dumps(model.model), "the diagnosis' model"
    if isinstance(model, dict):
        return json.dumps(model), "the model dict"
    if isinstance(model, (str, os.PathLike)):
        path = os.fspath(model)
        with open(path, encoding="utf-8") as f:
            return f.read(), path
    raise TypeError(f"model: want a GapReport, a model dict or a model file, got {type(model).__name__}")


def evaluate(config, model, data, keep_timing_events: bool = False) -> Dict[str, Any]:
    """`edsp-gap evaluate --json`: a saved model applied to data it never saw."""
    text, origin = _model(model)
    paths, texts = _sources(data)
    return json.loads(_edsp.gap_evaluate(_config(config), text, origin, paths, texts, bool(keep_timing_events)))


def save_model(report: Union[GapReport, dict], path) -> str:
    """Writes the model of a diagnosis (what `--save-model` writes); returns the path."""
    model = report.model if isinstance(report, GapReport) else report
    if isinstance(report, GapReport) and model is None:
        raise ValueError("save_model: " + _INCREMENTS)
    if not isinstance(model, dict) or "format" not in model:
        raise TypeError("save_model: want the GapReport diagnose returned (or its .model)")
    path = os.fspath(path)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(model, f, indent=2)
        f.write("\n")
    return path
