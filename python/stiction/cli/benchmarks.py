"""Timing of whole runs as a user sees them (``Model.simulate``, TOML included).

A run returns its ``Result`` once the states are recorded; algebraic variables (torques,
accelerations, …) are computed on first access. ``table_ms`` times that extra step
(``Result.data``, every variable of every row), so both numbers are on the table.
``recording_ms`` times a run that records every variable as it goes
(``Model.simulate(record="all")``, then ``Result.data``).
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from typing import Any

from stiction.model.model import Model

__all__ = [
    "BenchRow",
    "ScaleRow",
    "SolverRow",
    "SweepBench",
    "bench",
    "bench_scale",
    "bench_solvers",
    "bench_sweep",
    "timed_ms",
]


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
    core_median_ms: float = float("nan")
    core_min_ms: float = float("nan")
    recording_ms: float = float("nan")

    @property
    def after_ratio(self) -> float:
        """Every variable computed after the run against the run that records the states
        (medians): ``Model.simulate`` and then ``Result.data``, over ``Model.simulate``."""
        return (self.median_ms + self.table_ms) / self.median_ms

    @property
    def all_variables_ratio(self) -> float:
        """A run that records every variable against one that records the states (medians):
        ``Model.simulate(record="all")`` and then ``Result.data``, over ``Model.simulate``."""
        return self.recording_ms / self.median_ms

    @property
    def python_ms(self) -> float:
        """What the Python path adds to the core's run (medians): ``Model.simulate`` against
        the core's own ``wall_ms``, which it measures around building and running."""
        return self.median_ms - self.core_median_ms


def bench(model: Model, repeat: int = 50, warmup: int = 3) -> BenchRow:
    """Run ``model`` ``warmup`` times untimed, then ``repeat`` times timed."""
    if repeat < 1:
        raise ValueError(f"repeat must be at least 1, got {repeat}")
    for _ in range(warmup):
        model.simulate()
    times = []
    table_times = []
    core_times = []
    recording_times = []
    result = None
    for _ in range(repeat):
        start = time.perf_counter()
        result = model.simulate()
        times.append((time.perf_counter() - start) * 1e3)
        core_times.append(float(result.stats["wall_ms"]))
        start = time.perf_counter()
        _ = result.data
        table_times.append((time.perf_counter() - start) * 1e3)
    # in a loop of its own: interleaved with the runs above, the allocator handed the next
    # run's states fresh pages (HeatLosses' run 4.3 -> 5.3 ms, 640 more page faults)
    for _ in range(warmup):
        _ = model.simulate(record="all").data
    for _ in range(repeat):
        start = time.perf_counter()
        result = model.simulate(record="all")
        _ = result.data
        recording_times.append((time.perf_counter() - start) * 1e3)
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
        core_median_ms=statistics.median(core_times),
        core_min_ms=min(core_times),
        recording_ms=statistics.median(recording_times),
    )


@dataclass(frozen=True)
class SweepBench:
    """Wall-clock time of one sweep, the core's own time for its runs, and a single run."""

    variants: int
    workers: int
    seconds: float
    single_run_ms: float
    core_seconds: float
    where: str = "local"

    @property
    def per_variant_ms(self) -> float:
        """Wall time per variant (all workers together)."""
        return 1e3 * self.seconds / self.variants

    @property
    def overhead(self) -> float:
        """Time outside the core's runs as a fraction of them: wall × workers against the sum
        of each variant's ``wall_s`` (measured in the core around building and running it)."""
        return (self.seconds * self.workers - self.core_seconds) / self.core_seconds

    @property
    def overhead_us(self) -> float:
        """Time outside the core's runs per variant, in microseconds of one worker."""
        return 1e6 * (self.seconds * self.workers - self.core_seconds) / self.variants


def bench_sweep(model: Model, variants: int, workers: int | None, client: Any = None) -> SweepBench:
    """Sweep ``variants`` Monte Carlo variants of ``model`` (clutch/brake ``fn_max`` of the
    first friction element found, ±50 %) with two metrics and no trajectories.

    With ``client`` (a ``distributed.Client``) the sweep runs on its cluster, ``workers``
    being its total threads; one small sweep first (untimed) lets the workers import
    stiction, as the local warm-up does. Starting the cluster is not timed."""
    import os

    from stiction.sweeps.runner import sample, sweep

    compiled = model.compile()
    table = sample(variants, seed=1, dists=_fn_max_range(model) or {"StopTime": (0.9, 1.0)})
    metrics = [f"max({compiled.simulate().names[1]})", "events()"]
    single = min(timed_ms(lambda: compiled.simulate()) for _ in range(20))
    options: dict[str, Any] = {"workers": workers, "client": client, "progress": False}
    sweep(compiled, table.iloc[: min(64, variants)], metrics, **options)  # warm up
    start = time.perf_counter()
    result = sweep(compiled, table, metrics, **options)
    seconds = time.perf_counter() - start
    threads = workers or os.cpu_count() or 1
    if client is not None:
        threads = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
    return SweepBench(
        variants,
        threads,
        seconds,
        single,
        float(result.table["wall_s"].sum()),
        "dask" if client is not None else "local",
    )


