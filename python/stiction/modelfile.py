"""The TOML model file: parsing it into plain data and writing it back.

Only syntax and shape live here (which keys exist, what kind of value each holds);
whether a component type, parameter or port exists is checked by ``Model``, with the
engine's catalogue. The writer puts ``name`` and ``connect`` at the top (before any
table, as TOML requires for top-level keys) and one inline table per component, the
layout a person would write.
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from collections.abc import Iterable, Mapping
from typing import Any, NamedTuple

import tomli_w

from .errors import ModelError

__all__ = ["EXPERIMENT_KEYS", "FORMAT_VERSION", "ModelData", "dumps", "parse"]

EXPERIMENT_KEYS = (
    "StartTime",
    "StopTime",
    "Interval",
    "Tolerance",
    "Solver",
    "max_events",
    "max_steps",
    "timeout",
)
# The model file format written here; every older one is read, a newer one refused by name.
FORMAT_VERSION = 1
_TOP_KEYS = (
    "format",
    "name",
    "connect",
    "inputs",
    "experiment",
    "parameters",
    "declarations",
    "components",
    "variables",
)
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
_INLINE_MAX = 110  # longer components are written as [components.<name>] sections instead


class ModelData(NamedTuple):
    """A model file's content, shape-checked but not yet checked against the engine."""

    name: str | None
    experiment: dict[str, Any]
    components: list[tuple[str, str, dict[str, Any]]]  # (name, type, parameters)
    connections: list[tuple[str, str]]
    inputs: dict[str, float]  # model input port -> start value
    variables: dict[str, str]  # derived variable -> Modelica expression over result variables
    parameters: dict[str, Any]  # top-level parameter -> value or expression text
    # top-level parameter -> its Modelica declaration beyond the value: type, description, unit…
    declarations: dict[str, dict[str, Any]]


def _suggest(word: str, choices: Iterable[str]) -> str:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _connections(value: Any, where: str) -> list[tuple[str, str]]:
    if not isinstance(value, list):
        raise ModelError(f'{where}: \'connect\' must be an array of ["a.port", "b.port"] pairs')
    pairs = []
    for i, pair in enumerate(value):
        if not isinstance(pair, list) or len(pair) != 2 or not all(isinstance(end, str) for end in pair):
            raise ModelError(
                f'{where}: connect[{i}] must be a pair of "component.port" strings, got {pair!r}'
            )
        pairs.append((pair[0], pair[1]))
    return pairs


def _inputs(value: Any, where: str) -> dict[str, float]:
    if not isinstance(value, list):
        raise ModelError(f"{where}: 'inputs' must be an array of ports (\"brake.f_normalized\")")
    inputs: dict[str, float] = {}
    for i, item in enumerate(value):
        if isinstance(item, str):
            port, start = item, 0.0
        elif isinstance(item, dict) and isinstance(item.get("port"), str) and set(item) <= {"port", "start"}:
            port, start = item["port"], item.get("start", 0.0)
        else:
            raise ModelError(
                f'{where}: inputs[{i}] must be "component.port" or {{ port = "component.port", start = 0.0 }}'
            )
        if isinstance(start, bool) or not isinstance(start, (int, float)):
            raise ModelError(f"{where}: inputs[{i}]: start must be a number, got {start!r}")
        inputs[port] = float(start)
    return inputs


