"""Timing of whole runs as a user sees them (``Model.simulate``, TOML included).

A run returns its ``Result`` once the states are recorded; algebraic variables (torques,
accelerations, …) are computed on first access. ``table_ms`` times that extra step
(``Result.data``, every variable of every row), so both numbers are on the table.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass

from .model import Model

__all__ = ["BenchRow", "bench"]


@dataclass(frozen=True)
class BenchRow:
    """Wall-clock times of one model over repeated runs, and the last run's counts."""

    model: str
    median_ms: float
    min_ms: float
    table_ms: float
    steps: int
    rhs_evals: int
    events: int


def bench(model: Model, repeat: int = 50, warmup: int = 3) -> BenchRow:
    """Run ``model`` ``warmup`` times untimed, then ``repeat`` times timed."""
    if repeat < 1:
        raise ValueError(f"repeat must be at least 1, got {repeat}")
    for _ in range(warmup):
        model.simulate()
    times = []
    table_times = []
    result = None
    for _ in range(repeat):
        start = time.perf_counter()
        result = model.simulate()
        times.append((time.perf_counter() - start) * 1e3)
        start = time.perf_counter()
        _ = result.data
        table_times.append((time.perf_counter() - start) * 1e3)
    assert result is not None
    stats = result.stats
    return BenchRow(
        model=model.name,
        median_ms=statistics.median(times),
        min_ms=min(times),
        table_ms=statistics.median(table_times),
        steps=int(stats.get("steps", 0)),
        rhs_evals=int(stats.get("rhs_evals", 0)),
        events=int(stats.get("events", len(result.events))),
    )
