"""The component catalogue, as the core declares it: every type with its MSL class, parameters
(default, unit, valid range, description), ports and result variables with units.

It is read from the compiled engine (``stiction._core.catalogue()``), where each component
declares its parameters on the lines that read them; the component classes, their
docstrings and signatures, ``components.pyi``, ``docs/components.md``, ``st.describe`` and
``stiction list`` / ``stiction describe`` are all made from it.
"""

from __future__ import annotations

import difflib
import functools
import importlib
import inspect
import operator
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from stiction.errors import ModelError
from stiction.model.names import owner
from stiction.model.quantities import display_unit, in_display_unit

__all__ = ["ComponentInfo", "Parameter", "Port", "Variable", "catalogue", "describe", "show_value", "unit_of"]

# The Python type each parameter kind accepts, as annotations read.
_ANNOTATIONS = {
    "Real": "float",
    "Boolean": "bool",
    "start value": "float | StartValue",
    "Boolean start value": "bool | StartValue",
    "String": "str | os.PathLike[str]",
    "vector": "float | Sequence[float]",
    "record": "Mapping[str, Any]",
}


def show_value(value: Any) -> str:
    """A default as a model file writes it: ``true``, ``1e+10``, ``0.5``, ``[[0, 0.5]]``."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        short = f"{value:g}"
        return short if float(short) == value else repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(show_value(v) for v in value) + "]"
    return repr(value) if isinstance(value, str) else str(value)


_COMPARE: dict[str, Callable[[float, float], bool]] = {
    ">": operator.gt,
    ">=": operator.ge,
    "<": operator.lt,
    "<=": operator.le,
    "!=": operator.ne,
}


@functools.cache
def _range_test(text: str) -> Callable[[float], bool] | None:
    """The test of a catalogue range on a number: ``> 0``, ``>= -273.15``, ``!= 0``,
    ``(0, 100]``, ``a whole number``; None for a range written for a table."""
    if text == "a whole number":
        return lambda v: v.is_integer()
    compared = re.fullmatch(r"(>=|<=|!=|>|<) (\S+)", text)
    if compared:
        op, bound = _COMPARE[compared.group(1)], float(compared.group(2))
        return lambda v: op(v, bound)
    interval = re.fullmatch(r"([(\[])(\S+), (\S+)([)\]])", text)
    if interval:
        left, lo, hi, right = interval.groups()
        low = operator.ge if left == "[" else operator.gt
        high = operator.le if right == "]" else operator.lt
        a, b = float(lo), float(hi)
        return lambda v: low(v, a) and high(v, b)
    return None


def _table_violation(text: str, table: Any) -> str | None:
    """A table's range ``coefficients >= 0`` (what its values are, a comparison, a bound) on
    every column but the first (the abscissa); the engine's words, None for other ranges."""
    compared = re.fullmatch(r"(\w+) (>=|<=|!=|>|<) (\S+)", text)
    if compared is None or not isinstance(table, (list, tuple)):
        return None
    what, op, bound = compared.group(1), _COMPARE[compared.group(2)], float(compared.group(3))
    for row in table:
        if not isinstance(row, (list, tuple)):
            return None
        for cell in row[1:]:
            if isinstance(cell, bool) or not isinstance(cell, (int, float)) or op(float(cell), bound):
                continue
            shown = ", ".join(show_value(c) for c in row)
            return f"{what} must be {compared.group(2)} {compared.group(3)}, got {show_value(cell)} in row [{shown}]"
    return None


@dataclass(frozen=True)
class Parameter:
    """One parameter: its MSL name, kind, default, unit, valid range and description."""

    name: str
    kind: str
    default: Any
    required: bool
    unit: str
    description: str
    range: str | None = None
    choices: tuple[str, ...] = ()
    #: whether a running ``Simulation`` (``set_parameter``) and an FMU in step mode can take a
    #: new value; fixed are those that decide the structure, a position or a time event, and
    #: start values
    tunable: bool = False

    @property
    def annotation(self) -> str:
        """The Python type the parameter takes, as an annotation string."""
        if self.kind.startswith("table"):  # a cell may be a quantity or an expression (text)
            return "Sequence[Sequence[float | str]]"
        if self.choices:
            return "Literal[" + ", ".join(repr(c) for c in self.choices) + "]"
        return _ANNOTATIONS[self.kind]

    def violation(self, value: Any) -> str | None:
        """Why a plain number is outside this parameter's range (``must be > 0, got -1.2``), or
        a table's number outside its range (``coefficients >= 0``: every column but the first),
        the engine's words; None when it is inside, or not a plain number (a table's expression
        cell), or the range is one only the engine reads (``eta_mf1, eta_mf2 in (0, 1]``): the
        engine checks those when it reads them."""
        if self.range is not None and self.kind.startswith("table"):
            return _table_violation(self.range, value)
        if self.range is None or isinstance(value, bool) or not isinstance(value, (int, float)):
            return None
        inside = _range_test(self.range)
        if inside is None or inside(float(value)):
            return None
        shown = int(value) if float(value).is_integer() else value
        return f"must be {self.range}, got {shown}"

    def summary(self) -> str:
        """``Real [N], required, >= 0`` — kind, unit, default and range on one line; MSL's
        display unit with the unit and the default (``[K] (displayUnit degC) … 293.15 (20 degC)``)."""
        shown = display_unit(self.unit)
        parts = [self.kind + _unit_text(self.unit)]
        if self.required:
            parts.append("required")
        elif self.default is not None:
            what = {"start value": "start (a guess unless given)", "Boolean start value": "start"}
            what = what.get(self.kind, "default")
            default = show_value(self.default)
            if shown and isinstance(self.default, float) and self.default:
                default += f" ({show_value(round(in_display_unit(self.default, self.unit)[0], 10))} {shown})"
            parts.append(f"{what} {default}")
        if self.range:
            parts.append(self.range)
        return ", ".join(parts)


