"""Top-level parameters: named values and expressions the components' parameters refer to.

``[parameters]`` in a model file (``Model.parameters``) holds numbers, Booleans and
expressions (a string is a Modelica expression over other parameters: ``w = "2*T2"``); a
component parameter refers to them with ``{ expr = "T2" }`` (``st.expr("T2")`` in Python).
Before the engine sees the model every expression is evaluated — in any order, cycles refused
— so changing ``T2`` for a run (a sweep) recomputes everything that depends on it.

A cell of a table may be an expression too, written as text (``mu_pos = [[0, "mu0"], [100,
"0.9*mu0"]]``; ``st.expr("mu0")`` in Python): a sweep over ``mu0`` moves the table. A
whole-table expression over parameters (``{ expr = "[0, mu0; 100, 0.9*mu0]" }``, what a
Modelica model writes) is kept as those cells (``table_cells``). A cell (or a top-level
parameter) that is a number with a unit (``"10 rpm"``) is a quantity, converted to SI
(``stiction.model.quantities``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from stiction.errors import ModelError
from stiction.model.names import split_last

__all__ = [
    "evaluate_parameters",
    "expand_parameters",
    "expr",
    "is_expr",
    "is_table",
    "resolve_params",
    "table_cells",
]


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


def is_table(value: Any) -> bool:
    """Whether a value is a table: a list of rows (lists)."""
    return type(value) is list and bool(value) and all(type(row) is list for row in value)


def _has_expressions(table: list[list[Any]]) -> bool:
    return any(type(cell) is not float and type(cell) is not int for row in table for cell in row)


def _literal_cells(text: str, where: str) -> list[list[Any]] | None:
    """The cells of a whole-table expression that is a matrix or an array of arrays written
    out (``[0, mu0; 100, 0.9*mu0]``), each a number or its expression text; None otherwise."""
    from stiction.expressions.ast import Array, Matrix
    from stiction.expressions.evaluate import unparse
    from stiction.expressions.lexer import ModelicaError
    from stiction.expressions.parser import parse_expression

    try:
        tree = parse_expression(text, where)
    except ModelicaError:
        return None
    if isinstance(tree, Matrix):
        rows = tree.rows
    elif isinstance(tree, Array) and tree.items and all(isinstance(r, Array) for r in tree.items):
        rows = [r.items for r in tree.items]  # type: ignore[attr-defined]
    else:
        return None
    return [[unparse(cell) for cell in row] for row in rows]


def _cell(cell: Any, unit: str, where: str) -> Any:
    """One table cell as the model keeps it: a number, or an expression's text written as its
    syntax tree writes it (``0.9 * mu0``); a quantity (``"10 rpm"``) in the column's unit."""
    from stiction.expressions.evaluate import unparse
    from stiction.expressions.lexer import ModelicaError
    from stiction.expressions.parser import parse_expression
    from stiction.model.quantities import is_quantity, to_si

    if is_expr(cell):
        cell = cell["expr"]
    if type(cell) is not str:
        return cell
    try:
        return float(cell)
    except ValueError:
        pass
    if is_quantity(cell):
        return to_si(cell, unit, where)
    try:
        return unparse(parse_expression(cell, where))
    except ModelicaError as exc:
        raise ModelError(f"{where}: {exc.detail} in '{cell}'") from None


def table_cells(value: Any, units: list[str], where: str) -> Any:
    """A table parameter as the model keeps it: numbers, expression text over top-level
    parameters (``"0.9 * mu0"``; an ``expr`` cell becomes its text), quantities converted to
    the unit of their column (``units``, the catalogue's). A whole-table expression written
    out as a matrix becomes its cells; anything else is returned as it is."""
    if is_expr(value):
        cells = _literal_cells(value["expr"], where)
        if cells is None:
            return value
        value = cells
    if not is_table(value) or not _has_expressions(value):
        return value
    return [
        [
            _cell(cell, units[j] if j < len(units) else "1", f"{where}: row {i + 1}, column {j + 1}")
            for j, cell in enumerate(row)
        ]
        for i, row in enumerate(value)
    ]


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
        if isinstance(raw, str) and _is_quantity(raw):  # "1500 rpm": in SI base units
            raw = _in_si_base(raw, f"parameter '{name}'")
        elif isinstance(raw, str):
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
        if is_table(raw) and _has_expressions(raw):  # [[0, "mu0"], [100, "0.9 * mu0"]]
            return [
                [
                    float(_evaluate(cell, f"{where}: row {i + 1}, column {j + 1}", lookup))
                    if type(cell) is str
                    else cell
                    for j, cell in enumerate(row)
                ]
                for i, row in enumerate(raw)
            ]
        return raw

    # plain values (nearly all) skip `resolve` and the message it would carry
    return {
        key: raw if type(raw) in _PLAIN else resolve(raw, f"component '{comp}': parameter '{key}'")
        for key, raw in params.items()
    }


def _is_quantity(text: str) -> bool:
    from stiction.model.quantities import is_quantity

    return is_quantity(text)


def _in_si_base(text: str, where: str) -> float:
    from stiction.model.quantities import si_base

    return si_base(text, where)


def expand_parameters(
    parameters: Mapping[str, Any], components: Mapping[str, Any], overrides: Mapping[str, Any]
) -> dict[str, Any]:
    """Overrides with the top-level parameters among them (``T2``) turned into the component
    values they imply: every expression is evaluated again, and what changed is overridden.
    ``components`` maps names to objects with ``params`` (``Model.components``)."""
    top = {k: v for k, v in overrides.items() if k in parameters}
    # a table given with expression cells for this run: evaluated with this run's parameters
    tables = [k for k, v in overrides.items() if k not in top and is_table(v) and _has_expressions(v)]
    if not top and not tables:
        return dict(overrides)
    base = evaluate_parameters(parameters)
    varied = evaluate_parameters({**parameters, **top}) if top else base
    out = {k: v for k, v in overrides.items() if k not in top}
    for name in tables:
        comp, key = split_last(name)
        out[name] = resolve_params(comp, {key: out[name]}, varied)[key]
    for name, comp in components.items():
        before = resolve_params(name, comp.params, base)
        for key, value in resolve_params(name, comp.params, varied).items():
            if before.get(key) != value and f"{name}.{key}" not in out:
                out[f"{name}.{key}"] = value
    return out
