"""``stiction bench``: time whole runs (default: MSL examples shipped in the package), and the
tables it prints for --scale, --stiff and --sweep (issues 9, 10 and 13): each runs its benchmark
and echoes one row per case. The timing itself is ``stiction.cli.benchmarks``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from stiction import _deps
from stiction.cli.options import FILE, fail, friendly_errors, in_file
from stiction.errors import ModelError

__all__ = ["BENCH_MODELS", "bench", "print_scale", "print_stiff", "print_sweeps"]

# The models `bench` runs by default, copied into the package from examples/msl and
# examples/stiff by scripts/generate.py (so an installed wheel has them; `--check` keeps them equal).
BENCH_MODELS = Path(__file__).resolve().parent / "bench_models"
DEFAULT_BENCH = ("CoupledClutches", "Friction", "SimpleGearShift", "HeatLosses")
# `bench --stiff` (issue 13): the stiff shaft and HeatLosses with a stiff shaft.
STIFF_BENCH = ("StiffShaft", "StiffHeatLosses", "HeatLosses")


@click.command()
@click.argument("model_files", nargs=-1, type=FILE)
@click.option(
    "--repeat",
    type=click.IntRange(min=1),
    default=50,
    show_default=True,
    help="Timed runs per model.",
)
@click.option(
    "--warmup",
    type=click.IntRange(min=0),
    default=3,
    show_default=True,
    help="Untimed runs before timing.",
)
@click.option(
    "--sweep",
    "sweep_variants",
    type=click.IntRange(min=1),
    default=None,
    help="Time a sweep of this many variants instead (1 worker and every core).",
)
@click.option(
    "--dask",
    is_flag=True,
    help="With --sweep: the same sweep on a Dask LocalCluster of 2 processes × 1 thread too.",
)
@click.option(
    "--scale",
    "scale_sizes",
    default=None,
    help="Time generated chains, ladders and ladders engaging in waves of these sizes instead, "
    "e.g. 10,100,1000.",
)
@click.option(
    "--stiff",
    is_flag=True,
    help="Compare the solvers (tsit45, bdf, esdirk34, auto) on the stiff examples and HeatLosses "
    "(or on MODEL_FILES) instead.",
)
@click.option(
    "--fit", "fit_bench", is_flag=True, help="Time a fit of 4 parameters of a braked flywheel instead."
)
@click.option(
    "--floor",
    is_flag=True,
    help="Also time the floor (issue 34): experiment overrides, one variable read alone, the "
    "ladder of 100 and 1000 from a file with Python's share.",
)
@click.option(
    "--json",
    "json_out",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Save every figure printed (the models' table, --floor) as JSON to this file.",
)
@click.option(
    "--compare",
    "compare_ref",
    type=FILE,
    default=None,
    help="Print every figure against the same figure of a saved run (--json), marking the "
    "ones worse beyond the noise.",
)
@friendly_errors
def bench(
    model_files: tuple[Path, ...],
    repeat: int,
    warmup: int,
    sweep_variants: int | None,
    dask: bool,
    scale_sizes: str | None,
    stiff: bool,
    fit_bench: bool,
    floor: bool,
    json_out: Path | None,
    compare_ref: Path | None,
) -> None:
    """Time whole runs of MODEL_FILES (default: MSL CoupledClutches, Friction, SimpleGearShift, HeatLosses)."""
    from stiction.cli.benchmarks import bench as run_bench
    from stiction.model.model import Model

    if fit_bench:
        from stiction.cli.bench_fit import print_fit

        print_fit()
        return
    if scale_sizes is not None:
        print_scale(scale_sizes)
        return
    if stiff:
        print_stiff(list(model_files) or [BENCH_MODELS / f"{n}.toml" for n in STIFF_BENCH])
        return
    files = list(model_files) or [BENCH_MODELS / f"{n}.toml" for n in DEFAULT_BENCH]
    if not model_files and not all(f.is_file() for f in files):
        fail(f"no MODEL files given and the default examples are not in {BENCH_MODELS}")
    if sweep_variants is not None:
        print_sweeps(list(model_files) or [BENCH_MODELS / "CoupledClutches.toml"], sweep_variants, dask)
        return
    figures: dict[str, float] = {}
    click.echo(
        f"{'model':<24} {'median ms':>10} {'min ms':>10} {'core med':>9} {'core min':>9} "
        f"{'+all vars ms':>13} {'after/states':>12} {'record=all ms':>13} {'all/states':>10} "
        f"{'steps':>7} {'rhs evals':>10} {'events':>7}"
    )
    for path in files:
        try:
            row = run_bench(Model.load(path), repeat=repeat, warmup=warmup)
        except ModelError as exc:
            raise in_file(path, exc) from None
        click.echo(
            f"{row.model:<24} {row.median_ms:>10.3f} {row.min_ms:>10.3f} {row.core_median_ms:>9.3f} "
            f"{row.core_min_ms:>9.3f} {row.table_ms:>13.3f} {row.after_ratio:>11.2f}× "
            f"{row.recording_ms:>13.3f} {row.all_variables_ratio:>9.2f}× "
            f"{row.steps:>7} {row.rhs_evals:>10} {row.events:>7}"
        )
        figures |= row_figures(row)
    if floor:
        figures |= _print_floor(repeat)
    _save_and_compare(figures, json_out, compare_ref)


def row_figures(row: Any) -> dict[str, float]:
    """The times of a row of the models' table, as named figures."""
    names = ("median_ms", "min_ms", "core_median_ms", "core_min_ms", "table_ms", "recording_ms")
    return {f"{row.model}.{n}": float(getattr(row, n)) for n in names}


