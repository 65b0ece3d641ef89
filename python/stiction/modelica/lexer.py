"""Tokens of Modelica text, each with its line and column, and the error that names them.

Hand-written, as is the parser: the Modelica parsers on PyPI are either unmaintained
(modparc 2017, modelicalang alpha 2023) or a whole compiler front end with heavy
dependencies (pymoca brings an ANTLR runtime and a CAS layer), while the subset stiction reads
(MSL-style models of components, parameters, connections and annotations) takes a few hundred
lines and lets every error carry ``file:line:column`` and the name at fault.
"""

from __future__ import annotations

import re
from typing import NamedTuple

from ..errors import ModelError

__all__ = ["KEYWORDS", "ModelicaError", "Pos", "Token", "tokenize"]


class Pos(NamedTuple):
    """A place in a source: file label, line and column (both from 1)."""

    source: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.source}:{self.line}:{self.col}"


class ModelicaError(ModelError):
    """Modelica text stiction cannot take; the message starts with ``file:line:column``."""

    def __init__(self, pos: Pos, message: str) -> None:
        super().__init__(f"{pos}: {message}")
        self.pos = pos
        self.detail = message


class Token(NamedTuple):
    """One token: kind (``ident``, ``number``, ``string``, ``op``, ``kw``, ``eof``) and text."""

    kind: str
    text: str
    pos: Pos


KEYWORDS = frozenset(
    [
        "algorithm",
        "and",
        "annotation",
        "block",
        "break",
        "class",
        "connect",
        "connector",
        "constant",
        "constrainedby",
        "der",
        "discrete",
        "each",
        "else",
        "elseif",
        "elsewhen",
        "encapsulated",
        "end",
        "enumeration",
        "equation",
        "expandable",
        "extends",
        "external",
        "false",
        "final",
        "flow",
        "for",
        "function",
        "if",
        "import",
        "impure",
        "in",
        "initial",
        "inner",
        "input",
        "loop",
        "model",
        "not",
        "operator",
        "or",
        "outer",
        "output",
        "package",
        "parameter",
        "partial",
        "protected",
        "public",
        "pure",
        "record",
        "redeclare",
        "replaceable",
        "return",
        "stream",
        "then",
        "true",
        "type",
        "when",
        "while",
        "within",
    ]
)

_TOKEN = re.compile(
    r"""
    (?P<ws>[ \t\r\f\v]+|\n)
  | (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<ident>[A-Za-z_][A-Za-z0-9_]*|'(?:[^'\\]|\\.)+')
  | (?P<string>"(?:[^"\\]|\\.)*")
  | (?P<op>\.\*|\./|\.\+|\.-|\.\^|:=|==|<>|<=|>=|[()\[\]{};,.=+\-*/^<>:])
    """,
    re.VERBOSE | re.DOTALL,
)


def tokenize(text: str, source: str = "<modelica>") -> list[Token]:
    """Split Modelica text into tokens; comments and white space are dropped."""
    tokens: list[Token] = []
    line, line_start, i = 1, 0, 0
    n = len(text)
    while i < n:
        m = _TOKEN.match(text, i)
        pos = Pos(source, line, i - line_start + 1)
        if m is None:
            what = "an unterminated comment" if text.startswith("/*", i) else repr(text[i])
            if text[i] == '"':
                what = "an unterminated string"
            raise ModelicaError(pos, f"syntax error: unexpected {what}")
        kind, value = m.lastgroup or "", m.group()
        if kind == "ident" and value in KEYWORDS:
            kind = "kw"
        if kind not in ("ws", "comment"):
            tokens.append(Token(kind, value, pos))
        newlines = value.count("\n")
        if newlines:
            line += newlines
            line_start = m.start() + value.rindex("\n") + 1
        i = m.end()
    tokens.append(Token("eof", "", Pos(source, line, i - line_start + 1)))
    return tokens
