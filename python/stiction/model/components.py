"""Component descriptions: a type name plus parameter values, nothing more.

A component here is data, not behaviour; the engine owns the physics. Values are
normalised at construction to what a TOML model file can hold (numbers, booleans,
strings, arrays, small tables), so a model built in Python and one loaded from a file
are indistinguishable. A quantity with a unit (``J="2 kg*m^2"``, ``w="1500 rpm"``) is
converted then to the parameter's SI unit, and a table's expression cells are kept as
expression text (``in_si``; ``stiction.model.quantities``, ``stiction.model.parameters``).
"""

from __future__ import annotations

import functools
import importlib
import numbers
import os
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar, Union

from stiction.errors import ModelError
from stiction.model.catalogue import ComponentInfo, Parameter, catalogue
from stiction.model.names import split_last
from stiction.model.parameters import table_cells
from stiction.model.quantities import to_si

__all__ = [
    "FACTORIES",
    "START_VARIABLES",
    "Component",
    "ParamValue",
    "StartValue",
    "component_types",
    "factory",
    "in_si",
    "si_overrides",
    "table_1ds_ports",
    "time_table_ports",
]

StartValue = Mapping[str, float | bool]
"""A start value with its flag, ``{"start": 10.0, "fixed": False}``; a bare number is fixed.
``"nominal": 1e-4`` (positive) scales the integrator's absolute tolerance of the states the
variable is made of to Tolerance·nominal."""

ParamValue = Union[bool, int, float, str, Sequence[Any], Mapping[str, Any], "os.PathLike[str]"]

# Variables with a start value and fixedness rather than a parameter value: in Python
# ``w={"start": 10.0, "fixed": False}``, in Modelica ``phi(start=0, fixed=true)``.
START_VARIABLES = frozenset(
    [
        "phi",
        "w",
        "a",
        "s",
        "v",
        "phi_rel",
        "w_rel",
        "a_rel",
        "s_rel",
        "v_rel",
        "startForward",
        "startBackward",
        "stuck",
        "locked",
        "T",
        "mode",
        "free",
    ]
)

_PLAIN = frozenset((float, int, bool, str))
_NUMBERS = frozenset((float, int, bool))
type_of = type  # `type` is Component.__init__'s argument (MSL's word): the builtin by another name


def normalize_value(value: Any, where: str) -> Any:
    """Turn a parameter value into TOML-able data, or raise ModelError naming it."""
    if type(value) in _PLAIN:  # the common cases, before the slower abstract-class checks
        return value
    if type(value) is dict:
        return _normalize_table(value, where)
    if isinstance(value, bool):
        return value
    if type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "tolist") and not isinstance(value, (list, tuple)):  # numpy arrays
        return normalize_value(value.tolist(), where)
    if isinstance(value, Mapping):
        return _normalize_table(value, where)
    if isinstance(value, (list, tuple)):
        return [normalize_value(item, where) for item in value]
    raise ModelError(f"{where}: unsupported value {value!r} ({type(value).__name__})")


def _normalize_table(value: Mapping[Any, Any], where: str) -> dict[str, Any]:
    out = {}
    for key, item in value.items():
        if not isinstance(key, str):
            raise ModelError(f"{where}: table keys must be strings, got {key!r}")
        out[key] = normalize_value(item, f"{where}.{key}")
    return out


