"""``stiction check``: validate a model file without running it."""

from __future__ import annotations

from pathlib import Path

import click

from stiction.cli.options import FILE, friendly_errors, in_file, load_model
from stiction.errors import ModelError


@click.command()
@click.argument("model_file", type=FILE)
@click.option("-v", "--verbose", is_flag=True, help="Also show the experiment and every start value.")
@friendly_errors
def check(model_file: Path, verbose: bool) -> None:
    """Validate MODEL_FILE (.toml or .mo) without running it."""
    model = load_model(model_file)
    try:
        model.check()
        info = model.run_info() if verbose else None
    except ModelError as exc:
        raise in_file(model_file, exc) from None
    click.echo(f"ok: {model.name} ({len(model.components)} components, {len(model.connections)} connections)")
    if info is not None:
        click.echo(f"experiment: {info.experiment}")
        click.echo(f"start values: {info.initialization.counts()}")
        click.echo(str(info.initialization))
