"""Result files by extension: MSL-style CSV (``csv``), the Dymola/OpenModelica MATLAB v4
result (``mat``) and Parquet (``parquet``); an extension no writer knows is refused.

CSV and ``.mat`` are written by the compiled core (a 100-clutch chain has millions of values;
Python formatting them one by one took seconds).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from stiction.results.io import csv as csvio
from stiction.results.io.mat import read_mat, write_mat
from stiction.results.io.parquet import read_parquet, write_parquet

__all__ = ["FORMATS", "read", "result_format", "write", "write_csv", "write_mat", "write_parquet"]

FORMATS = (".csv", ".mat", ".parquet")


def result_format(path: str | os.PathLike[str]) -> str:
    """The format (``.csv``, ``.mat``, ``.parquet``) of a result path, or ValueError."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        shown = f"'{suffix}'" if suffix else "no extension"
        raise ValueError(f"{path}: unknown result format ({shown}); use one of {', '.join(FORMATS)}")
    return suffix


# Every writer (write_csv, mat.write_mat, parquet.write_parquet) takes the same four arguments:
# the one signature `write` dispatches on, so their headers look alike.
def write(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """Write ``data`` (rows × names, ``time`` first) in the format of ``path``'s extension.

    The file is written under a temporary name and renamed at the end, so an interrupted
    write (Ctrl-C, a full disk) never leaves a half-written result under ``path``; missing
    folders of ``path`` are made."""
    suffix = result_format(path)
    writer = {".csv": write_csv, ".mat": write_mat, ".parquet": write_parquet}[suffix]
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)  # `-o out/x.csv` makes out/, as `make demo` expects
    partial = target.with_name(f".{target.name}.partial{suffix}")
    try:
        writer(partial, names, data, parameters)
        partial.replace(target)
    finally:
        partial.unlink(missing_ok=True)


def _core_module() -> Any:
    try:
        from stiction import _core
    except ImportError:
        return None
    return _core


def write_csv(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """MSL-style CSV (parameters are not part of it), by the core when it is built."""
    data = np.ascontiguousarray(data, dtype=np.float64)
    core = _core_module()
    if core is None:
        csvio.write_csv(path, names, data)
        return
    integer = [csvio.is_integer_signal(n) for n in names]
    core.write_csv(os.fspath(path), list(names), integer, data)


def read(path: str | os.PathLike[str]) -> tuple[list[str], np.ndarray, dict[str, float]]:
    """Read a result file: (names, data, parameters); ``time`` is the first name."""
    kind = result_format(path)
    if kind == ".csv":
        return (*csvio.read_csv(path), {})
    if kind == ".parquet":
        return (*read_parquet(path), {})
    return read_mat(Path(path))