@dataclass(frozen=True)
class Port:
    """A connector: its name, kind (flange, signal input/output, heat port) and condition."""

    name: str
    kind: str
    enabled_by: str | None = None

    def summary(self) -> str:
        """``support: flange (if useSupport = true)``."""
        cond = f" (if {self.enabled_by} = true)" if self.enabled_by else ""
        return f"{self.name}: {self.kind}{cond}"


@dataclass(frozen=True)
class Variable:
    """A result variable, relative to the instance (``tau``, ``flange_a.tau``), and its unit."""

    name: str
    unit: str


@dataclass(frozen=True)
class ComponentInfo:
    """Everything the reference says about one component type."""

    name: str
    msl_class: str
    description: str
    parameters: tuple[Parameter, ...]
    ports: tuple[Port, ...]
    variables: tuple[Variable, ...]

    def parameter(self, name: str) -> Parameter:
        """The parameter of that name; ModelError with suggestions if there is none."""
        for p in self.parameters:
            if p.name == name:
                return p
        names = [p.name for p in self.parameters]
        raise ModelError(f"{self.name}: parameter '{name}': unknown parameter{_suggest(name, names)}")

    def docstring(self) -> str:
        """The class docstring: description, MSL class, parameters, ports, variables."""
        lines = [f"{self.description}.", "", self.origin(), ""]
        if self.parameters:
            lines += ["Parameters", "----------"]
            for p in self.parameters:
                lines += [f"{p.name} : {p.summary()}", f"    {p.description}"]
            lines.append("")
        lines += ["Ports", "-----"] + [f"- {p.summary()}" for p in self.ports] + [""]
        lines += ["Variables", "---------"]
        lines += [f"- {v.name}{_unit_text(v.unit)}" for v in self.variables]
        return "\n".join(lines)

    def origin(self) -> str:
        """Where the type comes from: its MSL class, or stiction's own (``stiction.SlipWheel``)."""
        if self.msl_class.startswith("stiction."):
            return "stiction's own component (not in the MSL)."
        return f"MSL class: ``{self.msl_class}``"

    def signature(self) -> inspect.Signature:
        """Keyword-only parameters with their types; MSL defaults shown, required ones bare."""
        params = []
        for p in self.parameters:
            default: Any = inspect.Parameter.empty if p.required else p.default
            annotation = p.annotation
            if "start" in p.kind or p.kind in ("String", "record"):
                default, annotation = None, f"{annotation} | None"  # not given: a guess / no file
            params.append(
                inspect.Parameter(
                    p.name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation
                )
            )
        return inspect.Signature(params, return_annotation=None)

    def __str__(self) -> str:
        return f"{self.name}\n{'=' * len(self.name)}\n{self.docstring()}"


def _unit_text(unit: str) -> str:
    """`` [K] (displayUnit degC)``, `` [N.m]`` or nothing."""
    shown = display_unit(unit)
    return f" [{unit}] (displayUnit {shown})" if shown else f" [{unit}]" if unit else ""


def _suggest(word: str, choices: list[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=3)
    return f" (did you mean {', '.join(repr(c) for c in close)}?)" if close else ""


def _info(raw: dict[str, Any]) -> ComponentInfo:
    params = tuple(
        Parameter(
            name=p["name"],
            kind=p["kind"],
            default=p["default"],
            required=p["required"],
            unit=p["unit"],
            description=p["description"],
            range=p["range"],
            choices=tuple(p.get("choices", ())),
            tunable=p["tunable"],
        )
        for p in raw["parameters"]
    )
    return ComponentInfo(
        name=raw["name"],
        msl_class=raw["msl_class"],
        description=raw["description"],
        parameters=params,
        ports=tuple(Port(*p) for p in raw["ports"]),
        variables=tuple(Variable(*v) for v in raw["variables"]),
    )


@functools.cache
def catalogue() -> dict[str, ComponentInfo]:
    """Every component type the engine knows, by type name, in the engine's order."""
    core = importlib.import_module("stiction._core")
    return {raw["name"]: _info(raw) for raw in core.catalogue()}


def describe(type_name: str) -> ComponentInfo:
    """The reference of one component type; ``print(st.describe("Brake"))`` reads it.

    Raises ModelError (with suggestions) for an unknown type.
    """
    known = catalogue()
    if type_name not in known:
        raise ModelError(f"unknown component type '{type_name}'{_suggest(type_name, list(known))}")
    return known[type_name]


def unit_of(variable: str, types: dict[str, str]) -> str:
    """The unit of a result variable (``brake.tau`` → ``N.m``) given component → type names.

    System-wide variables (``system.kineticEnergy``) are in joules; unknown names give "".
    """
    if variable.startswith("system."):
        return "J"
    component = owner(variable, types) or ""
    rest = variable[len(component) + 1 :]
    info = catalogue().get(types.get(component, ""))
    if info is None:
        return ""
    return next((v.unit for v in info.variables if v.name == rest), "")
