"""Evaluating and writing Modelica expressions.

The evaluator of parameter expressions (scalars, when a model is read or a run starts);
arithmetic and functions are NumPy's, so it takes arrays too. Names are looked up through a
callback, which raises ModelicaError for an unknown one. Derived variables (a model's
``[variables]``) are evaluated by the engine (``crates/stiction-core/src/system/formula.rs``),
with the same functions (``FUNCTIONS``) and constants (``CONSTANTS``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from stiction.expressions.ast import Array, BinOp, Call, Expr, IfExpr, Literal, Matrix, Ref, Unary
from stiction.expressions.lexer import ModelicaError, Pos

__all__ = ["CONSTANTS", "FUNCTIONS", "MSL_CONSTANTS", "evaluate", "python_value", "unparse"]

CONSTANTS: dict[str, float] = {
    "Modelica.Constants.pi": math.pi,
    "Modelica.Constants.e": math.e,
    "Modelica.Constants.g_n": 9.80665,
    "Modelica.Constants.eps": 2.220446049250313e-16,
    "Modelica.Constants.small": 1e-60,
    "Modelica.Constants.T_zero": -273.15,
}
# The rest of MSL's constants, for parameter values only (the engine's derived variables know
# CONSTANTS; a derived variable using one of these is refused by name).
MSL_CONSTANTS: dict[str, float] = {
    **CONSTANTS,
    "Modelica.Constants.inf": 1e60,  # ModelicaServices.Machine.inf
    "Modelica.Constants.D2R": math.pi / 180,
    "Modelica.Constants.R2D": 180 / math.pi,
    "Modelica.Constants.gamma": 0.57721566490153286060,
    # constants of nature as MSL 4.x states them (CODATA 2018)
    "Modelica.Constants.c": 299792458.0,
    "Modelica.Constants.G": 6.67430e-11,
    "Modelica.Constants.F": 9.648533212e4,
    "Modelica.Constants.h": 6.62607015e-34,
    "Modelica.Constants.k": 1.380649e-23,
    "Modelica.Constants.q": 1.602176634e-19,
    "Modelica.Constants.R": 8.314462618,
    "Modelica.Constants.sigma": 5.670374419e-8,
    "Modelica.Constants.N_A": 6.02214076e23,
    "Modelica.Constants.mu_0": 1.25663706212e-6,
    "Modelica.Constants.epsilon_0": 1 / (1.25663706212e-6 * 299792458.0**2),
    # conductor materials' temperature coefficients (Modelica.Electrical.Machines.Thermal)
    **{
        f"Modelica.Electrical.Machines.Thermal.Constants.alpha20{name}": value
        for name, value in (
            ("Zero", 0.0),
            ("Aluminium", 4.0e-3),
            ("Brass", 1.1e-3),
            ("Bronze", 0.8e-3),
            ("Copper", 3.92e-3),
        )
    },
}
_RPM = 2 * math.pi / 60
FUNCTIONS: dict[str, Callable[..., Any]] = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "asin": np.arcsin,
    "acos": np.arccos,
    "atan": np.arctan,
    "atan2": np.arctan2,
    "sinh": np.sinh,
    "cosh": np.cosh,
    "tanh": np.tanh,
    "exp": np.exp,
    "log": np.log,
    "log10": np.log10,
    "sqrt": np.sqrt,
    "abs": np.abs,
    "sign": np.sign,
    "floor": np.floor,
    "ceil": np.ceil,
    "max": np.maximum,
    "min": np.minimum,
    "Modelica.Units.Conversions.from_rpm": lambda x: x * _RPM,
    "Modelica.Units.Conversions.to_rpm": lambda x: x / _RPM,
    "Modelica.Units.Conversions.from_degC": lambda x: x + 273.15,
    "Modelica.Units.Conversions.to_degC": lambda x: x - 273.15,
    "Modelica.Units.Conversions.from_deg": lambda x: x * math.pi / 180,
    "Modelica.Units.Conversions.to_deg": lambda x: x * 180 / math.pi,
}
for _name in list(FUNCTIONS):
    if "." not in _name:
        FUNCTIONS[f"Modelica.Math.{_name}"] = FUNCTIONS[_name]


def _stribeck_table(
    F_prop: float, F_Coulomb: float, F_Stribeck: float, fexp: float, v_max: float, nTable: int = 100
) -> np.ndarray:
    """MSL's ``Translational.Examples.Utilities.GenerateStribeckFrictionTable``: ``nTable`` rows
    ``[v, F_Coulomb + F_prop·v + F_Stribeck·exp(−fexp·v)]`` for v evenly from 0 to ``v_max``."""
    n = int(nTable)
    if n != nTable or n < 2:
        raise ValueError(f"nTable = {nTable} must be an integer >= 2")
    v = np.array([v_max * (i - 1) / (n - 1) for i in range(1, n + 1)])
    return np.column_stack([v, F_Coulomb + F_prop * v + F_Stribeck * np.exp(-fexp * v)])


# Functions of parameter values only (an MSL function computing a table), not of the
# expression language the core evaluates; their arguments may be named: input names in order.
NAMED_INPUTS: dict[str, tuple[str, ...]] = {
    "Modelica.Mechanics.Translational.Examples.Utilities.GenerateStribeckFrictionTable": (
        "F_prop",
        "F_Coulomb",
        "F_Stribeck",
        "fexp",
        "v_max",
        "nTable",
    ),
}
PARAMETER_FUNCTIONS: dict[str, Callable[..., Any]] = {name: _stribeck_table for name in NAMED_INPUTS}

_BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: np.divide(a, b) if isinstance(a, np.ndarray) or isinstance(b, np.ndarray) else a / b,
    # Integer powers in floats once large: Python's exact 10**(10**9) would take minutes
    "^": lambda a, b: float(a) ** b if type(a) is type(b) is int and abs(b) > 64 else a**b,
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
    "==": lambda a, b: a == b,
    "<>": lambda a, b: a != b,
    "and": lambda a, b: np.logical_and(a, b),
    "or": lambda a, b: np.logical_or(a, b),
}

Lookup = Callable[[Ref], Any]
Resolve = Callable[[str, Pos], str]


def evaluate(expr: Expr, lookup: Lookup, resolve: Resolve, der: Lookup | None = None) -> Any:
    """Value of ``expr``; ``lookup`` gives a name's value, ``resolve`` qualifies function names."""

    def ev(e: Expr) -> Any:
        if isinstance(e, Literal):
            return e.value
        if isinstance(e, Ref):
            return lookup(e)
        if isinstance(e, Unary):
            value = ev(e.operand)
            _check_operands(e, value)
            return np.logical_not(value) if e.op == "not" else (-value if e.op == "-" else value)
        if isinstance(e, BinOp):
            left, right = ev(e.left), ev(e.right)
            _check_operands(e, left, right)
            return _arithmetic(e, lambda: _BINARY[e.op](left, right))
        if isinstance(e, IfExpr):
            cond = ev(e.cond)
            if isinstance(cond, np.ndarray):
                return np.where(cond, ev(e.then), ev(e.other))
            return ev(e.then) if cond else ev(e.other)
        if isinstance(e, Array):
            return [ev(item) for item in e.items]
        if isinstance(e, Matrix):
            return [[ev(item) for item in row] for row in e.rows]
        return _call(e, ev, resolve, der)

    return ev(expr)


