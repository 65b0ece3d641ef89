"""The syntax tree of expressions: Modelica's expression grammar, which parameters, derived
variables and the ``.mo`` importer all read.

Every node keeps the position of its first token, so a later stage (name resolution,
conversion) can still say ``file:line:column`` about it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from stiction.expressions.lexer import Pos

__all__ = ["Array", "BinOp", "Call", "Expr", "IfExpr", "Literal", "Matrix", "Ref", "Unary"]


@dataclass
class Literal:
    """A number, string or Boolean written in the text (``1`` is an Integer, ``1.0`` a Real)."""

    value: bool | int | float | str
    pos: Pos


@dataclass
class Ref:
    """A dotted name (``Modelica.Constants.pi``, ``gear.flange_a.tau``), maybe subscripted."""

    name: str
    pos: Pos
    subscripts: list[Expr] = field(default_factory=list)


@dataclass
class Call:
    """``f(a, b, key=c)``; ``der`` is a call too."""

    func: str
    args: list[Expr]
    kwargs: dict[str, Expr]
    pos: Pos


@dataclass
class Array:
    """``{a, b, c}``."""

    items: list[Expr]
    pos: Pos


@dataclass
class Matrix:
    """``[a, b; c, d]``: rows of expressions."""

    rows: list[list[Expr]]
    pos: Pos


@dataclass
class BinOp:
    """``left op right`` (arithmetic, relations, and/or)."""

    op: str
    left: Expr
    right: Expr
    pos: Pos


@dataclass
class Unary:
    """``-x``, ``+x``, ``not x``."""

    op: str
    operand: Expr
    pos: Pos


@dataclass
class IfExpr:
    """``if c then a else b`` as an expression."""

    cond: Expr
    then: Expr
    other: Expr
    pos: Pos


Expr = Literal | Ref | Call | Array | Matrix | BinOp | Unary | IfExpr
