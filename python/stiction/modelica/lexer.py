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
    \s*(?:(?://[^\n]*|/\*.*?\*/)\s*)*
    (?:
      (?P<ident>[A-Za-z_][A-Za-z0-9_]*|'(?:[^'\\]|\\.)+')
    | (?P<op>[()\[\]{};,+\-*/^]|\.[*/+\-^]?|:=?|==|=|<[>=]?|>=?)
    | (?P<number>\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)
    | (?P<string>"(?:[^"\\]|\\.)*")
    | (?P<end>\Z)
    )
    """,
    re.VERBOSE | re.DOTALL,
)


_SCAN_ANNOTATION = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/|\bannotation\s*\(', re.DOTALL)
_SCAN_PARENS = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/|[()]', re.DOTALL)
_NOT_NEWLINE = re.compile(r"[^\n]")


def blank_graphics(text: str) -> str:
    """The text with every annotation that holds no ``experiment`` blanked out (same length and
    lines, so positions stay true). Placement, line and icon annotations are most of an MSL
    model's tokens and are skipped anyway; blanking them first keeps a 1500-component import fast.
    An annotation whose parentheses do not close is left for the parser to report."""
    pieces: list[str] = []
    last = 0
    for m in _SCAN_ANNOTATION.finditer(text):
        if m.start() < last or not m.group().startswith("annotation"):
            continue
        depth = 0
        for p in _SCAN_PARENS.finditer(text, m.end() - 1):
            depth += {"(": 1, ")": -1}.get(p.group(), 0)
            if depth == 0:
                break
        else:
            continue
        span = text[m.start() : p.end()]
        if "experiment" in span:
            continue
        pieces += [text[last : m.start()], _NOT_NEWLINE.sub(" ", span)]
        last = p.end()
    pieces.append(text[last:])
    return "".join(pieces)


def tokenize(text: str, source: str = "<modelica>") -> list[Token]:
    """Split Modelica text into tokens; comments, white space and graphical annotations
    (``blank_graphics``) are dropped."""
    lines = _Lines(source, text)
    text = blank_graphics(text)
    found = [
        (m.lastgroup, m.group(m.lastgroup), m.start(m.lastgroup), m.start(), m.end())
        for m in _TOKEN.finditer(text)
    ]
    previous, stop = 0, len(found)
    for i, (kind, _, _, blank, end) in enumerate(found):
        if blank != previous:  # finditer skipped text that no token matches
            _refuse(text, previous, lines)
        if kind == "end":
            stop = i
            break
        previous = end
    else:
        _refuse(text, previous, lines)
    del found[stop + 1 :]
    keywords = KEYWORDS
    make = Token._make
    tokens = [
        make(("kw" if kind == "ident" and value in keywords else kind, value, start, lines))
        for kind, value, start, _, _ in found
    ]
    tokens[-1] = Token("eof", "", tokens[-1].offset, lines)
    return tokens


def _refuse(text: str, i: int, lines: _Lines) -> None:
    start = _skip_blanks(text, i)
    what = repr(text[start]) if start < len(text) else "end of file"
    if text.startswith("/*", start):
        what = "an unterminated comment"
    elif start < len(text) and text[start] == '"':
        what = "an unterminated string"
    raise ModelicaError(lines.pos(start), f"syntax error: unexpected {what}")


_BLANKS = re.compile(r"(?:\s+|//[^\n]*|/\*.*?\*/)*", re.DOTALL)


def _skip_blanks(text: str, i: int) -> int:
    m = _BLANKS.match(text, i)
    return m.end() if m else i
