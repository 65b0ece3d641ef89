"""``stiction dyno``: run a dynamometer schedule on a brake model and write its report."""

from __future__ import annotations

from pathlib import Path

import click

from stiction.cli.options import FILE, friendly_errors, load_model


@click.command("dyno")
@click.argument("model_file", type=FILE)
@click.argument("schedule_file", type=FILE)
@click.option(
    "-o",
    "--output",
    "output",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("dyno-report"),
    show_default=True,
    help="Folder for stops.parquet, stops.csv, samples.parquet and dyno.png (and worn_out.txt when the pad wore out).",
)
@click.option("--no-plots", is_flag=True, help="Write the tables only.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
@friendly_errors
def dyno_cmd(model_file: Path, schedule_file: Path, output: Path, no_plots: bool, quiet: bool) -> None:
    """Run SCHEDULE_FILE (a dyno schedule, TOML) on the brake in MODEL_FILE (.toml or .mo)
    and write the per-stop report into the output folder."""
    from stiction.dynamometer import dyno, load_schedule

    report = dyno(load_model(model_file), load_schedule(schedule_file), progress=not quiet)
    files = report.write(output, plots=not no_plots)
    timing = report.timing
    click.echo(
        f"{len(report)} stops: {timing['stops']:.2f} s in stops, {timing['cooling']:.2f} s cooling; "
        f"wrote {', '.join(str(f) for f in files)}"
    )
    if report.worn_out or len(report.missed):  # a result, not a failure: the stops done are written
        click.echo(f"{'stopped early' if report.worn_out else 'note'}: {report.summary()}", err=True)
