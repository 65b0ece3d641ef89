"""The syntax tree of a ``.mo`` file beyond expressions: modifications, declarations, imports,
connections, classes (expressions are ``stiction.expressions.ast``).

Every node keeps the position of its first token, so a later stage (name resolution,
conversion) can still say ``file:line:column`` about it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from stiction.expressions.ast import Expr, Ref
from stiction.expressions.lexer import ModelicaError, Pos

__all__ = ["ClassDef", "Connect", "Declaration", "Import", "Modification", "StoredDefinition"]


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
    refused: bool = False  # read past an error the parser reported (conditional, array, …)
    # stiction's own annotations of the component (``__stiction_wear(…)``); graphics are skipped
    annotation: list[Modification] = field(default_factory=list)


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
    extends_args: list[list[Modification]] = field(default_factory=list)  # `extends B(p=1)`
    declarations: list[Declaration] = field(default_factory=list)
    connects: list[Connect] = field(default_factory=list)
    classes: list[ClassDef] = field(default_factory=list)
    annotation: list[Modification] = field(default_factory=list)


@dataclass
class StoredDefinition:
    """A whole file: an optional ``within`` and its classes; ``refused``, the constructs the
    parser reported and read past (reported with the converter's errors)."""

    within: str
    classes: list[ClassDef]
    refused: list[ModelicaError] = field(default_factory=list)
