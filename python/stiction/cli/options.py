"""What the commands share: one-line errors with exit code 2, the experiment and ``--model``
options, and reading a model file of either kind."""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar

import click

from stiction.errors import ModelError

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = [
    "FILE",
    "experiment_options",
    "fail",
    "friendly_errors",
    "in_file",
    "load_model",
    "model_option",
    "output_option",
]

F = TypeVar("F", bound=Callable[..., Any])

FILE = click.Path(dir_okay=False, path_type=Path)
"""A file argument or option: a path, never a folder."""


def fail(message: str, *more: str) -> NoReturn:
    """Each message on one ``error: …`` line on stderr, then exit code 2."""
    for line in (message, *more):
        click.echo(f"error: {' '.join(line.split())}", err=True)
    sys.exit(2)


def in_file(path: Path, exc: ModelError) -> ModelError:
    """Prefix an engine error with the model file it concerns."""
    message = str(exc)
    return exc if message.startswith(str(path)) else ModelError(f"{path}: {message}")


def friendly_errors(func: F) -> F:
    """Turn expected failures into one line on stderr and exit code 2."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except ModelError as exc:
            if len(getattr(exc, "each", ())) > 1:  # a Modelica file's errors, one a line
                fail(*str(exc).split("\n"))
            fail(str(exc))
        except OSError as exc:
            if exc.strerror and exc.filename:
                fail(f"{exc.strerror}: {exc.filename}")
            fail(str(exc))
        except KeyError as exc:
            fail(str(exc.args[0]) if exc.args else "unknown name")
        except ValueError as exc:  # malformed TOML or CSV
            fail(str(exc))
        except RuntimeError as exc:  # the engine gave up (e.g. an event iteration)
            fail(f"simulation failed: {exc}")
        except ImportError as exc:
            fail(f"the compiled engine is not available ({exc}); build it with maturin")
        except KeyboardInterrupt:
            # Files being written are already gone (removed as the interrupt unwound); leave at
            # once, as shells expect of Ctrl-C: tearing down the interpreter with NumPy, pandas
            # and Arrow loaded takes longer than the run took to stop.
            click.echo("interrupted", err=True)
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(130)

    return wrapper  # type: ignore[return-value]


def experiment_options(func: F) -> F:
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


def load_model(model_file: Path, model_name: str | None = None) -> Model:
    """A model from a TOML model file or a Modelica ``.mo`` file (``model_name`` picks one)."""
    from stiction.model.model import Model

    if model_file.suffix.lower() == ".mo":
        return Model.from_modelica(model_file, model_name)
    if model_name is not None:
        raise ModelError(f"{model_file}: --model applies to Modelica (.mo) files only")
    return Model.load(model_file)


def model_option(func: F) -> F:
    return click.option(
        "--model",
        "model_name",
        default=None,
        help="The model to use when a .mo file holds several (short or qualified name).",
    )(func)


def output_option(help: str, required: bool = True) -> Callable[[F], F]:
    """``-o/--output FILE``: what a command writes."""
    return click.option("-o", "--output", type=FILE, required=required, help=help)
