#!/usr/bin/env python3
"""Memory of a metrics-only sweep (issue 9): peak RSS of fresh processes sweeping 1 000,
10 000 and 50 000 variants of CoupledClutches with two metrics. Prints numbers, asserts
nothing; the growth should be the table's (and the variants') size, not the runs'.

Run: .venv/bin/python scripts/bench_sweep_memory.py
"""

from __future__ import annotations

import subprocess
import sys

CHILD = """
import resource, sys
import stiction as st
n = int(sys.argv[1])
model = st.Model.load("examples/msl/CoupledClutches.toml")
variants = st.sample(n, seed=1, dists={"clutch1.fn_max": (10.0, 30.0)})
result = st.sweep(model, variants, ["max(J1.w)", "events()"], progress=False)
table = result.table.memory_usage(deep=True).sum() / 1e6
print(f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.1f} {table:.2f}")
"""


def main() -> None:
    print(f"{'variants':>9} {'peak RSS MB':>12} {'table MB':>9} {'growth MB':>10}")
    first = None
    for n in (1_000, 10_000, 50_000):
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(n)], check=True, capture_output=True, text=True
        )
        rss, table = (float(v) for v in out.stdout.split())
        first = first if first is not None else rss
        print(f"{n:>9} {rss:>12.1f} {table:>9.2f} {rss - first:>10.1f}")


if __name__ == "__main__":
    main()
