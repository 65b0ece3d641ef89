"""Derived variables: result columns computed from a run by a Modelica expression.

``SI.Power PowerLoss = gear.flange_a.tau*der(gear.flange_a.phi) + …`` in a ``.mo`` model
(or ``[variables] PowerLoss = "…"`` in a model file) adds the result variable ``PowerLoss``.
The engine computes them (``crates/stiction-core/src/system/variables.rs``): the model's
engine text carries ``[variables]``, so a derived variable is a result variable like any
other — in ``Result``, in metrics and sweeps, as an FMU output. ``der(x)`` is exact, never a
finite difference: the recorded derivative (``J.phi`` → ``J.w``, a flange's angle → its
speed, ``J.w`` → ``J.a``). A result read from a file has the columns as they were written.

Here only the check the Modelica importer makes of a binding's names, so that a wrong one is
refused at its line and column (the engine refuses it too, without a place).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from stiction.expressions.ast import Expr
    from stiction.model.model import Model

__all__ = ["check_expression"]


def check_expression(expr: Expr, model: Model, resolve: Callable[..., str], params: set[str]) -> None:
    """Refuse at import a name that cannot be a result variable of ``model``."""
    from stiction.expressions.ast import Array, BinOp, Call, IfExpr, Matrix, Ref, Unary
    from stiction.expressions.lexer import ModelicaError
    from stiction.model.names import owner

    def walk(e: Any) -> None:
        if isinstance(e, Ref):
            head = owner(e.name, model.components) or e.name.split(".")[0]
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