def _check_operands(e: BinOp | Unary, *values: Any) -> None:
    """A string or an array is no operand of an operator (a fuzzed `tau = - "a comment"`)."""
    for value in values:
        if isinstance(value, (str, list)):
            raise ModelicaError(e.pos, f"type mismatch: operator '{e.op}' on {python_value(value)!r}")


def _call(e: Call, ev: Callable[[Expr], Any], resolve: Resolve, der: Lookup | None) -> Any:
    if e.func == "der":
        if der is None or len(e.args) != 1 or not isinstance(e.args[0], Ref):
            raise ModelicaError(e.pos, "der(…) of a variable is only allowed in a variable's binding")
        return der(e.args[0])
    name = e.func if e.func in FUNCTIONS else resolve(e.func, e.pos)
    function = FUNCTIONS.get(name) or PARAMETER_FUNCTIONS.get(name)
    if function is None:
        known = ", ".join(sorted(n for n in FUNCTIONS if "." not in n))
        raise ModelicaError(e.pos, f"unknown function '{e.func}' (supported: {known}, der)")
    if e.kwargs and name not in NAMED_INPUTS:
        raise ModelicaError(e.pos, f"named arguments in a call of '{e.func}' are not supported")
    args = [ev(a) for a in e.args]
    kwargs = {k: ev(a) for k, a in e.kwargs.items()}
    unknown = set(kwargs) - set(NAMED_INPUTS.get(name, ()))
    if unknown:
        raise ModelicaError(e.pos, f"'{e.func}' has no input {', '.join(sorted(unknown))}")
    try:
        return _arithmetic(e, lambda: function(*args, **kwargs))
    except (TypeError, ValueError) as exc:
        raise ModelicaError(e.pos, f"bad call of '{e.func}': {exc}") from None


