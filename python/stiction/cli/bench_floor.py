"""The figures of issue 34 ("the floor", as users call it) and what ``stiction bench`` saves
and compares: every figure a run of ``bench`` prints is a named number (``--json OUT`` writes
them), and ``--compare REF.json`` prints each against the same figure of an earlier run, with
a marker where it is worse beyond the noise, so that a regression shows in one command.

The floor: an override of the experiment against a plain ``Model.simulate()`` (alternating,
so both see the same load), one algebraic variable read alone against the run, and the
ladder of ``stiction.testing.ladder_toml`` loaded from a file and run through
``Model.load(...).simulate()``, with the share of that time outside the core's run and, of
that, the share spent in Python: the engine's own parse and compile of the file
(``_core.load_model``, timed alone alternately) is not Python's, a Rust caller
pays it too.
"""

from __future__ import annotations

import json
import math
import os
import statistics
import tempfile
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from stiction.cli.benchmarks import timed_ms

__all__ = ["Comparison", "compare_figures", "floor_figures", "read_figures", "write_figures"]

FORMAT = "stiction-bench/1"
# A figure worse than its reference by more than this fraction is marked: run-to-run noise on
# a shared machine is 5-10 %.
NOISE = 0.10


def _alternating(repeat: int, *calls: Callable[[], Any]) -> list[list[float]]:
    """Each call timed ``repeat`` times, in turn, so that every one sees the same load."""
    times: list[list[float]] = [[] for _ in calls]
    for _ in range(repeat):
        for k, call in enumerate(calls):
            times[k].append(timed_ms(call))
    return times


def overrides_figures(model: Any, repeat: int) -> dict[str, float]:
    """``Model.simulate()`` against the same run with its experiment given as overrides
    (equal to the model's, and another StopTime), medians of alternating runs."""
    exp = {k: model.experiment[k] for k in ("StopTime", "Interval", "Tolerance") if k in model.experiment}
    other = {**exp, "StopTime": 0.95 * float(exp.get("StopTime", 1.0))}
    calls = (model.simulate, lambda: model.simulate(**exp), lambda: model.simulate(**other))
    for call in calls:
        call()  # warm-up: the compiled model and its variants
    plain, same, changed = map(statistics.median, _alternating(repeat, *calls))
    return {
        "overrides.plain_ms": plain,
        "overrides.same_ms": same,
        "overrides.same_ratio": same / plain,
        "overrides.other_stoptime_ms": changed,
    }


def column_figures(model: Any, name: str, repeat: int) -> dict[str, float]:
    """A run against reading one variable ``name`` of a fresh result (medians)."""
    runs, reads = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        result = model.simulate()
        runs.append((time.perf_counter() - start) * 1e3)
        reads.append(timed_ms(lambda r=result: r[name]))
    run, read = statistics.median(runs), statistics.median(reads)
    return {"column.run_ms": run, f"column.{name}_ms": read, f"column.{name}_ratio": read / run}


def ladder_figures(n: int, repeat: int, column: str | None = None) -> dict[str, float]:
    """The ladder of ``n`` inertias from a model file: load, simulate, the engine's parse and
    compile of the file alone, the core's run, the share outside the run and Python's share
    (medians), and reading ``column`` alone once."""
    from stiction import _core
    from stiction.model.model import Model
    from stiction.testing import ladder_toml

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"ladder{n}.toml"
        text = ladder_toml(n)
        path.write_text(text, encoding="utf-8")
        loads, sims, cores, engine_loads, reads = [], [], [], [], []
        for _ in range(repeat):
            start = time.perf_counter()
            model = Model.load(path)
            loaded = time.perf_counter()
            result = model.simulate()
            done = time.perf_counter()
            loads.append((loaded - start) * 1e3)
            sims.append((done - loaded) * 1e3)
            cores.append(float(result.stats["wall_ms"]))
            engine_loads.append(timed_ms(lambda: _core.load_model(text, tmp, path.stem)))
            if column is not None:
                reads.append(timed_ms(lambda r=result: r[column]))
    load, sim, core, engine_load = (statistics.median(x) for x in (loads, sims, cores, engine_loads))
    total = load + sim
    figures = {
        f"ladder{n}.load_ms": load,
        f"ladder{n}.engine_load_ms": engine_load,
        f"ladder{n}.simulate_ms": sim,
        f"ladder{n}.core_ms": core,
        f"ladder{n}.total_ms": total,
        f"ladder{n}.outside_run_share": (total - core) / total,
        f"ladder{n}.python_share": max(0.0, total - core - engine_load) / total,
    }
    if reads:
        figures[f"ladder{n}.{column}_ms"] = statistics.median(reads)
    return figures


def floor_figures(coupled: Any, repeat: int) -> dict[str, float]:
    """Every figure of the floor; the ladders are timed fewer times (N = 1000 runs a second)."""
    figures = overrides_figures(coupled, repeat)
    figures |= column_figures(coupled, "clutch1.tau", repeat)
    figures |= ladder_figures(100, max(1, min(repeat, 10)), "system.kineticEnergy")
    figures |= ladder_figures(1000, max(1, min(repeat, 3)), "system.kineticEnergy")
    return figures


def floor_lines(figures: Mapping[str, float]) -> Iterable[str]:
    """The floor's figures as lines of text, one each."""
    for name, value in figures.items():
        unit = "" if name.endswith("_ms") else ("%" if name.endswith("_share") else "×")
        shown = 100 * value if unit == "%" else value
        yield f"{name:<44} {shown:>10.3f} {unit}".rstrip()


def write_figures(path: str | os.PathLike[str], figures: Mapping[str, float]) -> None:
    """Save ``figures`` (name → number) as JSON, with the time and machine they were taken on."""
    doc = {
        "format": FORMAT,
        "taken": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "cpus": os.cpu_count(),
        "figures": {k: float(v) for k, v in figures.items()},
    }
    Path(path).write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n", encoding="utf-8")


def read_figures(path: str | os.PathLike[str]) -> dict[str, float]:
    """The figures of a file ``write_figures`` wrote; ``ValueError`` for any other file."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not a bench file ({e})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT or not isinstance(doc.get("figures"), dict):
        raise ValueError(f"{path}: not a bench file (expected format {FORMAT!r})")
    return {str(k): float(v) for k, v in doc["figures"].items()}


@dataclass(frozen=True)
class Comparison:
    """One figure now against the same figure of a saved run."""

    name: str
    now: float
    ref: float | None

    @property
    def ratio(self) -> float:
        """Now over then (NaN when the saved run has no such figure)."""
        if self.ref is None or self.ref == 0:
            return math.nan
        return self.now / self.ref

    def worse(self, noise: float = NOISE) -> bool:
        """Worse than the saved run beyond ``noise`` (a fraction): every figure is a time, a
        share or a ratio, where less is better."""
        if math.isnan(self.ratio):
            return False
        return self.ratio > 1 + noise

    def line(self, noise: float = NOISE) -> str:
        ref = "—" if self.ref is None else f"{self.ref:.4g}"
        ratio = "new" if math.isnan(self.ratio) else f"{self.ratio:.2f}×"
        mark = "  WORSE" if self.worse(noise) else ""
        return f"{self.name:<44} {self.now:>10.4g} {ref:>10} {ratio:>7}{mark}"


def compare_figures(now: Mapping[str, float], ref: Mapping[str, float]) -> list[Comparison]:
    """Each figure of ``now`` against ``ref``'s (None where ``ref`` lacks it)."""
    return [Comparison(name, value, ref.get(name)) for name, value in now.items()]
