"""What a run was set up with, reported instead of chosen silently: the experiment (and which
of its settings were defaults) and the initialization (every start value fixed, guessed or
computed). Both come from the engine, computed when first asked for.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

__all__ = ["Experiment", "Initialization", "RunInfo", "StartValue"]


@dataclass(frozen=True)
class Experiment:
    """The experiment a run used (MSL names); ``defaults`` lists the settings nobody gave."""

    StartTime: float  # MSL names, hence capitalised
    StopTime: float
    Interval: float
    Tolerance: float
    Solver: str
    defaults: tuple[str, ...] = ()

    def __getitem__(self, key: str) -> float | str:
        if key not in ("StartTime", "StopTime", "Interval", "Tolerance", "Solver"):
            raise KeyError(key)
        value: float | str = getattr(self, key)
        return value

    def __str__(self) -> str:
        parts = []
        for key in ("StartTime", "StopTime", "Interval", "Tolerance", "Solver"):
            value = self[key]
            shown = f"{value:g}" if isinstance(value, float) else value
            parts.append(f"{key} {shown}" + (" (default)" if key in self.defaults else ""))
        return ", ".join(parts)


@dataclass(frozen=True)
class StartValue:
    """One start value: ``fixed`` (an initial equation), ``guessed`` (a guess the
    initialization kept) or ``computed`` (a guess other equations overrode), and the value the
    run starts from."""

    variable: str
    start: float
    status: str
    value: float


class Initialization(tuple[StartValue, ...]):
    """Every start value of a model in model order; ``str()`` gives a table."""

    def by_status(self, status: str) -> list[StartValue]:
        """The start values with that status ("fixed", "guessed" or "computed")."""
        return [v for v in self if v.status == status]

    def counts(self) -> str:
        """``3 fixed, 1 guessed, 0 computed``."""
        return ", ".join(f"{len(self.by_status(s))} {s}" for s in ("fixed", "guessed", "computed"))

    def __str__(self) -> str:
        if not self:
            return "no start values"
        width = max(len(v.variable) for v in self)
        lines = [f"{'variable':<{width}}  {'status':<8}  {'start':>12}  {'initial':>12}"]
        for v in self:
            lines.append(f"{v.variable:<{width}}  {v.status:<8}  {v.start:>12.6g}  {v.value:>12.6g}")
        return "\n".join(lines)


class RunInfo:
    """The engine's view of one model text and its overrides, computed when first asked for."""

    def __init__(
        self,
        model_toml: str,
        base_dir: str,
        overrides: dict[str, float],
        solver: str | None = None,
        types: dict[str, str] | Callable[[], dict[str, str]] | None = None,
    ) -> None:
        self._args = (model_toml, base_dir)
        self._overrides = overrides
        self._solver = solver
        # component name → type; or what gives them, when first needed (a loaded file's)
        self._types: dict[str, str] | Callable[[], dict[str, str]] = (
            types if callable(types) else dict(types or {})
        )

    def unit(self, variable: str) -> str:
        """The unit of a result variable, from the component catalogue."""
        from stiction.model.catalogue import unit_of

        if callable(self._types):
            self._types = dict(self._types())
        return unit_of(variable, self._types)

    @functools.cached_property
    def experiment(self) -> Experiment:
        """The experiment settings in force, and which were defaults."""
        from stiction import _core

        raw: dict[str, Any] = _core.experiment(*self._args, self._overrides, self._solver)
        defaults = tuple(raw.pop("defaults"))
        return Experiment(**raw, defaults=defaults)

    def time_event_sources(self, times: list[float]) -> list[list[str]]:
        """For each time, the components whose time event it is (``"press (Step)"``)."""
        from stiction import _core

        return _core.time_event_sources(*self._args, self._overrides, times)

    @functools.cached_property
    def initialization(self) -> Initialization:
        """Every start value: fixed, guessed or computed, with its initial value."""
        from stiction import _core

        return Initialization(StartValue(*row) for row in _core.initialization(*self._args))
