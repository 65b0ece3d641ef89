"""Trajectory CSV files in the MSL reference style.

Quoted header, ``time`` first, one row per output point (event instants twice).
Reads MAP-LIB reference files and our own results alike.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

__all__ = ["INTEGER_SUFFIXES", "is_integer_signal", "read_csv", "write_csv"]

# Discrete signals (friction modes, Boolean flags) are written as integers, as in MSL.
INTEGER_SUFFIXES = (
    ".mode",
    ".locked",
    ".startForward",
    ".startBackward",
    ".free",
    ".stuck",
)


def is_integer_signal(name: str) -> bool:
    """Tell whether a column holds a mode or flag (written as -1, 0, 1 …, not -1.0)."""
    return name.endswith(INTEGER_SUFFIXES)


def read_csv(path: str | os.PathLike[str]) -> tuple[list[str], np.ndarray]:
    """Read a trajectory file into (names, data); data has shape (rows, len(names))."""
    path = Path(path)
    with path.open("r", encoding="utf-8-sig", newline="") as f:
        header_line = f.readline()
        if not header_line.strip():
            raise ValueError(f"{path}: empty file, expected a header row of signal names")
        names = [n.strip() for n in next(csv.reader([header_line]))]
        body = f.read()
    if not body.strip():
        return names, np.empty((0, len(names)))
    try:
        data = np.loadtxt(io.StringIO(body), delimiter=",", ndmin=2, dtype=np.float64)
    except ValueError as exc:
        raise ValueError(f"{path}: not a numeric CSV body: {exc}") from None
    if data.shape[1] != len(names):
        raise ValueError(f"{path}: header has {len(names)} names but rows have {data.shape[1]} values")
    return names, data


def _cell(value: float, integer: bool) -> str:
    if integer and value.is_integer():
        return str(int(value))
    return repr(value)  # shortest text that reads back to the same double


def write_csv(path: str | os.PathLike[str], names: Sequence[str], data: np.ndarray) -> None:
    """Write (names, data): quoted header, full precision, integer modes and flags."""
    data = np.asarray(data, dtype=np.float64)
    if data.ndim != 2 or data.shape[1] != len(names):
        raise ValueError(f"data shape {data.shape} does not match {len(names)} names")
    integer = [is_integer_signal(n) for n in names]
    header = ",".join('"' + n.replace('"', '""') + '"' for n in names)
    lines = [header]
    for row in data.tolist():
        lines.append(",".join(_cell(v, i) for v, i in zip(row, integer, strict=True)))
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8", newline="\n")