class Component:
    """One component: an MSL-like type name and its parameter values.

    ``Component("Inertia", {"J": 2.0})`` works for any type the engine knows; the
    subclasses below (``Inertia(J=2.0)``) are the same with the type filled in.
    """

    type_name: ClassVar[str | None] = None
    __hash__ = None  # type: ignore[assignment]  # mutable

    def __init__(self, type: str, params: Mapping[str, Any] | None = None) -> None:
        if not isinstance(type, str) or not type:
            raise ModelError(f"component type must be a non-empty string, got {type!r}")
        self.type: str = type
        self.params: dict[str, Any] = {}
        for key, value in (params or {}).items():
            if not isinstance(key, str) or not key:
                raise ModelError(f"{type}: parameter names must be non-empty strings, got {key!r}")
            if key == "type":
                raise ModelError(f"{type}: 'type' is reserved and cannot be a parameter name")
            if type_of(value) in _NUMBERS:  # most values: kept as they are, no message made
                self.params[key] = value
                continue
            where = f"{type}: parameter '{key}'"
            value = normalize_value(value, where)
            self.params[key] = value if type_of(value) in _NUMBERS else in_si(type, key, value, where)
        _check_ranges(type, self.params)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        # a namespaced class (``stiction.translational.Mass``) names its dotted type itself
        cls.type_name = cls.__dict__.get("_type_name", cls.__name__)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Component):
            return NotImplemented
        return self.type == other.type and self.params == other.params

    def __repr__(self) -> str:
        if type(self).type_name == self.type:
            args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
            space, _, name = self.type.rpartition(".")
            return f"{NAMESPACES.get(space, space) + '.' if space else ''}{name}({args})"
        return f"Component({self.type!r}, {self.params!r})"


def _known_types() -> dict[str, ComponentInfo] | None:
    """The engine's catalogue, or None in a source tree without the compiled engine (a broken
    build still fails)."""
    try:
        return catalogue()
    except ModuleNotFoundError as exc:
        if exc.name != "stiction._core":
            raise
        return None


@functools.cache
def _parameters_of(type_name: str) -> dict[str, Parameter]:
    """Every parameter of a type by name (none for an unknown type or without the engine)."""
    info = (_known_types() or {}).get(type_name)
    return {p.name: p for p in info.parameters} if info else {}


def in_si(type_name: str, key: str, value: Any, where: str) -> Any:
    """A parameter value with its quantities in the parameter's unit: ``"20 kN"`` → 20000.0
    for a Real in N, ``"1500 rpm"`` (or ``{"start": "1500 rpm", …}``) for a start value in
    rad/s; a table's cells (quantities in their column's unit, expressions kept as text, see
    ``table_cells``). Other values, and those of unknown parameters, are returned as they are."""
    param = _parameters_of(type_name).get(key)
    if param is None:
        return value
    if param.kind in ("Real", "start value") and type_of(value) is str:
        return to_si(value, param.unit, where)
    if param.kind == "start value" and isinstance(value, dict) and type_of(value.get("start")) is str:
        return {**value, "start": to_si(value["start"], param.unit, f"{where}: start")}
    if param.kind.startswith("table"):
        return table_cells(value, [u.strip() for u in param.unit.split(",")], where)
    return value


# experiment settings that are times: a sweep may vary StopTime = "2 min"
_EXPERIMENT_UNITS = {"StartTime": "s", "StopTime": "s", "Interval": "s", "timeout": "s"}


def si_overrides(components: Mapping[str, Component], overrides: Mapping[str, Any]) -> dict[str, Any]:
    """A run's overrides (``{"J1.w": "100 rpm", "brake.mu_pos": [[0, "mu0"]]}``) with their
    quantities converted as ``in_si`` converts a component's; top-level parameters are left to
    ``evaluate_parameters`` (it reads ``"100 rpm"`` there too), numbers as they are."""
    out = dict(overrides)
    for name, value in overrides.items():
        if type_of(value) in _NUMBERS:
            continue
        comp_name, key = split_last(name)
        comp = components.get(comp_name) if key else None
        if comp is not None:
            where = f"component '{comp_name}' ({comp.type}): parameter '{key}'"
            out[name] = in_si(comp.type, key, normalize_value(value, where), where)
        elif name in _EXPERIMENT_UNITS and type_of(value) is str:
            out[name] = to_si(value, _EXPERIMENT_UNITS[name], f"experiment: '{name}'")
    return out


@functools.cache
def _ranged_parameters(type_name: str) -> dict[str, Parameter]:
    """The parameters of a type that have a range, by name."""
    return {name: p for name, p in _parameters_of(type_name).items() if p.range is not None}


def _check_ranges(type_name: str, params: Mapping[str, Any]) -> None:
    """Refuse a number outside its parameter's range now (``Inertia(J=-1.2)``), with the
    engine's words, as ``Model.set`` and a model file do; tables, expressions and unknown names
    are the engine's to check when it reads the model."""
    ranged = _ranged_parameters(type_name)
    for key, value in params.items():
        problem = ranged[key].violation(value) if key in ranged else None
        if problem:
            raise ModelError(f"{type_name}: parameter '{key}': {problem}")


