"""``CompiledModel``: a model assembled once, run many times with other values.

Overrides name parameters the MSL way (``clutch1.fn_max``, ``brake.mu_pos`` with a whole
table, ``sin1.f``), start values (``J1.w``, ``J1.phi``) and experiment settings
(``StopTime``, ``Tolerance``). A variant with new numbers reuses the model's components
and topology; one that changes its structure (``useSupport``, ``useHeatPort``) is compiled
anew. Every name and value is checked before a run, and a bad one raises ``ModelError``
naming the component and the parameter. A compiled model pickles as its model text, so
it travels to Dask workers.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stiction.model.modelfile import EXPERIMENT_KEYS
from stiction.results.result import Result

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["CompiledModel"]

EXPERIMENT = EXPERIMENT_KEYS  # StartTime … Solver, max_events, max_steps, timeout


def merge_overrides(params: Mapping[str, Any] | None, experiment: Mapping[str, Any]) -> dict[str, Any]:
    """One mapping of overrides: ``params`` plus experiment keywords that are not None."""
    merged = dict(params or {})
    for key, value in experiment.items():
        if key not in EXPERIMENT:
            raise TypeError(f"unknown experiment setting {key!r} (one of {', '.join(EXPERIMENT)})")
        if value is not None:
            merged[key] = value
    return merged


class Precompiled:
    """The engine's compile of a parsed model file (``_core.load_model``), started now on a
    thread of its own: the compile releases the interpreter, so it runs while Python makes
    the model's objects (a ladder of 1000 inertias: 25 ms of compile beside 30 ms of
    objects), and the first run takes it. Its error, if any, is raised there, as a compile
    from the text would raise it."""

    def __init__(self, parsed: Any) -> None:
        from stiction import _core

        self._core: Any = None
        self._error: Exception | None = None

        def work() -> None:
            try:
                self._core = _core.CompiledModel.from_parsed(parsed)
            except Exception as exc:  # noqa: BLE001  # kept: the run that takes the compile raises it
                self._error = exc

        self._thread = threading.Thread(target=work, name="stiction-compile", daemon=True)
        self._thread.start()

    def result(self) -> Any:
        """The engine's compiled model (None if the reading was taken already); the
        compile's error raised."""
        self._thread.join()
        if self._error is not None:
            raise self._error
        return self._core


class CompiledModel:
    """A model compiled for repeated runs (see the module docstring)."""

    def __init__(
        self, text: str, base_dir: str | os.PathLike[str] = ".", name: str = "model", *, parsed: Any = None
    ) -> None:
        """Compile model-file ``text``; relative file names are resolved against ``base_dir``.
        ``parsed``: the engine's compile of that same text and folder (``Precompiled``), which
        spares parsing and compiling it here."""
        from stiction import _core

        self.text = text
        self.base_dir = Path(base_dir)
        self.name = name
        core = parsed.result() if parsed is not None else None
        self._core = core if core is not None else _core.CompiledModel(text, str(self.base_dir))
        self._variants: dict[tuple[Any, ...], Any] = {}

    @classmethod
    def of(cls, model: Model) -> CompiledModel:
        """Compile a ``Model``."""
        return cls(model.to_toml(), model.base_dir, model.name)

    def __reduce__(self) -> tuple[Any, tuple[str, str, str]]:
        # travels as its description; compiled again where it lands
        return (CompiledModel, (self.text, str(self.base_dir), self.name))

    def __repr__(self) -> str:
        return f"<CompiledModel {self.name!r}>"

    @property
    def parameter_names(self) -> list[str]:
        """Every name an override may use: ``component.parameter``, then experiment settings."""
        return list(self._core.parameter_names())

    def simulate(
        self, params: Mapping[str, Any] | None = None, *, record: str = "states", **experiment: Any
    ) -> Result:
        """Run with ``params`` overridden (and ``StopTime=…`` etc. as keywords); ``record``
        as for ``Model.simulate``."""
        all_variables = records_all(record)
        overrides = merge_overrides(params, experiment)
        return Result.from_core(self._variant(overrides).simulate(record_all=all_variables), name=self.name)

    def _variant(self, overrides: Mapping[str, Any]) -> Any:
        """The engine's variant with ``overrides`` (this model itself for none), kept for the
        next run with the same overrides: building a variant is a fifth of a CoupledClutches
        run, and a script calls ``simulate(StopTime=2)`` again and again. Kept only for plain
        values (numbers, Booleans, strings); a few of them, the newest."""
        if not overrides:
            return self._core
        key = _variant_key(overrides)
        core = self._variants.get(key) if key is not None else None
        if core is None:
            core = self._core.variant(dict(overrides))
            if key is not None:
                if len(self._variants) >= VARIANTS_KEPT:
                    self._variants.pop(next(iter(self._variants)), None)  # the oldest
                self._variants[key] = core
        return core

    def check_overrides(self, params: Mapping[str, Any]) -> None:
        """Raise ``ModelError`` if a name or value of ``params`` is not valid."""
        self._core.variant(dict(params))


# How many variants a compiled model keeps for runs with the same overrides again.
VARIANTS_KEPT = 8
_PLAIN = (bool, int, float, str)


def _variant_key(overrides: Mapping[str, Any]) -> tuple[Any, ...] | None:
    """A key for ``overrides`` when every value is plain (its type part of it: ``1`` and
    ``1.0`` and ``True`` are other overrides), else None: not kept."""
    if not all(type(v) in _PLAIN for v in overrides.values()):
        return None
    return tuple(sorted((k, type(v).__name__, v) for k, v in overrides.items()))


RECORD_CHOICES = ("states", "all")


def records_all(record: str) -> bool:
    """Whether ``record`` (``"states"`` or ``"all"``) asks for every variable during the run;
    a ``ValueError`` naming the choices for anything else."""
    if record not in RECORD_CHOICES:
        raise ValueError(f"record must be one of {', '.join(map(repr, RECORD_CHOICES))}, got {record!r}")
    return record == "all"
