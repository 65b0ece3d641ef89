"""The MSL regression check: does a result stay inside the tube around a reference?

This is the comparison the Modelica Association runs on MAP-LIB reference results (CSV
Compare, tube method, relative tolerance 2e-3). For each reference signal:

* ``X = tol * (t_max - t_min)`` is the tube half-width in time,
* ``Y = tol * baseY`` its half-height,
  with ``baseY = max(y_max - y_min, 1e-15 * max(1, max|y|))``,
* the reference is a piecewise-linear curve (a repeated time is a vertical jump),
  and the tube at time ``t`` is ``[min - Y, max + Y]`` of that curve over the
  window ``[t - X, t + X]``.

Every point of the test signal must lie inside. The time half-width is what lets an
event that happens a little earlier or later than in the reference still pass.

One addition to MSL's method: ``Y`` is at least an absolute ``floor`` (default 1e-9), so a
signal that is exactly zero in the reference (a torque in an unconnected flange) is not failed
by round-off of 1e-12 in the result, where MSL's ``Y`` would be 2e-18.

The tube and the check of a signal are the core's (``compare.rs``, through ``_core.tube`` and
``_core.check_signal``): one implementation for ``cargo test`` and Python alike. This module
reads the inputs and reports.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

import numpy as np

from stiction.results.io import csv as csvio
from stiction.results.io import formats as resultio

__all__ = [
    "DEFAULT_FLOOR",
    "CompareReport",
    "SignalReport",
    "compare",
    "parse_signals",
    "read_signal_list",
    "tube",
]

Trajectories = Union[str, "os.PathLike[str]", Any, tuple[Sequence[str], np.ndarray]]


@dataclass(frozen=True)
class SignalReport:
    """The verdict for one signal.

    ``max_excess`` is the largest distance of a test point outside the tube, in units
    of the tube half-height Y (0 when every point is inside; inf for NaN values).
    ``missing`` names the side that lacks the signal ("result" or "reference"), or is
    None.
    """

    name: str
    passed: bool
    max_excess: float = 0.0
    worst_time: float | None = None
    points_outside: int = 0
    missing: str | None = None
    x: float = 0.0  # tube half-width in time
    y: float = 0.0  # tube half-height

    def __str__(self) -> str:
        if self.passed:
            return f"PASS {self.name}"
        if self.missing:
            return f"FAIL {self.name}  missing in {self.missing}"
        excess, when = self.max_excess, self.worst_time
        return f"FAIL {self.name}  max excess {excess:.3g}×tube at t={when:.6g}"


@dataclass(frozen=True)
class CompareReport:
    """Verdicts for all compared signals; passes only if every one does."""

    signals: list[SignalReport]
    tolerance: float
    _by_name: dict[str, SignalReport] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_by_name", {s.name: s for s in self.signals})

    @property
    def passed(self) -> bool:
        return all(s.passed for s in self.signals)

    @property
    def failed(self) -> list[str]:
        """Names of the signals that failed."""
        return [s.name for s in self.signals if not s.passed]

    def __getitem__(self, name: str) -> SignalReport:
        return self._by_name[name]

    def __iter__(self) -> Iterator[SignalReport]:
        return iter(self.signals)

    def __len__(self) -> int:
        return len(self.signals)

    def __str__(self) -> str:
        return "\n".join(str(s) for s in self.signals)

    def summary(self, verbose: bool = False) -> str:
        """The failures (every signal if ``verbose``) and a count: ``12/13 signals passed``."""
        shown = [str(s) for s in self.signals if verbose or not s.passed]
        passed = len(self) - len(self.failed)
        return "\n".join([*shown, f"{passed}/{len(self)} signals passed (tolerance {self.tolerance:g})"])


# --- the tube: computed by the core (compare.rs), the one implementation -----------------
DEFAULT_FLOOR = 1e-9
"""Smallest tube half-height: exact zeros compare equal to round-off."""


def _f64(values: Any) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.float64)


def tube(
    t_ref: np.ndarray,
    y_ref: np.ndarray,
    t: np.ndarray,
    tolerance: float = 2e-3,
    floor: float = DEFAULT_FLOOR,
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Lower and upper tube edges at times ``t``, and the half-sizes (X, Y); Y >= ``floor``."""
    from stiction import _core

    return _core.tube(_f64(t_ref), _f64(y_ref), _f64(t), float(tolerance), float(floor))


