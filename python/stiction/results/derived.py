"""Derived variables: result columns computed from a run by a Modelica expression.

``SI.Power PowerLoss = gear.flange_a.tau*der(gear.flange_a.phi) + …`` in a ``.mo`` model
(or ``[variables] PowerLoss = "…"`` in a model file) adds the column ``PowerLoss``. The
expression reads result variables by name, evaluated over all rows at once with NumPy.
``der(x)`` is exact, never a finite difference: the derivative of an angle is the speed
recorded with it (``J.phi`` → ``J.w``, ``c.phi_rel`` → ``c.w_rel``, ``J.w`` → ``J.a``), and
a flange angle's is the speed of an inertia or element side that moves with it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction.errors import ModelError

if TYPE_CHECKING:
    from stiction.expressions.ast import Expr, Ref
    from stiction.model.model import Model
    from stiction.results.result import Result

__all__ = ["check_expression", "derived_columns"]

_DERIVATIVES = {"phi": "w", "phi_rel": "w_rel", "w": "a", "w_rel": "a_rel", "phi_a": "w_a", "w_a": "a_a"}


def check_expression(expr: Expr, model: Model, resolve: Callable[..., str], params: set[str]) -> None:
    """Refuse at import a name that cannot be a result variable of ``model``."""
    from stiction.expressions.ast import Array, BinOp, Call, IfExpr, Matrix, Ref, Unary
    from stiction.expressions.lexer import ModelicaError

    def walk(e: Any) -> None:
        if isinstance(e, Ref):
            head = e.name.split(".")[0]
            known = head in model.components or e.name in params or e.name in model.variables
            if not known and not e.name.startswith("Modelica.") and e.name != "time":
                raise ModelicaError(e.pos, f"'{e.name}' is undefined: no component '{head}' in the model")
        elif isinstance(e, BinOp):
            walk(e.left)
            walk(e.right)
        elif isinstance(e, Unary):
            walk(e.operand)
        elif isinstance(e, IfExpr):
            for part in (e.cond, e.then, e.other):
                walk(part)
        elif isinstance(e, (Array, Matrix)):
            raise ModelicaError(e.pos, "array-valued variables are not supported")
        elif isinstance(e, Call):
            for arg in e.args:
                walk(arg)

    walk(expr)


def derived_columns(
    result: Result, variables: Mapping[str, str], parameters: Mapping[str, Any] | None = None
) -> dict[str, np.ndarray]:
    """The derived variables' columns over the result's rows, in declaration order;
    ``parameters`` (top-level, evaluated) may be used by name."""
    from stiction.expressions.evaluate import CONSTANTS, evaluate
    from stiction.expressions.lexer import ModelicaError
    from stiction.expressions.parser import parse_expression

    columns: dict[str, np.ndarray] = {}

    def lookup(ref: Ref) -> Any:
        if ref.name in columns:
            return columns[ref.name]
        if ref.name in CONSTANTS:
            return CONSTANTS[ref.name]
        if parameters and ref.name in parameters:
            return parameters[ref.name]
        if ref.name in result:
            return result[ref.name]
        raise ModelicaError(ref.pos, f"no variable '{ref.name}' in the result")

    def der(ref: Ref) -> Any:
        return _derivative(result, ref)

    for name, text in variables.items():
        try:
            expr = parse_expression(text, f"variable '{name}'")
            value = evaluate(expr, lookup, lambda n, _pos: n, der)
        except ModelError as exc:
            raise ModelError(f"derived variable '{name}' = {text}: {exc}") from None
        columns[name] = np.broadcast_to(np.asarray(value, dtype=np.float64), (len(result),)).copy()
    return columns


def _derivative(result: Result, ref: Ref) -> np.ndarray:
    from stiction.expressions.lexer import ModelicaError

    head, _, last = ref.name.rpartition(".")
    rate = f"{head}.{_DERIVATIVES.get(last, '')}"
    if rate in result:
        return result[rate]
    if last == "phi" and ref.name in result:  # a flange: find what moves with it
        angle = result[ref.name]
        for name in result.names:
            moving = name.endswith(".phi") and name != ref.name and f"{name[:-4]}.w" in result
            if moving and np.array_equal(result[name], angle):
                return result[f"{name[:-4]}.w"]
    raise ModelicaError(ref.pos, f"der({ref.name}): no recorded derivative of '{ref.name}'")
