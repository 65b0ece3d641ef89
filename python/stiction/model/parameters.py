"""Top-level parameters: named values and expressions the components' parameters refer to.

``[parameters]`` in a model file (``Model.parameters``) holds numbers, Booleans and
expressions (a string is a Modelica expression over other parameters: ``w = "2*T2"``); a
component parameter refers to them with ``{ expr = "T2" }`` (``st.expr("T2")`` in Python).
Before the engine sees the model every expression is evaluated — in any order, cycles refused
— so changing ``T2`` for a run (a sweep) recomputes everything that depends on it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from stiction.errors import ModelError

__all__ = ["evaluate_parameters", "expand_parameters", "expr", "is_expr", "resolve_params"]


def expr(text: str) -> dict[str, str]:
    """A parameter value computed from top-level parameters: ``st.Step(startTime=st.expr("T2"))``."""
    if not isinstance(text, str) or not text.strip():
        raise ModelError(f"an expression must be non-empty text, got {text!r}")
    return {"expr": text}


_PLAIN = frozenset((float, int, bool, str))


def is_expr(value: Any) -> bool:
    """Whether a parameter value is ``{ expr = "…" }``."""
    if type(value) in _PLAIN:  # most values, before the slower abstract-class check
        return False
    return isinstance(value, Mapping) and set(value) == {"expr"} and isinstance(value["expr"], str)


def _evaluate(text: str, where: str, lookup: Any) -> Any:
    from stiction.expressions.evaluate import CONSTANTS, evaluate, python_value
    from stiction.expressions.lexer import ModelicaError
    from stiction.expressions.parser import parse_expression

    def name(ref: Any) -> Any:
        if ref.name in CONSTANTS:
            return CONSTANTS[ref.name]
        return lookup(ref.name)

    try:
        return python_value(evaluate(parse_expression(text, where), name, lambda n, _p: n))
    except ModelicaError as exc:
        raise ModelError(f"{where}: {exc.detail} in '{text}'") from None
    except ModelError as exc:
        message = str(exc)
        raise ModelError(message if message.startswith("parameter '") else f"{where}: {message}") from None


def evaluate_parameters(parameters: Mapping[str, Any]) -> dict[str, Any]:
    """The value of every top-level parameter (strings are expressions over the others)."""
    values: dict[str, Any] = {}
    active: list[str] = []

    def value(name: str) -> Any:
        if name in values:
            return values[name]
        if name not in parameters:
            raise ModelError(f"unknown parameter '{name}'")
        if name in active:
            raise ModelError(f"parameter '{name}': cyclic definition {' -> '.join([*active, name])}")
        raw = parameters[name]
        if isinstance(raw, str):
            active.append(name)
            raw = _evaluate(raw, f"parameter '{name}'", value)
            active.pop()
        values[name] = raw
        return raw

    for name in parameters:
        value(name)
    return values


def resolve_params(comp: str, params: Mapping[str, Any], values: Mapping[str, Any]) -> dict[str, Any]:
    """A component's parameters with every ``{ expr = "…" }`` replaced by its value."""

    def lookup(name: str) -> Any:
        if name not in values:
            raise ModelError(f"no parameter '{name}' in the model")
        return values[name]

    def resolve(raw: Any, where: str) -> Any:
        if type(raw) in _PLAIN:
            return raw
        if is_expr(raw):
            result = _evaluate(raw["expr"], where, lookup)
            return float(result) if type(result) is int else result
        if isinstance(raw, Mapping):  # a start value: { start = { expr = "w0" }, fixed = true }
            return {k: resolve(v, f"{where}.{k}") for k, v in raw.items()}
        return raw

    # plain values (nearly all) skip `resolve` and the message it would carry
    return {
        key: raw if type(raw) in _PLAIN else resolve(raw, f"component '{comp}': parameter '{key}'")
        for key, raw in params.items()
    }


def expand_parameters(
    parameters: Mapping[str, Any], components: Mapping[str, Any], overrides: Mapping[str, Any]
) -> dict[str, Any]:
    """Overrides with the top-level parameters among them (``T2``) turned into the component
    values they imply: every expression is evaluated again, and what changed is overridden.
    ``components`` maps names to objects with ``params`` (``Model.components``)."""
    top = {k: v for k, v in overrides.items() if k in parameters}
    if not top:
        return dict(overrides)
    base = evaluate_parameters(parameters)
    varied = evaluate_parameters({**parameters, **top})
    out = {k: v for k, v in overrides.items() if k not in top}
    for name, comp in components.items():
        before = resolve_params(name, comp.params, base)
        for key, value in resolve_params(name, comp.params, varied).items():
            if before.get(key) != value and f"{name}.{key}" not in out:
                out[f"{name}.{key}"] = value
    return out