def _check_signal(
    name: str,
    t_ref: np.ndarray,
    y_ref: np.ndarray,
    t: np.ndarray,
    y: np.ndarray,
    tol: float,
    floor: float,
) -> SignalReport:
    from stiction import _core

    excess, when, outside, x_half, y_half = _core.check_signal(
        _f64(t_ref), _f64(y_ref), _f64(t), _f64(y), float(tol), float(floor)
    )
    return SignalReport(name, outside == 0, excess, when, outside, None, x_half, y_half)


# --- inputs ---------------------------------------------------------------------------
def read_signal_list(path: str | os.PathLike[str]) -> list[str]:
    """Read an MSL ``comparisonSignals.txt`` list: one name per line, ``time`` first."""
    names = []
    for line in Path(path).read_text(encoding="utf-8-sig").splitlines():
        name = line.strip()
        if name and not name.startswith("#") and name != "time":
            names.append(name)
    return names


def parse_signals(text: str) -> list[str]:
    """The ``--signals`` argument of every command: ``a,b,c`` or ``@FILE`` (one per line).

    A name may join others with ``+`` (``a+b``: one plot axes); the caller splits that.
    """
    text = text.strip()
    if text.startswith("@"):
        return read_signal_list(text[1:])
    if Path(text).is_file():
        raise ValueError(f"--signals {text}: to read names from that file, write @{text}")
    return [n.strip() for n in text.split(",") if n.strip() and n.strip() != "time"]


def _as_table(source: Trajectories, what: str) -> tuple[list[str], np.ndarray]:
    if isinstance(source, (str, os.PathLike)):
        if Path(source).suffix.lower() in resultio.FORMATS:  # CSV, Dymola/OpenModelica .mat, Parquet
            names, data, _ = resultio.read(source)
            return names, data
        return csvio.read_csv(source)
    if hasattr(source, "names") and hasattr(source, "data"):  # a Result
        return list(source.names), np.asarray(source.data, dtype=np.float64)
    if isinstance(source, tuple) and len(source) == 2:
        names, data = source
        data = np.asarray(data, dtype=np.float64)
        if data.ndim != 2 or data.shape[1] != len(names):
            raise ValueError(f"{what}: data shape {data.shape} does not match {len(names)} names")
        return list(names), data
    raise TypeError(f"{what}: expected a CSV path, a Result or (names, data), got {type(source)}")


def _time_column(names: list[str], data: np.ndarray, what: str) -> np.ndarray:
    if "time" not in names:
        raise ValueError(f"{what}: no 'time' column")
    t = data[:, names.index("time")]
    if t.size > 1 and np.any(np.diff(t) < 0):
        raise ValueError(f"{what}: time decreases")
    return t


def compare(
    result: Trajectories,
    reference: Trajectories,
    tolerance: float = 2e-3,
    signals: Sequence[str] | str | os.PathLike[str] | None = None,
    floor: float = DEFAULT_FLOOR,
) -> CompareReport:
    """Check ``result`` against ``reference`` with the MSL tube method.

    ``result`` and ``reference`` are CSV paths, ``Result`` objects or ``(names, data)``
    pairs. ``signals`` is a list of names, a path to a ``.signals.txt`` list, or None
    for every signal of the reference except time. ``floor`` is the smallest tube
    half-height (0 gives MSL's method exactly).
    """
    if not tolerance > 0:
        raise ValueError(f"tolerance must be positive, got {tolerance}")
    if not floor >= 0:
        raise ValueError(f"floor must be >= 0, got {floor}")
    ref_names, ref_data = _as_table(reference, "reference")
    test_names, test_data = _as_table(result, "result")
    t_ref = _time_column(ref_names, ref_data, "reference")
    t_test = _time_column(test_names, test_data, "result")

    if signals is None:
        wanted = [n for n in ref_names if n != "time"]
    elif isinstance(signals, (str, os.PathLike)):
        wanted = read_signal_list(signals)
    else:
        wanted = [n for n in signals if n != "time"]

    ref_index = {n: i for i, n in enumerate(ref_names)}
    test_index = {n: i for i, n in enumerate(test_names)}
    reports = []
    for name in wanted:
        if name not in ref_index:
            reports.append(SignalReport(name, False, missing="reference"))
        elif name not in test_index:
            reports.append(SignalReport(name, False, missing="result"))
        else:
            y_ref = ref_data[:, ref_index[name]]
            y = test_data[:, test_index[name]]
            reports.append(_check_signal(name, t_ref, y_ref, t_test, y, tolerance, floor))
    return CompareReport(reports, tolerance)