def _check_format(value: Any, where: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ModelError(f"{where}: 'format' must be a format version (an integer from 1)")
    if value > FORMAT_VERSION:
        raise ModelError(
            f"{where}: model file format {value} is newer than this version of stiction reads "
            f"(format {FORMAT_VERSION}); update stiction"
        )


def _load_toml(text: str, source: str) -> dict[str, Any]:
    """The TOML document: parsed in the engine when it is there (a model of thousands of
    components took 0.3 s in ``tomllib``), else, and for every error message, by ``tomllib``."""
    try:
        from . import _core
    except ImportError:  # the pure-Python package (tests of the file format alone)
        doc = None
    else:
        doc = _core.parse_toml(text)
    if doc is not None:
        return doc
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(f"{source}: invalid TOML: {exc}") from None


def parse(text: str, source: str = "model") -> ModelData:
    """Parse model-file text; ``source`` (usually the path) prefixes error messages."""
    doc = _load_toml(text, source)

    for key in doc:
        if key not in _TOP_KEYS:
            raise ModelError(
                f"{source}: unknown top-level key '{key}'{_suggest(key, _TOP_KEYS)}; "
                f"expected {', '.join(_TOP_KEYS)}"
            )
    if "format" in doc:
        _check_format(doc["format"], source)
    name = doc.get("name")
    if name is not None and not isinstance(name, str):
        raise ModelError(f"{source}: 'name' must be a string, got {name!r}")

    experiment = doc.get("experiment", {})
    if not isinstance(experiment, dict):
        raise ModelError(f"{source}: 'experiment' must be a table")
    for key, value in experiment.items():
        if key not in EXPERIMENT_KEYS:
            raise ModelError(f"{source}: experiment: unknown setting '{key}'{_suggest(key, EXPERIMENT_KEYS)}")
        wanted = str if key == "Solver" else (int, float)
        if isinstance(value, bool) or not isinstance(value, wanted):
            raise ModelError(f"{source}: experiment: '{key}' has the wrong kind of value {value!r}")

    connections = _connections(doc["connect"], source) if "connect" in doc else []
    inputs = _inputs(doc["inputs"], source) if "inputs" in doc else {}
    components: list[tuple[str, str, dict[str, Any]]] = []
    table = doc.get("components", {})
    if not isinstance(table, dict):
        raise ModelError(f"{source}: 'components' must be a table")
    for comp_name, entry in table.items():
        if comp_name == "connect" and isinstance(entry, list):
            # `connect = [...]` written after [components] lands here; accept it.
            connections.extend(_connections(entry, source))
            continue
        if comp_name == "inputs" and isinstance(entry, list):
            inputs.update(_inputs(entry, source))
            continue
        if not isinstance(entry, dict):
            raise ModelError(
                f"{source}: component '{comp_name}': expected a table like "
                f'{{ type = "Inertia", J = 1.0 }}, got {entry!r}'
            )
        params = dict(entry)
        comp_type = params.pop("type", None)
        if not isinstance(comp_type, str):
            raise ModelError(f"{source}: component '{comp_name}': missing 'type' (a string)")
        components.append((comp_name, comp_type, params))
    variables, parameters = _variables_and_parameters(doc, source)
    declarations = _declarations(doc, parameters, source)
    return ModelData(
        name, dict(experiment), components, connections, inputs, variables, parameters, declarations
    )


DECLARATION_KEYS = ("type", "description", "unit", "displayUnit", "quantity", "min", "max", "nominal")


def _declarations(doc: dict[str, Any], parameters: dict[str, Any], source: str) -> dict[str, dict[str, Any]]:
    """The ``[declarations]`` table: for a top-level parameter, what its Modelica declaration
    says beyond the value (``type``, ``description``, ``unit``, ``min``…), kept so that an
    imported model exports as it was declared; the engine never reads it."""
    table = doc.get("declarations", {})
    if not isinstance(table, dict):
        raise ModelError(f"{source}: 'declarations' must be a table, e.g. J = {{ unit = \"kg.m2\" }}")
    for name, entry in table.items():
        if name not in parameters:
            raise ModelError(
                f"{source}: declarations: '{name}' is not a parameter{_suggest(name, parameters)}"
            )
        if not isinstance(entry, dict):
            raise ModelError(f"{source}: declarations: '{name}' must be a table, e.g. {{ unit = \"s\" }}")
        for key, value in entry.items():
            if key not in DECLARATION_KEYS:
                raise ModelError(
                    f"{source}: declarations: '{name}': unknown key '{key}'{_suggest(key, DECLARATION_KEYS)}"
                )
            if isinstance(value, bool) or not isinstance(value, (str, int, float)):
                raise ModelError(f"{source}: declarations: '{name}.{key}' must be text or a number")
    return {name: dict(entry) for name, entry in table.items()}


def _variables_and_parameters(doc: dict[str, Any], source: str) -> tuple[dict[str, str], dict[str, Any]]:
    """The ``[variables]`` (derived, expression text) and ``[parameters]`` tables, shape-checked."""
    variables = doc.get("variables", {})
    if not isinstance(variables, dict) or not all(isinstance(v, str) for v in variables.values()):
        raise ModelError(f"{source}: 'variables' must be a table of expressions, e.g. dw = \"J1.w - J2.w\"")
    parameters = doc.get("parameters", {})
    if not isinstance(parameters, dict):
        raise ModelError(f"{source}: 'parameters' must be a table, e.g. T2 = 0.4, w = \"2*T2\"")
    for key, value in parameters.items():
        if not isinstance(value, (bool, int, float, str, list)):
            raise ModelError(f"{source}: parameters: '{key}' must be a number, Boolean or expression text")
    return dict(variables), dict(parameters)


# --- writing --------------------------------------------------------------------------
# strings TOML writes between double quotes as they are
_PLAIN_STRING = re.compile(r"[ !#-\[\]-~]*")


def _key(key: str) -> str:
    return key if _BARE_KEY.fullmatch(key) else _scalar(key)


def _scalar(value: Any) -> str:
    # The common cases spelled directly (a model of thousands of components writes tens of
    # thousands of scalars); tomli-w knows the exact TOML spelling of the rest (escapes, inf, nan).
    kind = type(value)
    if kind is bool:
        return "true" if value else "false"
    if kind is int:
        return str(value)
    if kind is float and math.isfinite(value):
        return repr(value)
    if kind is str and _PLAIN_STRING.fullmatch(value):
        return f'"{value}"'
    return tomli_w.dumps({"v": value})[len("v = ") : -1]


def _value(value: Any, multiline: bool = False) -> str:
    if isinstance(value, Mapping):
        if not value:
            return "{}"
        return "{ " + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, (list, tuple)):
        items = [_value(v) for v in value]
        if multiline and items:
            return "[\n" + "".join(f"  {item},\n" for item in items) + "]"
        return "[" + ", ".join(items) + "]"
    return _scalar(value)


