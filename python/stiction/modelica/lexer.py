"""Tokens of Modelica text, each with its line and column, and the error that names them.

Hand-written, as is the parser: the Modelica parsers on PyPI are either unmaintained
(modparc 2017, modelicalang alpha 2023) or a whole compiler front end with heavy
dependencies (pymoca brings an ANTLR runtime and a CAS layer), while the subset stiction reads
(MSL-style models of components, parameters, connections and annotations) takes a few hundred
lines and lets every error carry ``file:line:column`` and the name at fault.
"""

from __future__ import annotations

import bisect
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


class _Lines:
    """Line starts of a text, to turn an offset into line and column only when asked."""

    def __init__(self, source: str, text: str) -> None:
        self.source = source
        self.starts = [0, *(m.end() for m in re.finditer("\n", text))]

    def pos(self, offset: int) -> Pos:
        line = bisect.bisect_right(self.starts, offset)
        return Pos(self.source, line, offset - self.starts[line - 1] + 1)


class Token(NamedTuple):
    """One token: kind (``ident``, ``number``, ``string``, ``op``, ``kw``, ``eof``) and text."""

    kind: str
    text: str
    offset: int
    lines: _Lines

    @property
    def pos(self) -> Pos:
        """Where the token starts."""
        return self.lines.pos(self.offset)


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

# Blanks and comments are skipped as the prefix of every token, so one match is one token.
_TOKEN = re.compile(
    r"""
    (?:\s+|//[^\n]*|/\*.*?\*/)*
    (?:
      (?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    | (?P<ident>[A-Za-z_][A-Za-z0-9_]*|'(?:[^'\\]|\\.)+')
    | (?P<string>"(?:[^"\\]|\\.)*")
    | (?P<op>\.\*|\./|\.\+|\.-|\.\^|:=|==|<>|<=|>=|[()\[\]{};,.=+\-*/^<>:])
    | (?P<end>\Z)
    )
    """,
    re.VERBOSE | re.DOTALL,
)


def tokenize(text: str, source: str = "<modelica>") -> list[Token]:
    """Split Modelica text into tokens; comments and white space are dropped."""
    lines = _Lines(source, text)
    tokens: list[Token] = []
    append, match, keywords = tokens.append, _TOKEN.match, KEYWORDS
    i = 0
    while True:
        m = match(text, i)
        if m is None:
            start = _skip_blanks(text, i)
            what = repr(text[start])
            if text.startswith("/*", start):
                what = "an unterminated comment"
            elif text[start] == '"':
                what = "an unterminated string"
            raise ModelicaError(lines.pos(start), f"syntax error: unexpected {what}")
        kind = m.lastgroup or ""
        start = m.start(kind)
        if kind == "end":
            append(Token("eof", "", start, lines))
            return tokens
        value = m.group(kind)
        if kind == "ident" and value in keywords:
            kind = "kw"
        append(Token(kind, value, start, lines))
        i = m.end()


def _skip_blanks(text: str, i: int) -> int:
    m = re.compile(r"(?:\s+|//[^\n]*|/\*.*?\*/)*", re.DOTALL).match(text, i)
    return m.end() if m else i
