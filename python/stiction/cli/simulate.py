"""``stiction simulate``: run a model file and write, plot and summarize the result."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import click

from stiction.cli.options import (
    FILE,
    experiment_options,
    friendly_errors,
    in_file,
    load_model,
    model_option,
    output_option,
)
from stiction.errors import EnergyWarning, ModelError


@click.command()
@click.argument("model_file", type=FILE)
@output_option("Write the result: .csv (MSL style), .mat (Dymola/OpenModelica) or .parquet.", required=False)
@click.option(
    "--outputs",
    default=None,
    help="Signals to write: names or globs, comma-separated (J1.w,clutch*.mode). Default: all.",
)
@click.option(
    "--plot",
    "plot_file",
    type=FILE,
    help="Save a plot (PNG).",
)
@click.option(
    "--signals",
    default=None,
    help="Signals to plot: a,b,c or @FILE (one per line), one axes each; a+b shares axes.",
)
@model_option
@experiment_options
@friendly_errors
def simulate(
    model_file: Path,
    output: Path | None,
    outputs: str | None,
    plot_file: Path | None,
    signals: str | None,
    model_name: str | None,
    **experiment: Any,
) -> None:
    """Run MODEL_FILE (.toml or Modelica .mo) and print a summary."""
    from stiction.results.io.formats import result_format

    if output is not None:
        result_format(output)  # refuse an unknown format before running
    model = load_model(model_file, model_name)
    # a file of every variable: computed while the run goes on
    record = "all" if output is not None and not outputs else "states"
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", EnergyWarning)
            result = model.simulate(record=record, **experiment)
    except ModelError as exc:
        raise in_file(model_file, exc) from None
    for w in caught:  # a run whose energy balance does not close: one line each, on stderr
        if issubclass(w.category, EnergyWarning):
            click.echo(f"warning: {w.message}", err=True)
        else:
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    if output is not None:
        chosen = [n.strip() for n in outputs.split(",") if n.strip()] if outputs else None
        result.save(output, chosen)
    if plot_file is not None:
        from stiction.results.comparison import parse_signals

        groups = [[n.strip() for n in g.split("+") if n.strip()] for g in parse_signals(signals or "")]
        result.plot(*groups, path=plot_file)
    click.echo(result.summary())
    if output is not None:
        click.echo(f"wrote {output}")
    if plot_file is not None:
        click.echo(f"wrote {plot_file}")
