"""Scaling benchmark (issue 10): prints numbers, asserts nothing.

1. A chain of N clutches engaging one after another (0.05 s apart): load + simulate in-process.
2. The ladder (clutches and spring-dampers alternating, brakes on every fourth inertia).
3. ``Model.check`` of a 750-clutch chain (about 2250 components).

Run: .venv/bin/python scripts/bench_scaling.py [--quick]
"""

from __future__ import annotations

import sys
import time

import stiction as st
from stiction.testing import chain_toml, ladder_toml


def run(text: str) -> tuple[float, int, int]:
    t0 = time.perf_counter()
    res = st.Model.loads(text).simulate()
    return time.perf_counter() - t0, len(res.time), len(res.events)


def main() -> None:
    quick = "--quick" in sys.argv
    chain_sizes = [20, 40, 80, 160] if quick else [20, 40, 80, 160, 320]
    print(f"{'model':>12} {'N':>6} {'time [ms]':>11} {'rows':>7} {'events':>7}")
    for n in chain_sizes:
        dt, rows, events = run(chain_toml(n))
        print(f"{'chain':>12} {n:>6} {dt * 1e3:>11.1f} {rows:>7} {events:>7}")
    for n in [25, 50, 100, 200] if quick else [25, 50, 100, 200, 400]:
        dt, rows, events = run(ladder_toml(n))
        print(f"{'ladder':>12} {n:>6} {dt * 1e3:>11.1f} {rows:>7} {events:>7}")
    model = st.Model.loads(chain_toml(750))
    t0 = time.perf_counter()
    model.check()
    print(
        f"check of a 750-clutch chain ({len(model.components)} components): {(time.perf_counter() - t0) * 1e3:.0f} ms"
    )


if __name__ == "__main__":
    main()
