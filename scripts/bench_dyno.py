"""Time the J2522-like dynamometer schedule end to end (issue 32's target: ≤ 5 s on 2 cores).

Runs examples/dyno/j2522_like.toml on examples/dyno/disc_brake.toml, writes the report (Parquet,
CSV and the plots) into a temporary folder and prints the wall-clock split: reading, stops,
cooling, report tables, plots. ``--repeat N`` runs it N times and prints the min and median.

    .venv/bin/python scripts/bench_dyno.py [--repeat 3] [--no-plots]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import stiction as st
from stiction.dynamometer import dyno, load_schedule

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
    started = time.perf_counter()
    runs = [once(not args.no_plots) for _ in range(args.repeat)]
    print(f"J2522-like schedule, {runs[0]['stops']:.0f} stops ({args.repeat} run(s), first includes imports)")
    for key in ("read", "run", "in stops", "cooling", "tables", "plots", "total"):
        values = [r[key] for r in runs]
        print(f"  {key:9s} min {min(values):7.3f} s   median {statistics.median(values):7.3f} s")
    print(f"  process   {time.perf_counter() - started:.3f} s for all runs")


if __name__ == "__main__":
    main()
