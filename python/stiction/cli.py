"""The ``stiction`` command: simulate, check, compare against references, benchmark.

User mistakes (a bad model, a missing file, malformed TOML) and engine failures end in
one ``error: …`` line on stderr and exit code 2, never a traceback; a failed comparison
exits with 1.
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar

import click

from .errors import ModelError

if TYPE_CHECKING:
    from .model import Model

F = TypeVar("F", bound=Callable[..., Any])

# MSL examples of a source checkout (repo/examples/msl): `bench` runs these by default.
EXAMPLES_DIR = Path(__file__).resolve().parents[2] / "examples" / "msl"
DEFAULT_BENCH = ("CoupledClutches", "Friction", "SimpleGearShift", "HeatLosses")
# `bench --stiff` (issue 13): the stiff shaft and HeatLosses with a stiff shaft.
STIFF_BENCH = tuple(EXAMPLES_DIR.parent / "stiff" / f"{n}.toml" for n in ("StiffShaft", "StiffHeatLosses"))


def _fail(message: str) -> NoReturn:
    click.echo(f"error: {' '.join(message.split())}", err=True)
    sys.exit(2)


def _in_file(path: Path, exc: ModelError) -> ModelError:
    """Prefix an engine error with the model file it concerns."""
    message = str(exc)
    return exc if message.startswith(str(path)) else ModelError(f"{path}: {message}")


def _friendly_errors(func: F) -> F:
    """Turn expected failures into one line on stderr and exit code 2."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except ModelError as exc:
            _fail(str(exc))
        except OSError as exc:
            if exc.strerror and exc.filename:
                _fail(f"{exc.strerror}: {exc.filename}")
            _fail(str(exc))
        except KeyError as exc:
            _fail(str(exc.args[0]) if exc.args else "unknown name")
        except ValueError as exc:  # malformed TOML or CSV
            _fail(str(exc))
        except RuntimeError as exc:  # the engine gave up (e.g. an event iteration)
            _fail(f"simulation failed: {exc}")
        except ImportError as exc:
            _fail(f"the compiled engine is not available ({exc}); build it with maturin")
        except KeyboardInterrupt:
            # Files being written are already gone (removed as the interrupt unwound); leave at
            # once, as shells expect of Ctrl-C: tearing down the interpreter with NumPy, pandas
            # and Arrow loaded takes longer than the run took to stop.
            click.echo("interrupted", err=True)
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(130)

    return wrapper  # type: ignore[return-value]


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="stiction", prog_name="stiction", message="%(prog)s %(version)s")
def main() -> None:
    """Simulate rotational drivetrains with exact Coulomb friction (MSL semantics)."""


def _experiment_options(func: F) -> F:
    func = click.option(
        "--Solver",
        "Solver",
        type=click.Choice(["auto", "tsit45", "bdf", "esdirk34"]),
        default=None,
        help="Override the experiment's Solver (auto default: tsit45, esdirk34 once stiff; tsit45, bdf, esdirk34).",
    )(func)
    for key in reversed(("StartTime", "StopTime", "Interval", "Tolerance")):
        func = click.option(
            f"--{key}",
            key,
            type=float,
            default=None,
            help=f"Override the experiment's {key}.",
        )(func)
    return func


def _load(model_file: Path, model_name: str | None = None) -> Model:
    """A model from a TOML model file or a Modelica ``.mo`` file (``model_name`` picks one)."""
    from .model import Model

    if model_file.suffix.lower() == ".mo":
        return Model.from_modelica(model_file, model_name)
    if model_name is not None:
        raise ModelError(f"{model_file}: --model applies to Modelica (.mo) files only")
    return Model.load(model_file)


def _model_option(func: F) -> F:
    return click.option(
        "--model",
        "model_name",
        default=None,
        help="The model to use when a .mo file holds several (short or qualified name).",
    )(func)


@main.command()
@click.argument("model_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Write the result: .csv (MSL style), .mat (Dymola/OpenModelica) or .parquet.",
)
@click.option(
    "--outputs",
    default=None,
    help="Signals to write: names or globs, comma-separated (J1.w,clutch*.mode). Default: all.",
)
@click.option(
    "--plot",
    "plot_file",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Save a plot (PNG).",
)
@click.option(
    "--signals",
    default=None,
    help="Signals to plot: a,b,c or @FILE (one per line), one axes each; a+b shares axes.",
)
@_model_option
@_experiment_options
@_friendly_errors
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
    from .resultio import result_format

    if output is not None:
        result_format(output)  # refuse an unknown format before running
    model = _load(model_file, model_name)
    # a file of every variable: computed while the run goes on
    record = "all" if output is not None and not outputs else "states"
    try:
        result = model.simulate(record=record, **experiment)
    except ModelError as exc:
        raise _in_file(model_file, exc) from None
    if output is not None:
        chosen = [n.strip() for n in outputs.split(",") if n.strip()] if outputs else None
        result.save(output, chosen)
    if plot_file is not None:
        from .comparison import parse_signals

        groups = [[n.strip() for n in g.split("+") if n.strip()] for g in parse_signals(signals or "")]
        result.plot(*groups, path=plot_file)
    click.echo(result.summary())
    if output is not None:
        click.echo(f"wrote {output}")
    if plot_file is not None:
        click.echo(f"wrote {plot_file}")


@main.command(name="import")
@click.argument("mo_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="The TOML model file to write.",
)
@_model_option
@_friendly_errors
def import_cmd(mo_file: Path, output: Path, model_name: str | None) -> None:
    """Convert a Modelica model (MO_FILE) into a TOML model file."""
    from .model import Model

    model = Model.from_modelica(mo_file, model_name)
    model.save(output)
    click.echo(f"wrote {output} ({len(model.components)} components, {len(model.connections)} connections)")