def dumps(
    name: str,
    experiment: Mapping[str, Any],
    components: Iterable[tuple[str, str, Mapping[str, Any]]],
    connections: Iterable[tuple[str, str]],
    inputs: Mapping[str, float] | None = None,
    variables: Mapping[str, str] | None = None,
    parameters: Mapping[str, Any] | None = None,
    declarations: Mapping[str, Mapping[str, Any]] | None = None,
) -> str:
    """Write a model file; it parses back to the same data."""
    lines = [f"format = {FORMAT_VERSION}", f"name = {_scalar(name)}"]
    pairs = list(connections)
    if pairs:
        lines.append("connect = [")
        lines.extend(f"  [{_scalar(a)}, {_scalar(b)}]," for a, b in pairs)
        lines.append("]")
    else:
        lines.append("connect = []")
    if inputs:
        lines.append("inputs = [")
        lines.extend(f"  {{ port = {_scalar(p)}, start = {_scalar(float(v))} }}," for p, v in inputs.items())
        lines.append("]")
    if experiment:
        lines += ["", "[experiment]"]
        lines.extend(f"{_key(k)} = {_value(v)}" for k, v in experiment.items())
    if parameters:
        lines += ["", "[parameters]"]
        lines.extend(f"{_key(k)} = {_value(v)}" for k, v in parameters.items())
    if declarations:
        lines += ["", "[declarations]"]
        lines.extend(f"{_key(k)} = {_value(dict(v))}" for k, v in declarations.items())
    if variables:
        lines += ["", "[variables]"]
        lines.extend(f"{_key(k)} = {_scalar(v)}" for k, v in variables.items())

    comps = [(n, {"type": t, **dict(p)}) for n, t, p in components]
    keys = [_key(n) for n, _ in comps]
    values = [_value(entry) for _, entry in comps]  # written once: thousands of components
    if all(len(k) + 3 + len(v) <= _INLINE_MAX for k, v in zip(keys, values, strict=True)):
        width = max(map(len, keys), default=0)
        lines += ["", "[components]"]
        lines.extend(f"{k:<{width}} = {v}" for k, v in zip(keys, values, strict=True))
    else:  # long tables: one section per component keeps the file readable
        for comp_name, entry in comps:
            lines += ["", f"[components.{_key(comp_name)}]"]
            lines.extend(f"{_key(k)} = {_value(v, multiline=True)}" for k, v in entry.items())
    return "\n".join(lines) + "\n"
