"""``stiction import``, ``export`` and ``fmu``: a model from one form into another (TOML, ``.mo``, FMU)."""

from __future__ import annotations

from pathlib import Path

import click

from stiction.cli.options import FILE, friendly_errors, load_model, model_option, output_option


@click.command(name="import")
@click.argument("mo_file", type=FILE)
@output_option("The TOML model file to write.")
@model_option
@friendly_errors
def import_cmd(mo_file: Path, output: Path, model_name: str | None) -> None:
    """Convert a Modelica model (MO_FILE) into a TOML model file."""
    from stiction.model.model import Model

    model = Model.from_modelica(mo_file, model_name)
    model.save(output)
    click.echo(f"wrote {output} ({len(model.components)} components, {len(model.connections)} connections)")


@click.command(name="export")
@click.argument("model_file", type=FILE)
@output_option("The Modelica file to write (Model.mo).")
@friendly_errors
def export_cmd(model_file: Path, output: Path) -> None:
    """Write MODEL_FILE as a Modelica model with fully qualified MSL classes."""
    model = load_model(model_file)
    model.to_modelica(output)
    click.echo(f"wrote {output}")


@click.command()
@click.argument("model_file", type=FILE)
@output_option("The FMU to write (Name.fmu).")
@click.option("--fmi", "fmi_version", type=click.Choice(["2", "3"]), default="2", help="FMI version.")
@click.option(
    "--outputs",
    default=None,
    help="Variables the FMU outputs, comma-separated (J1.w,brake.mode). Default: the states.",
)
@model_option
@friendly_errors
def fmu(
    model_file: Path, output: Path, fmi_version: str, outputs: str | None, model_name: str | None
) -> None:
    """Write MODEL_FILE (.toml or .mo) as an FMI Co-Simulation FMU."""
    model = load_model(model_file, model_name)
    chosen = [s.strip() for s in outputs.split(",") if s.strip()] if outputs else None
    model.to_fmu(output, fmi_version=int(fmi_version), outputs=chosen)
    click.echo(f"wrote {output}")