@main.command(name="export")
@click.argument("model_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="The Modelica file to write (Model.mo).",
)
@_friendly_errors
def export_cmd(model_file: Path, output: Path) -> None:
    """Write MODEL_FILE as a Modelica model with fully qualified MSL classes."""
    model = _load(model_file)
    model.to_modelica(output)
    click.echo(f"wrote {output}")


@main.command()
@click.argument("model_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="The FMU to write (Name.fmu).",
)
@click.option("--fmi", "fmi_version", type=click.Choice(["2", "3"]), default="2", help="FMI version.")
@click.option(
    "--outputs",
    default=None,
    help="Variables the FMU outputs, comma-separated (J1.w,brake.mode). Default: the states.",
)
@_model_option
@_friendly_errors
def fmu(
    model_file: Path, output: Path, fmi_version: str, outputs: str | None, model_name: str | None
) -> None:
    """Write MODEL_FILE (.toml or .mo) as an FMI Co-Simulation FMU."""
    model = _load(model_file, model_name)
    chosen = [s.strip() for s in outputs.split(",") if s.strip()] if outputs else None
    model.to_fmu(output, fmi_version=int(fmi_version), outputs=chosen)
    click.echo(f"wrote {output}")


@main.command()
@click.argument("model_file", type=click.Path(dir_okay=False, path_type=Path))
@click.option("-v", "--verbose", is_flag=True, help="Also show the experiment and every start value.")
@_friendly_errors
def check(model_file: Path, verbose: bool) -> None:
    """Validate MODEL_FILE (.toml or .mo) without running it."""
    model = _load(model_file)
    try:
        model.check()
        info = model.run_info() if verbose else None
    except ModelError as exc:
        raise _in_file(model_file, exc) from None
    click.echo(f"ok: {model.name} ({len(model.components)} components, {len(model.connections)} connections)")
    if info is not None:
        click.echo(f"experiment: {info.experiment}")
        click.echo(f"start values: {info.initialization.counts()}")
        click.echo(str(info.initialization))


@main.command(name="list")
@_friendly_errors
def list_cmd() -> None:
    """List every component type with its MSL class and description."""
    from .catalogue import catalogue

    known = catalogue()
    width = max(len(n) for n in known)
    for info in known.values():
        click.echo(f"{info.name:<{width}}  {info.description} ({info.msl_class})")


@main.command()
@click.argument("type_name")
@_friendly_errors
def describe(type_name: str) -> None:
    """Show TYPE_NAME's parameters (default, unit, range), ports and variables."""
    from .catalogue import describe as describe_type

    click.echo(str(describe_type(type_name)))


@main.command(name="compare")
@click.argument("result_csv", type=click.Path(dir_okay=False, path_type=Path))
@click.argument("reference_csv", type=click.Path(dir_okay=False, path_type=Path))
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
@_friendly_errors
def compare_cmd(
    result_csv: Path, reference_csv: Path, tolerance: float, floor: float, signals: str | None, verbose: bool
) -> None:
    """Check RESULT_CSV against REFERENCE_CSV (MSL tube method); exit 1 on failure.

    Either file may be a CSV, a Dymola/OpenModelica .mat result or a Parquet table."""
    from .comparison import compare, parse_signals

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


@main.command()
@click.argument("model_files", nargs=-1, type=click.Path(dir_okay=False, path_type=Path))
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
@_friendly_errors
def bench(
    model_files: tuple[Path, ...],
    repeat: int,
    warmup: int,
    sweep_variants: int | None,
    dask: bool,
    scale_sizes: str | None,
    stiff: bool,
) -> None:
    """Time whole runs of MODEL_FILES (default: MSL CoupledClutches, Friction, SimpleGearShift, HeatLosses)."""
    from .bench import bench as run_bench
    from .cli_bench import print_scale, print_stiff, print_sweeps
    from .model import Model

    if scale_sizes is not None:
        print_scale(scale_sizes)
        return
    if stiff:
        print_stiff(list(model_files) or [*STIFF_BENCH, EXAMPLES_DIR / "HeatLosses.toml"])
        return
    files = list(model_files) or [EXAMPLES_DIR / f"{n}.toml" for n in DEFAULT_BENCH]
    if not model_files and not all(f.is_file() for f in files):
        _fail(f"no MODEL files given and the default examples are not in {EXAMPLES_DIR}")
    if sweep_variants is not None:
        print_sweeps(list(model_files) or [EXAMPLES_DIR / "CoupledClutches.toml"], sweep_variants, dask)
        return
    click.echo(
        f"{'model':<24} {'median ms':>10} {'min ms':>10} {'core med':>9} {'core min':>9} "
        f"{'+all vars ms':>13} {'after/states':>12} {'record=all ms':>13} {'all/states':>10} "
        f"{'steps':>7} {'rhs evals':>10} {'events':>7}"
    )
    for path in files:
        try:
            row = run_bench(Model.load(path), repeat=repeat, warmup=warmup)
        except ModelError as exc:
            raise _in_file(path, exc) from None
        click.echo(
            f"{row.model:<24} {row.median_ms:>10.3f} {row.min_ms:>10.3f} {row.core_median_ms:>9.3f} "
            f"{row.core_min_ms:>9.3f} {row.table_ms:>13.3f} {row.after_ratio:>11.2f}× "
            f"{row.recording_ms:>13.3f} {row.all_variables_ratio:>9.2f}× "
            f"{row.steps:>7} {row.rhs_evals:>10} {row.events:>7}"
        )


from . import cli_sweep as _cli_sweep  # noqa: F401  (registers `stiction sweep`)
