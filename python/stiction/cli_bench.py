"""The tables `stiction bench` prints for --scale, --stiff and --sweep (issues 9, 10 and 13):
each runs its benchmark and echoes one row per case."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

__all__ = ["print_scale", "print_stiff", "print_sweeps"]


def print_scale(sizes: str) -> None:
    """One row per generated chain, ladder and ladder-waves of each size; a size the engine
    refuses prints its reason in place of the numbers."""
    from .bench import bench_scale
    from .errors import StictionError

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
    from .bench import bench_solvers
    from .model import Model

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
    from .bench import bench_sweep
    from .model import Model

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
    from distributed import Client, LocalCluster

    from .bench import bench_sweep

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
