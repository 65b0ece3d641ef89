"""Result files: MSL-style CSV, the Dymola/OpenModelica MATLAB v4 result, and Parquet.

The format follows the file extension; an extension no writer knows is refused. CSV and
``.mat`` are written by the compiled core (a 100-clutch chain has millions of values; Python
formatting them one by one took seconds), Parquet through pyarrow (an optional dependency:
``pip install stiction[parquet]``). The ``.mat`` reader is a few lines of NumPy, so results of
Dymola and OpenModelica load without SciPy.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from . import csvio

__all__ = ["FORMATS", "read", "result_format", "write", "write_csv", "write_mat", "write_parquet"]

FORMATS = (".csv", ".mat", ".parquet")


def result_format(path: str | os.PathLike[str]) -> str:
    """The format (``.csv``, ``.mat``, ``.parquet``) of a result path, or ValueError."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        shown = f"'{suffix}'" if suffix else "no extension"
        raise ValueError(f"{path}: unknown result format ({shown}); use one of {', '.join(FORMATS)}")
    return suffix


def write(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """Write ``data`` (rows × names, ``time`` first) in the format of ``path``'s extension.

    The file is written under a temporary name and renamed at the end, so an interrupted
    write (Ctrl-C, a full disk) never leaves a half-written result under ``path``."""
    suffix = result_format(path)
    writer = {".csv": write_csv, ".mat": write_mat, ".parquet": write_parquet}[suffix]
    target = Path(path)
    partial = target.with_name(f".{target.name}.partial{suffix}")
    try:
        writer(partial, names, data, parameters)
        partial.replace(target)
    finally:
        partial.unlink(missing_ok=True)


def _core_module() -> Any:
    try:
        from . import _core
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


def write_mat(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """Dymola/OpenModelica result (MATLAB v4, binTrans); ``parameters`` go to data_1."""
    core = _core_module()
    if core is None:
        raise ImportError("writing .mat needs the compiled engine")
    if list(names[:1]) != ["time"]:
        raise ValueError("a .mat result needs 'time' as its first signal")
    data = np.ascontiguousarray(data, dtype=np.float64)
    descriptions = ["Time in [s]" if n == "time" else "" for n in names]
    params = [(k, "", float(v)) for k, v in (parameters or {}).items()]
    core.write_mat(os.fspath(path), list(names), descriptions, data, params)


def write_parquet(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """A Parquet table, one float64 column per name (pyarrow); parameters are not stored."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise ImportError("writing Parquet needs pyarrow: pip install stiction[parquet]") from None
    columns = np.ascontiguousarray(np.asarray(data, dtype=np.float64).T)  # one contiguous row per signal
    rows = columns.shape[1]
    # Arrays made from the buffers directly: pa.array() would import pandas (0.7 s) to sniff types.
    arrays = [pa.Array.from_buffers(pa.float64(), rows, [None, pa.py_buffer(c)]) for c in columns]
    table = pa.Table.from_arrays(arrays, names=list(names))
    # Dictionary encoding and statistics cost more than the whole write for thousands of
    # float columns and buy nothing for trajectories; snappy compression stays.
    pq.write_table(table, os.fspath(path), use_dictionary=False, write_statistics=False)


def read(path: str | os.PathLike[str]) -> tuple[list[str], np.ndarray, dict[str, float]]:
    """Read a result file: (names, data, parameters); ``time`` is the first name."""
    kind = result_format(path)
    if kind == ".csv":
        names, data = csvio.read_csv(path)
        return names, data, {}
    if kind == ".parquet":
        try:
            import pyarrow.parquet as pq
        except ImportError:
            raise ImportError("reading Parquet needs pyarrow: pip install stiction[parquet]") from None
        table = pq.read_table(os.fspath(path))
        names = list(table.column_names)
        data = np.column_stack([table.column(n).to_numpy() for n in names]) if names else np.empty((0, 0))
        return names, np.asarray(data, dtype=np.float64), {}
    return _read_mat(Path(path))


# --- MATLAB v4 ------------------------------------------------------------------------------
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


def _read_mat(path: Path) -> tuple[list[str], np.ndarray, dict[str, float]]:
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
