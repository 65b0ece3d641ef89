#!/usr/bin/env python3
"""Memory of a metrics-only sweep (issue 9): peak RSS of fresh processes sweeping 10³ to
10⁵ variants of CoupledClutches with two metrics. Prints numbers, asserts nothing; beyond
the table, the peak should not grow with the number of variants: the last column (bytes
per variant beyond the table, from the smallest sweep to each) should be near zero.

Run: .venv/bin/python scripts/bench_sweep_memory.py [--stop-time 0.2] [--sizes 1000,10000,100000]
(a shorter StopTime makes the runs cheaper; what a metrics-only sweep keeps does not depend on it)
"""

from __future__ import annotations

import argparse
import subprocess
import sys

CHILD = """
import resource, sys
import stiction as st
n, stop = int(sys.argv[1]), sys.argv[2]
model = st.Model.load("examples/msl/CoupledClutches.toml")
if stop:
    model.experiment["StopTime"] = float(stop)
variants = st.sample(n, seed=1, dists={"clutch1.fn_max": (10.0, 30.0)})
result = st.sweep(model, variants, ["max(J1.w)", "events()"], progress=False)
table = result.table.memory_usage(deep=True).sum() / 1e6
print(f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.1f} {table:.3f}")
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--stop-time", default="", help="StopTime of the runs (default: the MSL experiment's)"
    )
    parser.add_argument("--sizes", default="1000,10000,100000", help="numbers of variants")
    args = parser.parse_args()
    print(
        f"{'variants':>9} {'peak RSS MB':>12} {'table MB':>9} {'growth MB':>10} {'beyond table B/variant':>23}"
    )
    first = None
    for n in (int(s) for s in args.sizes.split(",")):
        out = subprocess.run(
            [sys.executable, "-c", CHILD, str(n), args.stop_time], check=True, capture_output=True, text=True
        )
        rss, table = (float(v) for v in out.stdout.split())
        first = first or (n, rss, table)
        growth = rss - first[1]
        beyond = 1e6 * (growth - (table - first[2])) / (n - first[0]) if n > first[0] else 0.0
        print(f"{n:>9} {rss:>12.1f} {table:>9.3f} {growth:>10.1f} {beyond:>23.0f}")


if __name__ == "__main__":
    main()
