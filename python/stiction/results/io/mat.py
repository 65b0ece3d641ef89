"""The Dymola/OpenModelica result file (MATLAB v4, ``binTrans``): written by the compiled core,
read with a few lines of NumPy (so results of Dymola and OpenModelica load without SciPy)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["read_mat", "write_mat"]


def write_mat(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """Dymola/OpenModelica result (MATLAB v4, binTrans); ``parameters`` go to data_1."""
    from stiction import _core as core

    if list(names[:1]) != ["time"]:
        raise ValueError("a .mat result needs 'time' as its first signal")
    data = np.ascontiguousarray(data, dtype=np.float64)
    descriptions = ["Time in [s]" if n == "time" else "" for n in names]
    params = [(k, "", float(v)) for k, v in (parameters or {}).items()]
    core.write_mat(os.fspath(path), list(names), descriptions, data, params)


_DTYPES = {0: "<f8", 1: "<f4", 2: "<i4", 3: "<i2", 4: "<u2", 5: "u1"}


def _read_matrices(raw: bytes, path: Path) -> dict[str, np.ndarray]:
    out, pos = {}, 0
    while pos + 20 <= len(raw):
        kind, rows, cols, imag, namelen = np.frombuffer(raw, "<i4", 5, pos)
        pos += 20
        name = raw[pos : pos + namelen - 1].decode("latin-1")
        pos += namelen
        prec = (kind % 100) // 10
        if kind >= 1000 or prec not in _DTYPES or imag:
            raise ValueError(f"{path}: matrix '{name}' is not little-endian real MATLAB v4 data")
        dtype = np.dtype(_DTYPES[prec])
        count = int(rows) * int(cols)
        values = np.frombuffer(raw, dtype, count, pos)
        pos += count * dtype.itemsize
        out[name] = values.reshape((int(cols), int(rows))).T  # stored column-major
    return out


def _text(matrix: np.ndarray, transposed: bool) -> list[str]:
    chars = matrix if not transposed else matrix.T
    return ["".join(map(chr, row)).rstrip(" \0") for row in chars.astype(np.uint8)]


def read_mat(path: Path) -> tuple[list[str], np.ndarray, dict[str, float]]:
    m = _read_matrices(path.read_bytes(), path)
    if not {"Aclass", "name", "dataInfo", "data_2"} <= set(m):
        raise ValueError(f"{path}: not a Dymola/OpenModelica result (Aclass, name, dataInfo, data_2)")
    transposed = _text(m["Aclass"], False)[3] == "binTrans"
    names = _text(m["name"], transposed)
    info = m["dataInfo"] if transposed else m["dataInfo"].T
    data2 = m["data_2"].T if transposed else m["data_2"]
    data1 = (m["data_1"].T if transposed else m["data_1"]) if "data_1" in m else None
    columns: dict[str, Any] = {"time": data2[:, 0]}
    parameters: dict[str, float] = {}
    for i, name in enumerate(names):
        matrix, index = int(info[0, i]), int(info[1, i])
        sign = -1.0 if index < 0 else 1.0
        if matrix == 2 and name not in columns:
            columns[name] = sign * data2[:, abs(index) - 1]
        elif matrix == 1 and data1 is not None:
            parameters[name] = float(sign * data1[0, abs(index) - 1])
    names_out = list(columns)
    return names_out, np.column_stack([np.asarray(c, dtype=np.float64) for c in columns.values()]), parameters
