"""The syntax tree of the Modelica subset: expressions, modifications, declarations, classes.

Every node keeps the position of its first token, so a later stage (name resolution,
conversion) can still say ``file:line:column`` about it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .lexer import Pos

__all__ = [
    "Array",
    "BinOp",
    "Call",
    "ClassDef",
    "Connect",
    "Declaration",
    "Expr",
    "IfExpr",
    "Import",
    "Literal",
    "Matrix",
    "Modification",
    "Ref",
    "StoredDefinition",
    "Unary",
]


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


@dataclass
class Modification:
    """``name(sub-modifications) = value "description"``; any part may be missing."""

    name: str
    pos: Pos
    args: list[Modification] | None = None
    value: Expr | None = None
    description: str = ""


@dataclass
class Declaration:
    """A component or variable: ``prefix Type name(modifiers) = binding "description"``."""

    type_name: str
    type_pos: Pos
    name: str
    pos: Pos
    prefix: str = ""  # "parameter", "constant", "input", "output", "discrete" or ""
    args: list[Modification] = field(default_factory=list)
    binding: Expr | None = None
    description: str = ""


@dataclass
class Import:
    """``import A.B.C;``, ``import X = A.B;`` or ``import A.B.*;``."""

    alias: str | None
    target: str
    wildcard: bool
    pos: Pos


@dataclass
class Connect:
    """``connect(a, b);``."""

    a: Ref
    b: Ref
    pos: Pos


@dataclass
class ClassDef:
    """A model, block, class or package with what stiction reads of it."""

    kind: str
    name: str
    pos: Pos
    description: str = ""
    imports: list[Import] = field(default_factory=list)
    extends: list[tuple[str, Pos]] = field(default_factory=list)
    declarations: list[Declaration] = field(default_factory=list)
    connects: list[Connect] = field(default_factory=list)
    classes: list[ClassDef] = field(default_factory=list)
    annotation: list[Modification] = field(default_factory=list)


@dataclass
class StoredDefinition:
    """A whole file: an optional ``within`` and its classes."""

    within: str
    classes: list[ClassDef]
