"""Tokens of Modelica text, each with its line and column, and the error that names them.

Hand-written, as is the parser: the Modelica parsers on PyPI are either unmaintained
(modparc 2017, modelicalang alpha 2023) or a whole compiler front end with heavy
dependencies (pymoca brings an ANTLR runtime and a CAS layer), while the subset stiction reads
(MSL-style models of components, parameters, connections and annotations) takes a few hundred
lines and lets every error carry ``file:line:column`` and the name at fault.
"""

from __future__ import annotations

import bisect
import functools
import itertools
import re
from collections.abc import Iterator
from typing import Any, NamedTuple

from ..errors import ModelError

__all__ = ["KEYWORDS", "ModelicaError", "Pos", "Token", "tokenize"]


class Pos:
    """A place in a source: file label, line and column (both from 1). Every name in a syntax
    tree carries one, and almost none is ever shown: a token's line and column are worked out
    when first read (``Pos.at``), not when the tree is built."""

    __slots__ = ("_lines", "_offset", "_where")

    def __init__(self, source: str, line: int = 1, col: int = 1) -> None:
        self._lines: _Lines | None = None
        self._offset = 0
        self._where: tuple[str, int, int] | None = (source, line, col)

    @classmethod
    def at(cls, lines: _Lines, offset: int) -> Pos:
        """The place of character ``offset`` of the text ``lines`` indexes."""
        pos = cls.__new__(cls)
        pos._lines, pos._offset, pos._where = lines, offset, None
        return pos

    def _resolved(self) -> tuple[str, int, int]:
        if self._where is None:
            assert self._lines is not None
            self._where = self._lines.where(self._offset)
        return self._where

    @property
    def source(self) -> str:
        """The file label."""
        return self._resolved()[0]

    @property
    def line(self) -> int:
        """The line, from 1."""
        return self._resolved()[1]

    @property
    def col(self) -> int:
        """The column, from 1."""
        return self._resolved()[2]

    def __iter__(self) -> Iterator[Any]:
        return iter(self._resolved())

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Pos) and self._resolved() == other._resolved()

    def __hash__(self) -> int:
        return hash(self._resolved())

    def __repr__(self) -> str:
        return "Pos(source={!r}, line={}, col={})".format(*self._resolved())

    def __str__(self) -> str:
        return "{}:{}:{}".format(*self._resolved())


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
        return Pos.at(self, offset)

    def where(self, offset: int) -> tuple[str, int, int]:
        line = bisect.bisect_right(self.starts, offset)
        return self.source, line, offset - self.starts[line - 1] + 1


class Token(NamedTuple):
    """One token: kind (``ident``, ``number``, ``string``, ``op``, ``kw``, ``eof``) and text."""

    kind: str
    text: str
    offset: int
    lines: _Lines

    @property
    def pos(self) -> Pos:
        """Where the token starts."""
        return Pos.at(self.lines, self.offset)


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

# Blanks and comments are the first group, the token the second: one match per token, and
# findall builds the whole list in C (the 1500-component import spends its time here).
_TOKEN = re.compile(
    r"""
    (\s*(?:(?://[^\n]*|/\*.*?\*/)\s*)*)
    ( [A-Za-z_][A-Za-z0-9_]*|'(?:[^'\\]|\\.)+'
    | \d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?
    | [()\[\]{};,+\-*/^]|\.[*/+\-^]?|:=?|==|=|<[>=]?|>=?
    | "(?:[^"\\]|\\.)*"
    )
    """,
    re.VERBOSE | re.DOTALL,
)
_KIND = {
    **{c: "ident" for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_'"},
    **{c: "number" for c in "0123456789"},
    **{c: "op" for c in "()[]{};,+-*/^:=<>"},
    '"': "string",
}


def _kinds(texts: list[str]) -> list[str]:
    """The kind of every token text: keyword, identifier, number, string or operator."""
    keywords, kind = KEYWORDS, _KIND
    kinds = ["kw" if t in keywords else kind.get(t[0], "") for t in texts]
    for i in (i for i, k in enumerate(kinds) if not k):  # starts with "."
        kinds[i] = "number" if texts[i][1:2].isdigit() else "op"
    return kinds


_NOT_NEWLINE = re.compile(r"[^\n]")


def _nested_parens(depth: int) -> str:
    """A regex for balanced parentheses up to ``depth`` levels, no strings inside."""
    inner = r"[^()\"]*"
    for _ in range(depth):
        inner = rf"(?:[^()\"]|\({inner}\))*"
    return rf"\({inner}\)"


# A string or comment (kept as it is) or a graphical annotation (strings inside it, deeper
# nesting: left to the parser, which skips it token by token).
_GRAPHICS = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/|\bannotation\s*' + _nested_parens(6), re.DOTALL)


def _blank(m: re.Match[str]) -> str:
    span = m.group()
    if not span.startswith("annotation") or "experiment" in span:
        return span
    return _NOT_NEWLINE.sub(" ", span) if "\n" in span else " " * len(span)


def blank_graphics(text: str) -> str:
    """The text with every annotation that holds no ``experiment`` blanked out (same length and
    lines, so positions stay true). Placement, line and icon annotations are most of an MSL
    model's tokens and are skipped anyway; blanking them first keeps a 1500-component import fast."""
    return _GRAPHICS.sub(_blank, text)


def tokenize(text: str, source: str = "<modelica>") -> list[Token]:
    """Split Modelica text into tokens; comments, white space and graphical annotations
    (``blank_graphics``) are dropped."""
    lines = _Lines(source, text)
    text = blank_graphics(text)
    found = _TOKEN.findall(text)
    ends = list(itertools.accumulate([len(blank) + len(token) for blank, token in found]))
    covered = ends[-1] if ends else 0
    rest = _skip_blanks(text, covered)
    if rest != len(text):  # findall skipped text no token matches: the matches end later
        _refuse(text, _first_gap(text), lines)
    texts = [token for _, token in found]
    starts = [end - len(token) for end, token in zip(ends, texts, strict=True)]
    if "/*" in text:  # a comment that never closes reads as the tokens '/' '*'
        for token, start in zip(texts, starts, strict=True):
            if token == "/" and text.startswith("/*", start):
                _refuse(text, start, lines)
    make = functools.partial(tuple.__new__, Token)
    tokens = list(map(make, zip(_kinds(texts), texts, starts, itertools.repeat(lines))))
    tokens.append(Token("eof", "", rest, lines))
    return tokens


def _first_gap(text: str) -> int:
    """Where the first text no token matches begins (only called for bad text)."""
    i = 0
    while True:
        m = _TOKEN.match(text, i)
        if m is None:
            return i
        i = m.end()


def _refuse(text: str, i: int, lines: _Lines) -> None:
    start = _skip_blanks(text, i)
    what = f"unexpected {text[start]!r}" if start < len(text) else "unexpected end of file"
    if text.startswith("/*", start):
        what = "unterminated comment"
    elif start < len(text) and text[start] == '"':
        what = "unterminated string"
    raise ModelicaError(lines.pos(start), f"syntax error: {what}")


_BLANKS = re.compile(r"(?:\s+|//[^\n]*|/\*.*?\*/)*", re.DOTALL)


def _skip_blanks(text: str, i: int) -> int:
    m = _BLANKS.match(text, i)
    return m.end() if m else i
