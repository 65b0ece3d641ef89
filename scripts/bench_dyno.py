"""Time the J2522-like dynamometer schedule end to end (issue 32's target: ≤ 5 s on 2 cores).

Runs examples/dyno/j2522_like.toml on examples/dyno/disc_brake.toml (fade, Arrhenius wear,
speed-dependent convection and radiation), writes the report (Parquet, CSV and the plots) into a
temporary folder and prints the wall-clock split: importing stiction, reading, stops, cooling,
report tables, plots. ``--repeat N`` runs it N times and prints the first (cold: pandas, Arrow
and matplotlib imported on first use, the font cache read) and the min and median of the rest;
``process`` is the whole script from its first line, the end-to-end number.

    .venv/bin/python scripts/bench_dyno.py [--repeat 3] [--no-plots]
"""

from __future__ import annotations

import time

STARTED = time.perf_counter()

import argparse  # after the clock: the imports are part of the end to end
import statistics
import tempfile
from pathlib import Path

import stiction as st
from stiction.dynamometer import dyno, load_schedule

IMPORTED = time.perf_counter()

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "dyno"


def once(plots: bool) -> dict[str, float]:
    """One end-to-end run; the seconds each part took."""
    started = time.perf_counter()
    model = st.Model.load(EXAMPLES / "disc_brake.toml")
    schedule = load_schedule(EXAMPLES / "j2522_like.toml")
    read = time.perf_counter()
    report = dyno(model, schedule, progress=False)
    ran = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        report.write(folder, plots=False)
        tables = time.perf_counter()
        if plots:
            report.plot(Path(folder) / "dyno.png")
        done = time.perf_counter()
    return {
        "stops": len(report),
        "read": read - started,
        "run": ran - read,
        "in stops": report.timing["stops"],
        "cooling": report.timing["cooling"],
        "tables": tables - ran,
        "plots": done - tables,
        "total": done - started,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--no-plots", action="store_true")
    args = parser.parse_args()
    runs = [once(not args.no_plots) for _ in range(args.repeat)]
    print(f"J2522-like schedule, {runs[0]['stops']:.0f} stops ({args.repeat} run(s))")
    print(f"  import stiction {IMPORTED - STARTED:7.3f} s")
    warm = runs[1:]
    for key in ("read", "run", "in stops", "cooling", "tables", "plots", "total"):
        line = f"  {key:9s} first {runs[0][key]:7.3f} s"
        if warm:
            values = [r[key] for r in warm]
            line += f"   then min {min(values):7.3f} s   median {statistics.median(values):7.3f} s"
        print(line)
    print(f"  process   {time.perf_counter() - STARTED:.3f} s, imports and all {args.repeat} run(s)")


if __name__ == "__main__":
    main()
