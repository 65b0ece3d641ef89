"""The measured data of a fit: read, checked (time column, increasing times, every named column
present and every model name known) and turned into the model a fit runs — its experiment on
the data's time span, each input column a TimeTable driving its port."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps
from stiction.errors import ModelError
from stiction.model.components import Component
from stiction.model.model import Model
from stiction.results.result import Result

if TYPE_CHECKING:
    import pandas

__all__ = ["Measured", "fit_model", "read_data"]

TIME_NAMES = ("time", "Time", "t")


@dataclass
class Measured:
    """The data as a fit reads it: times, the matched outputs (model name → values) and the
    inputs (model port → values)."""

    time: np.ndarray
    outputs: dict[str, np.ndarray]
    inputs: dict[str, np.ndarray]
    columns: dict[str, str]  # model name -> data column, outputs then inputs


def _frame(data: Any) -> pandas.DataFrame:
    pd = _deps.pandas

    if isinstance(data, pd.DataFrame):
        return data
    if isinstance(data, str | os.PathLike):
        path = Path(data)
        if not path.exists():
            raise ModelError(f"fit data: no file {path}")
        result = Result.load(path)
        return pd.DataFrame(result.data, columns=result.names)
    raise ModelError(f"fit data: a pandas DataFrame or a CSV/.mat/Parquet path, got {type(data).__name__}")


def _mapping(given: Mapping[str, str] | Sequence[str] | None, what: str) -> dict[str, str] | None:
    if given is None:
        return None
    if isinstance(given, str):
        return {given: given}
    if isinstance(given, Mapping):
        return {str(k): str(v) for k, v in given.items()}
    return {str(n): str(n) for n in given}


def read_data(
    data: Any,
    outputs: Mapping[str, str] | Sequence[str] | None,
    inputs: Mapping[str, str] | Sequence[str] | None,
) -> Measured:
    """Read and check ``data`` (see the module docstring); ``ModelError`` naming what is wrong."""
    frame = _frame(data)
    names = [str(c) for c in frame.columns]
    time_name = next((n for n in TIME_NAMES if n in names), None)
    if time_name is None:
        raise ModelError(f"fit data: no time column (one named 'time'); the columns are {', '.join(names)}")
    time = np.asarray(frame[time_name], dtype=float)
    if len(time) < 3:
        raise ModelError(f"fit data: {len(time)} rows; a fit needs a trace")
    steps = np.diff(time)
    if not np.all(np.isfinite(time)) or np.any(steps <= 0):
        bad = int(np.flatnonzero(~(steps > 0))[0]) + 1 if np.any(~(steps > 0)) else 0
        raise ModelError(
            f"fit data: times must increase row by row; row {bad + 1} has t = {time[bad]:g} after {time[max(bad - 1, 0)]:g}"
        )
    ins = _mapping(inputs, "inputs") or {}
    outs = _mapping(outputs, "outputs")
    if outs is None:  # every other column is an output of the same name
        outs = {n: n for n in names if n != time_name and n not in ins.values()}
    if not outs:
        raise ModelError("fit: no outputs to match (name them with outputs={'J.w': 'speed'})")
    columns = {**outs, **ins}
    for model_name, column in columns.items():
        if column not in names:
            raise ModelError(
                f"fit data: no column '{column}' (for '{model_name}'); the columns are {', '.join(names)}"
            )

    def values(column: str) -> np.ndarray:
        v = np.asarray(frame[column], dtype=float)
        if not np.all(np.isfinite(v)):
            raise ModelError(f"fit data: column '{column}' has missing or infinite values")
        return v

    return Measured(
        time, {k: values(c) for k, c in outs.items()}, {k: values(c) for k, c in ins.items()}, columns
    )


def fit_model(model: Model, measured: Measured) -> Model:
    """A copy of ``model`` for the fit: its experiment over the data's time span (the output
    grid on the data's times when they are evenly spaced), each input driven by a TimeTable
    of its column (what drove the port before is cut off)."""
    t = measured.time
    fitted = Model(model.name, model.base_dir)
    fitted.experiment.update(model.experiment)
    fitted.experiment.update(
        StartTime=float(t[0]), StopTime=float(t[-1]), Interval=float((t[-1] - t[0]) / (len(t) - 1))
    )
    for port in measured.inputs:
        comp, _, rest = port.partition(".")
        if comp not in model.components or not rest:
            raise ModelError(f"fit input '{port}': not a port of a component of this model")
    for name, comp in model.components.items():
        fitted.add(name, comp)
    for a, b in model.connections:
        if a not in measured.inputs and b not in measured.inputs:
            fitted.connect(a, b)
    for port, start in model.inputs.items():
        if port not in measured.inputs:
            fitted.input(port, start)
    for i, (port, values) in enumerate(measured.inputs.items()):
        name = f"fit_input{i + 1}"
        table = np.column_stack([t, values]).tolist()
        fitted.add(name, Component("TimeTable", {"table": table, "extrapolation": "HoldLastPoint"}))
        fitted.connect(f"{name}.y", port)
    fitted.variables.update(model.variables)
    fitted.parameters.update(model.parameters)
    fitted.declarations.update(model.declarations)
    return fitted