def _arithmetic(e: BinOp | Call, compute: Callable[[], Any]) -> Any:
    """``compute()``, with Python's arithmetic errors as located ones. A result out of range
    as a float (inf, NaN) passes: the parameter it reaches refuses it, naming itself."""
    try:
        with np.errstate(all="ignore"):
            value = compute()
    except ZeroDivisionError:
        raise ModelicaError(e.pos, "division by zero") from None
    except OverflowError:
        raise ModelicaError(e.pos, "the result is too large for a Real") from None
    if type(value) is int and abs(value) >= 2**63:  # 10^400 of Integers: Python's int grows
        raise ModelicaError(e.pos, "the result is too large for an Integer")
    return value


_PLAIN = frozenset((float, int, bool, str))


def python_value(value: Any) -> Any:
    """Plain Python data (float, bool, lists) from an evaluation's NumPy scalars."""
    if type(value) in _PLAIN:
        return value
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, list):
        return [python_value(v) for v in value]
    return value


_PRECEDENCE = {
    "or": 1,
    "and": 2,
    "<": 4,
    "<=": 4,
    ">": 4,
    ">=": 4,
    "==": 4,
    "<>": 4,
    "+": 5,
    "-": 5,
    "*": 6,
    "/": 6,
    "^": 7,
}


def unparse(expr: Expr, substitute: Callable[[Ref], Expr | None] | None = None, outer: int = 0) -> str:
    """Modelica text of ``expr``; ``substitute`` may replace names (parameters by values)."""

    def up(e: Expr, prec: int = 0) -> str:
        return unparse(e, substitute, prec)

    if isinstance(expr, Literal):
        return format_literal(expr.value)
    if isinstance(expr, Ref):
        replaced = substitute(expr) if substitute else None
        if replaced is not None:
            return up(replaced, outer)
        subs = f"[{', '.join(up(s) for s in expr.subscripts)}]" if expr.subscripts else ""
        return expr.name + subs
    if isinstance(expr, Unary):
        text = f"not {up(expr.operand, 3)}" if expr.op == "not" else f"{expr.op}{up(expr.operand, 6)}"
        return f"({text})" if outer >= 5 else text
    if isinstance(expr, BinOp):
        prec = _PRECEDENCE[expr.op]
        right_prec = prec + 1 if expr.op in ("-", "/", "^") or prec == 4 else prec
        text = f"{up(expr.left, prec)} {expr.op} {up(expr.right, right_prec)}"
        return f"({text})" if prec < outer else text
    if isinstance(expr, IfExpr):
        text = f"if {up(expr.cond)} then {up(expr.then)} else {up(expr.other)}"
        return f"({text})" if outer else text
    if isinstance(expr, Array):
        return "{" + ", ".join(up(i) for i in expr.items) + "}"
    if isinstance(expr, Matrix):
        return "[" + "; ".join(", ".join(up(i) for i in row) for row in expr.rows) + "]"
    args = [up(a) for a in expr.args] + [f"{k}={up(v)}" for k, v in expr.kwargs.items()]
    return f"{expr.func}({', '.join(args)})"


def format_literal(value: Any) -> str:
    """Modelica text of a value: ``true``, ``2``, ``0.5``, ``1e-06``, ``"text"``, arrays."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value} has no Modelica literal")
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        if value and all(isinstance(row, (list, tuple)) for row in value):
            return "[" + "; ".join(", ".join(format_literal(v) for v in row) for row in value) + "]"
        return "{" + ", ".join(format_literal(v) for v in value) + "}"
    raise ValueError(f"{value!r} has no Modelica literal")
