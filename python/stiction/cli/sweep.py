"""``stiction sweep``: vary parameters of a model file, compute metrics, write a table.

``--vary clutch1.fn_max=10:30:21`` (start:stop:count) or ``--vary sin1.f=0.1,0.2,0.4``
give a full grid; with ``--samples N`` a range ``a:b`` is sampled (Latin hypercube) and a
list is drawn from. The table goes to ``-o sweep.parquet`` or ``sweep.csv``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Any

import click

from stiction.cli.options import FILE, fail, friendly_errors, in_file
from stiction.errors import ModelError


def _number(text: str, option: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise click.BadParameter(f"'{text}' is not a number", param_hint=option) from None


def _parse_vary(spec: str, sampled: bool) -> tuple[str, Any]:
    """``name=a:b:n`` → n values from a to b (sampled: the range a:b); ``name=v1,v2`` → values."""
    name, sep, values = spec.partition("=")
    if not sep or not name or not values:
        raise click.BadParameter(
            f"'{spec}': write NAME=START:STOP:COUNT or NAME=V1,V2,…", param_hint="--vary"
        )
    if ":" in values:
        parts = values.split(":")
        if sampled and len(parts) == 2:
            return name, (_number(parts[0], "--vary"), _number(parts[1], "--vary"))
        if len(parts) != 3:
            raise click.BadParameter(f"'{spec}': a range is START:STOP:COUNT", param_hint="--vary")
        start, stop = _number(parts[0], "--vary"), _number(parts[1], "--vary")
        count = int(_number(parts[2], "--vary"))
        if count < 1:
            raise click.BadParameter(f"'{spec}': COUNT must be at least 1", param_hint="--vary")
        import numpy as np  # only for a sweep (`stiction check` does not load NumPy)

        return name, list(np.linspace(start, stop, count))
    return name, [_number(v, "--vary") for v in values.split(",")]


@click.command(name="sweep")
@click.argument("model_file", type=FILE)
@click.option(
    "--vary", "vary", multiple=True, required=True, help="NAME=START:STOP:COUNT or NAME=V1,V2,… (repeat)."
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
    axes = dict(_parse_vary(v, samples is not None) for v in vary)
    variants = sample(samples, seed, axes) if samples else grid(axes)
    try:
        model = Model.load(model_file)
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
