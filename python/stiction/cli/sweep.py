"""``stiction sweep``: vary parameters of a model file, compute metrics, write a table.

``--vary clutch1.fn_max=10:30:21`` (start:stop:count) or ``--vary sin1.f=0.1,0.2,0.4``
give a full grid; with ``--samples N`` a range ``a:b`` is sampled (Latin hypercube) and a
list is drawn from. A value may carry a unit, converted to the parameter's
(``--vary "J1.w=100 rpm:300 rpm:3"``, ``--vary "brake.fn_max=10 kN,20 kN"``). A table
parameter takes tables separated by ``;``, each a TOML array whose cells may be numbers,
quantities or expressions over top-level parameters as text
(``--vary 'brake.mu_pos=[[0,0.4],[100,0.35]];[[0,"mu0"],[100,"0.9*mu0"]]'``). The table goes
to ``-o sweep.parquet`` or ``sweep.csv``.
"""

from __future__ import annotations

import sys
import time
import tomllib
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from stiction.cli.options import FILE, fail, friendly_errors, in_file
from stiction.errors import ModelError

if TYPE_CHECKING:
    from stiction.model.model import Model

_SYNTAX = "NAME=START:STOP:COUNT, NAME=V1,V2,… or NAME=TABLE;TABLE;…"


class _Vary:
    """One ``--vary``, split but not yet converted: values need the model's units."""

    def __init__(self, spec: str, sampled: bool) -> None:
        name, sep, values = spec.partition("=")
        if not sep or not name or not values.strip():
            raise click.BadParameter(f"'{spec}': write {_SYNTAX}", param_hint="--vary")
        self.name, self.spec, self.sampled = name.strip(), spec, sampled
        self.tables: list[Any] | None = None
        self.bounds: list[str] = []
        self.count = 0
        self.items: list[str] = []
        values = values.strip()
        if values.startswith("["):
            self.tables = [self._table(t) for t in values.split(";") if t.strip()]
        elif ":" in values:
            parts = values.split(":")
            if sampled and len(parts) == 2:
                self.bounds = parts
            elif len(parts) != 3:
                raise click.BadParameter(f"'{spec}': a range is START:STOP:COUNT", param_hint="--vary")
            else:
                self.bounds, self.count = parts[:2], int(_number(parts[2], "--vary"))
                if self.count < 1:
                    raise click.BadParameter(f"'{spec}': COUNT must be at least 1", param_hint="--vary")
        else:
            self.items = values.split(",")

    def _table(self, text: str) -> Any:
        try:
            table = tomllib.loads(f"v = {text.strip()}")["v"]
        except tomllib.TOMLDecodeError as exc:
            raise click.BadParameter(
                f"'{self.spec}': {text.strip()!r} is not a table written as a TOML array "
                f"([[0, 0.4], [100, 0.35]]): {exc}",
                param_hint="--vary",
            ) from None
        if not isinstance(table, list) or not all(isinstance(row, list) for row in table):
            raise click.BadParameter(f"'{self.spec}': a table is a list of rows", param_hint="--vary")
        return table

    def values(self, model: Model) -> Any:
        """The values in the parameter's unit: a list, or (low, high) to sample."""
        if self.tables is not None:
            return self.tables
        if self.items:
            return [_in_si(model, self.name, v) for v in self.items]
        low, high = (_in_si(model, self.name, b) for b in self.bounds)
        if not self.count:
            return (low, high)
        import numpy as np  # only for a sweep (`stiction check` does not load NumPy)

        return list(np.linspace(low, high, self.count))


def _number(text: str, option: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise click.BadParameter(f"'{text}' is not a number", param_hint=option) from None


def _in_si(model: Model, name: str, text: str) -> float:
    """``100 rpm`` for ``J1.w`` → 10.47: in the unit of the parameter (a top-level one's in SI
    base units), a bare number as it is."""
    from stiction.model.components import si_overrides
    from stiction.model.quantities import is_quantity, si_base, to_si

    text = text.strip()
    if not is_quantity(text):
        try:
            return float(text)
        except ValueError:
            raise click.BadParameter(
                f"'{text}' is not a number or a quantity ('20 kN')", param_hint="--vary"
            ) from None
    model.check_name(name, "--vary")
    value = si_overrides(model.components, {name: text})[name]
    if not isinstance(value, str):
        return float(value)
    return si_base(text, f"--vary '{name}'") if name in model.parameters else to_si(text, "1", name)


@click.command(name="sweep")
@click.argument("model_file", type=FILE)
@click.option(
    "--vary",
    "vary",
    multiple=True,
    required=True,
    help="NAME=START:STOP:COUNT, NAME=V1,V2,… or NAME=TABLE;TABLE;… (repeat); values may have "
    'units ("J1.w=100 rpm:300 rpm:3"), tables are TOML arrays ([[0,0.4],[100,0.35]]).',
)
@click.option(
    "--metric", "metrics", multiple=True, required=True, help='A metric, e.g. "max(J1.w)" (repeat).'
)
@click.option(
    "--samples", type=click.IntRange(min=1), default=None, help="Sample this many variants instead of a grid."
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of --samples.")
@click.option(
    "-o",
    "--output",
    "out_file",
    type=FILE,
    required=True,
    help="The table: .parquet or .csv.",
)
@click.option("--outputs", default="", help="Variables kept as trajectories (Parquet only), comma-separated.")
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Threads (default: every core).")
@click.option("--progress/--no-progress", default=None, help="A progress bar (default: on a terminal).")
@friendly_errors
def sweep_cmd(
    model_file: Path,
    vary: tuple[str, ...],
    metrics: tuple[str, ...],
    samples: int | None,
    seed: int,
    out_file: Path,
    outputs: str,
    workers: int | None,
    progress: bool | None,
) -> None:
    """Run variants of MODEL_FILE and write one row of metrics per variant."""
    from stiction.model.model import Model
    from stiction.sweeps.runner import grid, sample, sweep

    suffix = out_file.suffix.lower()
    if suffix not in (".parquet", ".csv"):
        fail(f"{out_file}: the table is written as .parquet or .csv")
    kept = [o.strip() for o in outputs.split(",") if o.strip()]
    if kept and suffix == ".csv":
        fail("--outputs (trajectories) need a .parquet table")
    specs = [_Vary(v, samples is not None) for v in vary]
    try:
        model = Model.load(model_file)
        try:
            axes = {spec.name: spec.values(model) for spec in specs}
        except ModelError as exc:  # a unit of the wrong kind: the option's mistake, not the file's
            raise click.BadParameter(str(exc), param_hint="--vary") from None
        variants = sample(samples, seed, axes) if samples else grid(axes)
        started = time.perf_counter()
        result = sweep(
            model,
            variants,
            metrics,
            outputs=kept,
            workers=workers,
            progress=sys.stderr.isatty() if progress is None else progress,
        )
    except ModelError as exc:
        raise in_file(model_file, exc) from None
    partial = out_file.with_name(f".{out_file.name}.partial{suffix}")  # never a half-written table
    if suffix == ".parquet":
        result.to_parquet(partial)
    else:
        result.table.to_csv(partial, index=False)
    partial.replace(out_file)
    failed = int((result.table["status"] != "ok").sum())
    click.echo(
        f"{len(result.table)} variants in {time.perf_counter() - started:.2f} s "
        f"({failed} failed) → {out_file}"
    )