def _fn_max_range(model: Model) -> dict[str, tuple[float, float]]:
    """``fn_max`` of the first friction element, ±50 % (empty when there is none)."""
    for name, component in model.components.items():
        if "fn_max" in component.params:
            value = float(component.params["fn_max"])
            return {f"{name}.fn_max": (0.5 * value, 1.5 * value)}
    return {}


def timed_ms(run: Any) -> float:
    """The wall time of one call of ``run``, in milliseconds."""
    start = time.perf_counter()
    run()
    return (time.perf_counter() - start) * 1e3


@dataclass(frozen=True)
class ScaleRow:
    """One generated model of the scaling table: load + simulate, and the run's counts."""

    kind: str
    elements: int
    ms: float
    steps: int
    rhs_evals: int
    events: int

    @property
    def us_per_step_element(self) -> float:
        """Microseconds per integrator step per element: flat when cost is linear in size."""
        return 1e3 * self.ms / max(self.steps * self.elements, 1)

    @property
    def ms_per_event(self) -> float:
        return self.ms / max(self.events, 1)


def bench_scale(kind: str, n: int) -> ScaleRow:
    """Time one generated ``chain``, ``ladder`` or ``ladder-waves`` (its clutches engaging in
    10 groups, so that its steps do not grow with ``n``) of ``n`` elements (``stiction.testing``)."""
    from stiction.testing import chain_toml, ladder_toml

    texts = {"chain": chain_toml, "ladder": ladder_toml, "ladder-waves": lambda n: ladder_toml(n, waves=10)}
    if kind not in texts:
        raise ValueError(f"unknown generated model {kind!r}: expected one of {sorted(texts)}")
    text = texts[kind](n)
    start = time.perf_counter()
    result = Model.loads(text).simulate()
    ms = (time.perf_counter() - start) * 1e3
    stats = result.stats
    return ScaleRow(
        kind=kind,
        elements=n,
        ms=ms,
        steps=int(stats.get("steps", 0)),
        rhs_evals=int(stats.get("rhs_evals", 0)),
        events=int(stats.get("events", len(result.events))),
    )


@dataclass(frozen=True)
class SolverRow:
    """One model under one ``Solver``: the fastest run and the last run's counts."""

    model: str
    solver: str
    min_ms: float
    steps: int
    rejected: int
    rhs_evals: int
    lu_setups: int
    jacobians: int
    switches: int


def bench_solvers(model: Model, solvers: list[str], repeat: int = 5) -> list[SolverRow]:
    """Run ``model`` under each of ``solvers``: once, then ``repeat`` more times if that took
    less than half a second; the fastest run counts.

    ``lu_setups`` counts the implicit methods' Newton-matrix factorizations, ``jacobians``
    the Jacobians they built (forward differences of the right-hand side, in the current
    mode); ``rhs_evals`` includes those differences and the "auto" stiffness checks."""
    rows = []
    for solver in solvers:
        start = time.perf_counter()
        result = model.simulate(Solver=solver)
        times = [(time.perf_counter() - start) * 1e3]
        # a run of seconds (an explicit method on a stiff model) is timed once
        for _ in range(repeat if times[0] < 500 else 0):
            start = time.perf_counter()
            result = model.simulate(Solver=solver)
            times.append((time.perf_counter() - start) * 1e3)
        s = result.stats
        rows.append(
            SolverRow(
                model=model.name,
                solver=solver,
                min_ms=min(times),
                steps=int(s.get("steps", 0)),
                rejected=int(s.get("rejected_steps", 0)),
                rhs_evals=int(s.get("rhs_evals", 0)),
                lu_setups=int(s.get("lu_setups", 0)),
                jacobians=int(s.get("jacobian_evals", 0)),
                switches=int(s.get("solver_switches", 0)),
            )
        )
    return rows
