"""``stiction compare``: the MSL regression check of a result against a reference."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from stiction.cli.options import FILE, friendly_errors


@click.command(name="compare")
@click.argument("result_csv", type=FILE)
@click.argument("reference_csv", type=FILE)
@click.option(
    "--tolerance",
    type=float,
    default=2e-3,
    show_default=True,
    help="Relative tube size, in y (of the signal range) and in t (of the time span).",
)
@click.option(
    "--floor",
    type=float,
    default=1e-9,  # comparison.DEFAULT_FLOOR, spelled here so the command loads without NumPy
    show_default=True,
    help="Smallest tube half-height, so exact zeros compare equal to round-off (0: MSL's method).",
)
@click.option(
    "--signals",
    default=None,
    help="Signals to compare: a,b,c or @FILE (one per line). Default: REFERENCE.signals.txt "
    "next to the reference if it exists, else every reference column.",
)
@click.option("-v", "--verbose", is_flag=True, help="Print every signal, not only the failures.")
@friendly_errors
def compare_cmd(
    result_csv: Path, reference_csv: Path, tolerance: float, floor: float, signals: str | None, verbose: bool
) -> None:
    """Check RESULT_CSV against REFERENCE_CSV (MSL tube method); exit 1 on failure.

    Either file may be a CSV, a Dymola/OpenModelica .mat result or a Parquet table."""
    from stiction.results.comparison import compare, parse_signals

    sibling = reference_csv.with_suffix(".signals.txt")
    if signals is None and sibling.is_file():
        signals = f"@{sibling}"
    names = parse_signals(signals) if signals else None
    report = compare(result_csv, reference_csv, tolerance=tolerance, signals=names, floor=floor)
    click.echo(report.summary(verbose))
    if signals and signals.startswith("@"):
        click.echo(f"signals from {signals[1:]}")
    if not report.passed:
        sys.exit(1)
