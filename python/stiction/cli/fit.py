"""``stiction fit``: estimate parameters of a model file from measured data.

``stiction fit model.toml data.csv --param brake.peak=1:2 --param 'brake.mu_pos[:,2]=0.1:0.8'
--output J.w=speed -o fitted.toml``: each ``--param NAME=LOW:HIGH`` (or ``LOW:START:HIGH``),
each ``--output MODEL_NAME=COLUMN`` (or a name that is also the column's), each ``--input
PORT=COLUMN``; the estimates are printed as a report, ``-o`` writes the fitted model
(``.toml``, or ``.mo``), ``--table`` the estimates as CSV.
"""

from __future__ import annotations

from pathlib import Path

import click

from stiction.cli.options import FILE, friendly_errors, in_file, load_model
from stiction.errors import ModelError


def _pairs(specs: tuple[str, ...], option: str) -> dict[str, str]:
    out = {}
    for spec in specs:
        name, sep, column = spec.partition("=")
        if not name.strip():
            raise click.BadParameter(f"'{spec}': write NAME=COLUMN", param_hint=option)
        out[name.strip()] = column.strip() if sep else name.strip()
    return out


def _bounds(specs: tuple[str, ...]) -> dict[str, tuple[float, ...]]:
    out = {}
    for spec in specs:
        name, sep, values = spec.partition("=")
        parts = values.split(":")
        if not sep or not name.strip() or len(parts) not in (2, 3):
            raise click.BadParameter(
                f"'{spec}': write NAME=LOW:HIGH or NAME=LOW:START:HIGH", param_hint="--param"
            )
        try:
            out[name.strip()] = tuple(float(p) for p in parts)
        except ValueError:
            raise click.BadParameter(f"'{spec}': bounds must be numbers", param_hint="--param") from None
    return out


@click.command("fit")
@click.argument("model_file", type=FILE)
@click.argument("data_file", type=FILE)
@click.option("--param", "params", multiple=True, required=True, help="NAME=LOW:HIGH or NAME=LOW:START:HIGH.")
@click.option(
    "--output", "outputs", multiple=True, help="MODEL_NAME=COLUMN to match (default: every column)."
)
@click.option("--input", "inputs", multiple=True, help="PORT=COLUMN: a column drives a model input.")
@click.option(
    "--method", type=click.Choice(["auto", "linear", "output-error"]), default="auto", show_default=True
)
@click.option("--loss", default="linear", show_default=True, help="linear, soft_l1, huber, cauchy or arctan.")
@click.option("--starts", default=1, show_default=True, help="Starts (a Latin hypercube beyond the first).")
@click.option("--workers", type=int, default=None, help="Threads for the model runs (default: every core).")
@click.option("-o", "--out", type=FILE, default=None, help="Write the fitted model (.toml or .mo).")
@click.option("--table", type=FILE, default=None, help="Write the estimates as CSV.")
@friendly_errors
def fit_cmd(
    model_file: Path,
    data_file: Path,
    params: tuple[str, ...],
    outputs: tuple[str, ...],
    inputs: tuple[str, ...],
    method: str,
    loss: str,
    starts: int,
    workers: int | None,
    out: Path | None,
    table: Path | None,
) -> None:
    """Estimate parameters of MODEL_FILE from DATA_FILE (CSV, .mat or Parquet with a time column)."""
    from stiction.fitting import fit

    model = load_model(model_file)
    try:
        result = fit(
            model,
            data_file,
            _bounds(params),
            outputs=_pairs(outputs, "--output") or None,
            inputs=_pairs(inputs, "--input") or None,
            method=method,
            workers=workers,
            progress=False,
            loss=loss,
            starts=starts,
        )
    except ModelError as exc:
        raise in_file(model_file, exc) from None
    click.echo(result.report())
    if out is not None:
        if out.suffix == ".mo":
            result.model.to_modelica(out)
        else:
            result.model.save(out)
        click.echo(f"wrote {out}")
    if table is not None:
        result.table.to_csv(table, index=False)
        click.echo(f"wrote {table}")
