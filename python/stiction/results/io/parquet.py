"""Results as Parquet, one float64 column per signal, through pyarrow (an optional dependency:
``pip install stiction[parquet]``)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

import numpy as np

from stiction import _deps

__all__ = ["read_parquet", "write_parquet"]


def write_parquet(
    path: str | os.PathLike[str],
    names: Sequence[str],
    data: np.ndarray,
    parameters: Mapping[str, float] | None = None,
) -> None:
    """A Parquet table, one float64 column per name (pyarrow); parameters are not stored."""
    pa, pq = _deps.pyarrow, _deps.parquet
    columns = np.ascontiguousarray(np.asarray(data, dtype=np.float64).T)  # one contiguous row per signal
    rows = columns.shape[1]
    # Arrays made from the buffers directly: pa.array() would import pandas (0.7 s) to sniff types.
    arrays = [pa.Array.from_buffers(pa.float64(), rows, [None, pa.py_buffer(c)]) for c in columns]
    table = pa.Table.from_arrays(arrays, names=list(names))
    # Dictionary encoding and statistics cost more than the whole write for thousands of
    # float columns and buy nothing for trajectories; snappy compression stays.
    pq.write_table(table, os.fspath(path), use_dictionary=False, write_statistics=False)


def read_parquet(path: str | os.PathLike[str]) -> tuple[list[str], np.ndarray]:
    """(names, data) of a Parquet result."""
    table = _deps.parquet.read_table(os.fspath(path))
    names = list(table.column_names)
    data = np.column_stack([table.column(n).to_numpy() for n in names]) if names else np.empty((0, 0))
    return names, np.asarray(data, dtype=np.float64)