class _Factory(Component):
    """Base of the typed factories: keyword arguments are the parameters."""

    def __init__(self, **params: Any) -> None:
        super().__init__(type(self).type_name or "", params)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        FACTORIES[cls.type_name or cls.__name__] = cls


FACTORIES: dict[str, type[Component]] = {}

# The dotted type names' prefixes that are Python namespaces (``Translational.Mass`` is
# ``stiction.translational.Mass``), and each namespace's module.
NAMESPACES = {"Translational": "translational"}


def _make_class(info: ComponentInfo, module: str = __name__) -> type[Component]:
    """The class of one engine type: its docstring and signature come from the catalogue; a
    dotted type (``Translational.Mass``) is the class ``Mass`` of its namespace ``module``."""
    short = info.name.rpartition(".")[2]
    body = {"__doc__": info.docstring(), "__module__": module, "_type_name": info.name}
    cls = type(short, (_Factory,), body)
    cls.__signature__ = info.signature()  # type: ignore[attr-defined]  # help(), IDEs
    return cls


def namespace_classes(space: str) -> dict[str, type[Component]]:
    """The classes of the types ``space.X`` (``Translational``), by their short names, made
    once: ``stiction.translational`` is these."""
    known = _known_types() or {}
    module = f"stiction.{NAMESPACES[space]}"
    classes = {}
    for name, info in known.items():
        head, _, short = name.rpartition(".")
        if head == space and short.isidentifier():
            classes[short] = FACTORIES.get(name) or _make_class(info, module)
    return classes


def _make_classes() -> dict[str, type[Component]]:
    """One class per engine type whose name is a Python identifier (not Celsius.…)."""
    known = _known_types() or {}
    return {name: _make_class(info) for name, info in known.items() if name.isidentifier()}


globals().update(_make_classes())  # Inertia, Brake, …: listed in components.pyi


@functools.cache
def component_types() -> dict[str, dict[str, list[str]]] | None:
    """Give the engine's types with their parameter and port names; None if not built."""
    known = _known_types()
    if known is None:
        return None
    return {
        name: {"parameters": [p.name for p in info.parameters], "ports": [p.name for p in info.ports]}
        for name, info in known.items()
    }


def factory(type_name: str) -> type[Component]:
    """Give the factory class of a type; engine types without one get one made."""
    if type_name in FACTORIES:
        return FACTORIES[type_name]
    space = type_name.rpartition(".")[0]
    if space in NAMESPACES:  # its namespace module makes the class (``Translational.Mass``)
        importlib.import_module(f"stiction.{NAMESPACES[space]}")
        if type_name in FACTORIES:
            return FACTORIES[type_name]
    known = component_types()
    if known is None or type_name not in known or not type_name.isidentifier():
        raise AttributeError(type_name)
    cls = type(
        type_name,
        (_Factory,),
        {"__doc__": f"{type_name} (engine type).", "__module__": __name__},
    )
    return cls


def table_1ds_ports(params: Mapping[str, Any]) -> list[str]:
    """A CombiTable1Ds's ports: its input ``u`` and one output ``y[1]``…``y[k]`` per entry
    of ``columns`` (default: every value column of its table), always indexed as MSL's
    output vector is."""
    outputs = time_table_ports(params)
    return ["u", *(["y[1]"] if outputs == ["y"] else outputs)]


def time_table_ports(params: Mapping[str, Any]) -> list[str]:
    """A TimeTable's outputs: ``y`` for one output column, ``y[1]``…``y[k]`` for its
    ``columns`` (default: every value column of its table)."""
    if isinstance(params.get("columns"), list):
        count = len(params["columns"])
    else:
        table = params.get("table")
        rows = [r for r in table if isinstance(r, list)] if isinstance(table, list) else []
        count = max(len(rows[0]) - 1, 1) if rows else 1
    return ["y"] if count == 1 else [f"y[{i}]" for i in range(1, count + 1)]