def _print_floor(repeat: int) -> dict[str, float]:
    from stiction.cli.bench_floor import floor_figures, floor_lines
    from stiction.model.model import Model

    click.echo("\nthe floor (issue 34), medians; ratios against a plain run measured alternately")
    figures = floor_figures(Model.load(BENCH_MODELS / "CoupledClutches.toml"), repeat)
    for line in floor_lines(figures):
        click.echo(line)
    return figures


def _save_and_compare(figures: dict[str, float], json_out: Path | None, compare_ref: Path | None) -> None:
    from stiction.cli.bench_floor import compare_figures, read_figures, write_figures

    if compare_ref is not None:
        try:
            ref = read_figures(compare_ref)
        except ValueError as e:
            fail(str(e))
        rows = compare_figures(figures, ref)
        click.echo(f"\n{'figure':<44} {'now':>10} {'then':>10} {'ratio':>7}   (against {compare_ref})")
        for row in rows:
            click.echo(row.line())
        worse = [r.name for r in rows if r.worse()]
        click.echo(
            f"{len(worse)} of {len(rows)} figures worse beyond the noise"
            + (": " + ", ".join(worse) if worse else "")
        )
    if json_out is not None:
        write_figures(json_out, figures)
        click.echo(f"figures saved to {json_out}")


def print_scale(sizes: str) -> None:
    """One row per generated chain, ladder and ladder-waves of each size; a size the engine
    refuses prints its reason in place of the numbers."""
    from stiction.cli.benchmarks import bench_scale
    from stiction.errors import StictionError

    try:
        ns = [int(s) for s in sizes.split(",") if s.strip()]
    except ValueError:
        raise click.BadParameter(f"expected sizes like 10,100,1000, got {sizes!r}", param_hint="--scale")
    click.echo(
        f"{'model':<12} {'N':>6} {'ms':>10} {'steps':>7} {'rhs evals':>10} {'events':>7} "
        f"{'us/step/elem':>13} {'ms/event':>9}"
    )
    for kind in ("chain", "ladder", "ladder-waves"):
        for n in ns:
            try:
                row = bench_scale(kind, n)
            except StictionError as e:
                # a size the engine refuses (the memory guard) is a row of the table, not the end of it
                click.echo(f"{kind:<12} {n:>6} refused: {str(e).splitlines()[0]}")
                continue
            click.echo(
                f"{kind:<12} {n:>6} {row.ms:>10.1f} {row.steps:>7} {row.rhs_evals:>10} {row.events:>7} "
                f"{row.us_per_step_element:>13.3f} {row.ms_per_event:>9.3f}"
            )


def print_stiff(files: list[Path]) -> None:
    from stiction.cli.benchmarks import bench_solvers
    from stiction.model.model import Model

    click.echo(
        f"{'model':<18} {'solver':<9} {'min ms':>10} {'steps':>8} {'rejected':>9} "
        f"{'rhs evals':>10} {'jacobians':>10} {'lu setups':>10} {'switches':>9}"
    )
    for path in files:
        model = Model.load(path)
        for row in bench_solvers(model, ["tsit45", "bdf", "esdirk34", "auto"], repeat=5):
            click.echo(
                f"{row.model:<18} {row.solver:<9} {row.min_ms:>10.1f} {row.steps:>8} {row.rejected:>9} "
                f"{row.rhs_evals:>10} {row.jacobians:>10} {row.lu_setups:>10} {row.switches:>9}"
            )


def print_sweeps(files: list[Path], variants: int, dask: bool) -> None:
    """Local sweeps on 1 worker and every core (and on Dask), with the time outside the
    core's runs: wall × workers against the sum of the variants' ``wall_s``."""
    from stiction.cli.benchmarks import bench_sweep
    from stiction.model.model import Model

    click.echo(
        f"{'model':<20} {'where':<6} {'variants':>8} {'workers':>7} {'total s':>8} {'ms/variant':>10} "
        f"{'overhead %':>10} {'us/variant':>10} {'single run ms':>13}"
    )
    for path in files:
        model = Model.load(path)
        for row in (bench_sweep(model, variants, workers) for workers in (1, None)):
            _echo_sweep_row(model.name, row)
        if dask:
            _bench_dask(model, variants)


def _echo_sweep_row(name: str, row: Any) -> None:
    click.echo(
        f"{name:<20} {row.where:<6} {row.variants:>8} {row.workers:>7} {row.seconds:>8.2f} "
        f"{row.per_variant_ms:>10.3f} {100 * row.overhead:>10.2f} {row.overhead_us:>10.1f} "
        f"{row.single_run_ms:>13.3f}"
    )


def _bench_dask(model: Any, variants: int) -> None:
    """The sweep on a LocalCluster of 2 processes × 1 thread (what ``LocalCluster()`` picks on
    a 2-core machine), alternating with the local sweep on every core, twice: on a shared
    machine the load drifts between runs, so each Dask run is compared with the local run
    just before it. Starting the cluster is not timed."""
    Client, LocalCluster = _deps.distributed.Client, _deps.distributed.LocalCluster

    from stiction.cli.benchmarks import bench_sweep

    ratios = []
    with (
        LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        for _ in range(2):
            local = bench_sweep(model, variants, None)
            remote = bench_sweep(model, variants, None, client=client)
            for row in (local, remote):
                _echo_sweep_row(model.name, row)
            ratios.append(remote.seconds / local.seconds)
    click.echo(
        "dask / local (every core), each against the local run before it: "
        + ", ".join(f"{r:.2f}x" for r in ratios)
    )
