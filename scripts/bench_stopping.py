#!/usr/bin/env python3
"""A 10⁴-variant stopping-distance sweep (issue 31): the quarter car of
examples/vehicle_stop.toml braked at 100 brake clamp forces (``brake.fn_max``, 5 to 40 kN) ×
100 tyre friction coefficients (``tyre.mu_pos``, 0.2 to 1.1); at high force and low mu the
wheel locks and the car skids (a SlipWheel stick/slip event). Prints the wall time, the
variants per second and a few of the stopping distances; asserts nothing (the issue's floor:
≤ 10 s on 2 cores).

Run: .venv/bin/python scripts/bench_stopping.py [--n 100] [--workers 2]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import stiction as st

MODEL = Path(__file__).resolve().parents[1] / "examples" / "vehicle_stop.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100, help="values per axis (n² variants)")
    parser.add_argument("--workers", type=int, default=None, help="threads (default: every core)")
    args = parser.parse_args()
    model = st.Model.load(MODEL)
    # long enough for a skid at mu 0.2 from 100 km/h (about 14 s); metrics need no dense grid
    model.experiment.update(StopTime=20.0, Interval=0.05)
    forces = np.linspace(5e3, 4e4, args.n)
    mus = np.linspace(0.2, 1.1, args.n)
    variants = st.grid({"brake.fn_max": list(forces), "tyre.mu_pos": [[[0.0, float(mu)]] for mu in mus]})
    metrics = ["final(car.s)", "time_of(brake.locked)", "min(tyre.locked)"]
    kwargs = {"progress": False} | ({"workers": args.workers} if args.workers else {})
    start = time.perf_counter()
    result = st.sweep(model, variants, metrics, **kwargs)
    wall = time.perf_counter() - start
    table = result.table
    ok = (table["status"] == "ok").sum()
    skids = (table["min(tyre.locked)"] < 0.5).sum()
    print(f"{len(table)} variants ({ok} ok, {skids} with the wheel locking) in {wall:.2f} s")
    print(f"{len(table) / wall:.0f} variants/s")
    d = table["final(car.s)"]
    print(f"stopping distance: min {d.min():.2f} m, median {d.median():.2f} m, max {d.max():.2f} m")


if __name__ == "__main__":
    main()
