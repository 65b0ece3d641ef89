"""Many variants of one model: ``grid`` and ``sample`` make variant tables, ``sweep`` runs
them on every core or a Dask cluster, keeping finished parts in a Parquet store."""

from stiction.sweeps.result import SweepResult
from stiction.sweeps.runner import run_batch, sweep
from stiction.sweeps.variants import grid, sample

__all__ = ["SweepResult", "grid", "run_batch", "sample", "sweep"]
