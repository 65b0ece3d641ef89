"""Tokens of Modelica text (parallel lists of kinds and texts, each token's line and column
found when asked), and the error that names a place.

Hand-written, as is the parser: the Modelica parsers on PyPI are either unmaintained
(modparc 2017, modelicalang alpha 2023) or a whole compiler front end with heavy
dependencies (pymoca brings an ANTLR runtime and a CAS layer), while the subset stiction reads
(MSL-style models of components, parameters, connections and annotations) takes a few hundred
lines and lets every error carry ``file:line:column`` and the name at fault.
"""

from __future__ import annotations

import bisect
import itertools
import operator
import re
from collections.abc import Iterator
from typing import Any, Protocol

from stiction.errors import ModelError

__all__ = ["KEYWORDS", "ModelicaError", "Pos", "Tokens", "tokenize"]


class Pos:
    """A place in a source: file label, line and column (both from 1). Every name in a syntax
    tree carries one, and almost none is ever shown: a token's line and column are worked out
    when first read (``Pos.at``), not when the tree is built."""

    __slots__ = ("_key", "_table", "_where")

    def __init__(self, source: str, line: int = 1, col: int = 1) -> None:
        self._table: _Where | None = None
        self._key = 0
        self._where: tuple[str, int, int] | None = (source, line, col)

    @classmethod
    def at(cls, table: _Where, key: int) -> Pos:
        """The place ``table.where(key)`` names: a character offset of a text (``_Lines``) or
        a token's index (``Tokens``)."""
        pos = cls.__new__(cls)
        pos._table, pos._key, pos._where = table, key, None
        return pos

    def _resolved(self) -> tuple[str, int, int]:
        if self._where is None:
            assert self._table is not None
            self._where = self._table.where(self._key)
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
    """Modelica text stiction cannot take; the message starts with ``file:line:column``.

    A file with several errors raises one ``ModelicaError`` listing them all, one a line,
    sorted by place (``ModelicaError.of``): ``pos`` and ``detail`` are the first one's and
    ``errors`` holds every one as ``(line, column, message)``."""

    REPORTED = 50  # the message lists this many, then "... and N more"

    def __init__(self, pos: Pos, message: str) -> None:
        super().__init__(f"{pos}: {message}")
        self.pos = pos
        self.detail = message
        self._each: list[ModelicaError] | None = None  # of a combined error: all it reports

    @property
    def each(self) -> list[ModelicaError]:
        """The single errors this one reports (itself alone, unless combined)."""
        return self._each or [self]

    @property
    def errors(self) -> list[tuple[int, int, str]]:
        """Every error reported, ``(line, column, message)``, in the order of the file."""
        return [(e.pos.line, e.pos.col, e.detail) for e in self.each]

    @classmethod
    def of(cls, errors: list[ModelicaError]) -> ModelicaError:
        """One error reporting all of ``errors`` (one at least), sorted by place, the same
        error at the same place once; the message names the first first."""
        unique: dict[tuple[Any, ...], ModelicaError] = {}
        for error in (one for e in errors for one in e.each):
            unique.setdefault((*error.pos, error.detail), error)
        ordered = sorted(unique.values(), key=lambda e: (e.pos.line, e.pos.col))
        if len(ordered) == 1:
            return ordered[0]
        lines = [str(e.args[0]) for e in ordered[: cls.REPORTED]]
        if len(ordered) > cls.REPORTED:
            lines.append(f"... and {len(ordered) - cls.REPORTED} more")
        combined = cls(ordered[0].pos, ordered[0].detail)
        combined.args = ("\n".join(lines),)
        combined._each = ordered
        return combined


class _Where(Protocol):
    """What a ``Pos`` asks for its place: ``where(key)`` → (file label, line, column)."""

    def where(self, key: int) -> tuple[str, int, int]: ...


class _Lines:
    """Line starts of a text, to turn an offset into line and column only when asked (the
    starts are found at the first question: a text read without error never needs them)."""

    def __init__(self, source: str, text: str) -> None:
        self.source = source
        self.text = text
        self._starts: list[int] | None = None

    def pos(self, offset: int) -> Pos:
        return Pos.at(self, offset)

    def where(self, offset: int) -> tuple[str, int, int]:
        if self._starts is None:
            self._starts = [0, *(m.end() for m in re.finditer("\n", self.text))]
        line = bisect.bisect_right(self._starts, offset)
        return self.source, line, offset - self._starts[line - 1] + 1


class Tokens:
    """The tokens of a text as parallel lists, ``kinds[i]`` (``ident``, ``number``,
    ``string``, ``op``, ``kw``, the last ``eof``) and ``texts[i]``: no object per token, and
    a token's offset is worked out only when its position is read (``pos``)."""

    __slots__ = ("_found", "_starts", "kinds", "lines", "texts")

    def __init__(
        self, lines: _Lines, found: list[tuple[str, str]], kinds: list[str], texts: list[str]
    ) -> None:
        self.lines = lines
        self.kinds = kinds
        self.texts = texts
        self._found = found  # (blanks before, token) per token, the end's token "": the offsets
        self._starts: list[int] | None = None

    def start(self, i: int) -> int:
        """The offset of token ``i`` in the text (the end of file's after trailing blanks)."""
        if self._starts is None:
            ends = itertools.accumulate(len(blank) + len(token) for blank, token in self._found)
            self._starts = [end - len(token) for end, (_, token) in zip(ends, self._found, strict=True)]
        return self._starts[i]

    def pos(self, i: int) -> Pos:
        """Where token ``i`` starts."""
        return Pos.at(self, i)

    def where(self, i: int) -> tuple[str, int, int]:
        """File label, line and column of token ``i``."""
        return self.lines.where(self.start(i))


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

# One match is one token with the blanks and comments before it (the first group), so
# findall builds the whole list in C. The blanks never give back what they took (possessive):
# a comment at the end of the file is not searched for a token; the end itself matches (\Z),
# with the trailing blanks, as the token "".
_BLANKS_BEFORE = r"(\s*+(?:(?://[^\n]*+|/\*.*?\*/MORE)\s*+)*+)"
_TOKEN_TEXT = r"""
    ( [A-Za-z_][A-Za-z0-9_]*|'(?:[^'\\]|\\.)+'
    | \d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?
    | [()\[\]{};,+\-*/^]|\.[*/+\-^]?|:=?|==|=|<[>=]?|>=?
    | "(?:[^"\\]|\\.)*"MORE|\Z
    )
"""
_TOKEN = re.compile(
    _BLANKS_BEFORE.replace("MORE", "") + _TOKEN_TEXT.replace("MORE", ""), re.VERBOSE | re.DOTALL
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


def _nested_parens(depth: int, char: str = r'[^()"]++') -> str:
    """A regex for balanced parentheses up to ``depth`` levels of ``char`` (no strings)."""
    inner = rf"(?:{char})*+"
    for _ in range(depth):
        inner = rf"(?:{char}|\({inner}\))*+"  # possessive: the balanced match is the only one
    return rf"\({inner}\)"


# A string or comment (kept as it is) or a graphical annotation (strings inside it, deeper
# nesting: left to the parser, which skips it token by token).
_ANNOTATION = r"\bannotation\s*+" + _nested_parens(6)
_GRAPHICS = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/|' + _ANNOTATION, re.DOTALL)
_GRAPHIC_AT = re.compile(_ANNOTATION, re.DOTALL)


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


def tokenize(text: str, source: str = "<modelica>") -> Tokens:
    """Split Modelica text into tokens; comments, white space and graphical annotations
    (``blank_graphics``) are dropped."""
    return _fast_tokens(text, source) or _careful_tokens(text, source)


# One pass for what MSL-style text holds: a graphical annotation (one that ``blank_graphics``
# blanks: no string inside, no "experiment") is skipped with the blanks before a token. Any
# other character is a token too (\S) and the end is one (\Z), so no text is left out.
_FAST = re.compile(
    _BLANKS_BEFORE.replace("MORE", r"|\bannotation\s*+" + _nested_parens(6, r'[^()"e]++|e(?!xperiment)'))
    + _TOKEN_TEXT.replace("MORE", r"|\S"),
    re.VERBOSE | re.DOTALL,
)


class _Unknown(dict[str, str]):
    def __missing__(self, key: str) -> str:
        return "?"


# Kinds by the whole text (keywords, operators starting with "."), else by the first
# character. "?" sends the text the careful way: a character no token starts with, an open
# string, a quoted identifier or a number such as .5, and "./" (in "a.//b" blank_graphics
# sees a comment where the tokens are "./" "/").
_KIND_OF_TEXT = {
    **dict.fromkeys(KEYWORDS, "kw"),
    **dict.fromkeys((".", ".*", ".+", ".-", ".^"), "op"),
    **dict.fromkeys(("./", '"', "'"), "?"),
}
_KIND_OF_FIRST = _Unknown({k: v for k, v in _KIND.items() if k != "'"})


def _fast_tokens(text: str, source: str) -> Tokens | None:
    """The tokens in one regex pass, or None where that pass could differ from the careful
    one (a stray character, an open comment, a quoted identifier, an annotation left whole):
    that one then decides, and places the error."""
    found = _findall(_FAST, text)
    texts = list(map(operator.itemgetter(1), found))
    texts.pop()
    first = map(_KIND_OF_FIRST.__getitem__, map(operator.itemgetter(0), texts))
    kinds = list(map(_KIND_OF_TEXT.get, texts, first))
    if (
        "?" in kinds
        or "/*" in text
        and _open_comment(texts, found) >= 0
        or not _whole_agree(text, found, texts)
    ):
        return None
    kinds.append("eof")
    texts.append("")
    return Tokens(_Lines(source, text), found, kinds, texts)


def _whole_agree(text: str, found: list[tuple[str, str]], texts: list[str]) -> bool:
    """Whether the careful pass leaves every annotation whole that this one leaves whole,
    and nothing inside it blanked. Counted from the end, where a class annotation is."""
    whole = []
    i = -1
    while (i := _index(texts, "annotation", i + 1)) >= 0:
        whole.append(i)
    end, counted = len(text), len(found)  # end: where found[counted:] begins
    for i in reversed(whole):
        end -= sum(map(len, itertools.chain.from_iterable(itertools.islice(found, i, counted))))
        counted = i
        m = _GRAPHIC_AT.match(text, end + len(found[i][0]))
        if m and ("experiment" not in m.group() or m.group().count("annotation") > 1):
            return False
    return True


def _careful_tokens(text: str, source: str) -> Tokens:
    """Graphical annotations blanked first, then the tokens; every error placed."""
    text = blank_graphics(text)
    lines = _Lines(source, text)  # the same lines and columns as the text given
    found = _findall(_TOKEN, text)
    if sum(map(len, itertools.chain.from_iterable(found))) != len(text):  # findall skipped text
        _refuse(text, _first_gap(text), lines)  # no token matches, so the matches end later
    texts = list(map(operator.itemgetter(1), found))
    texts.pop()
    kinds = _kinds(texts)
    # a quoted identifier names what it quotes: 'front.clutch' is the component front.clutch
    # (the export's spelling of a hierarchical name); its place stays the quoted text's
    texts = [t[1:-1] if t[:1] == "'" else t for t in texts]
    tokens = Tokens(lines, found, [*kinds, "eof"], [*texts, ""])
    if "/*" in text and (i := _open_comment(texts, found)) >= 0:
        _refuse(text, tokens.start(i), lines)
    return tokens


def _open_comment(texts: list[str], found: list[tuple[str, str]]) -> int:
    """The first '/' token of a comment that never closes (it reads as the tokens '/' '*')."""
    i = -1
    while (i := _index(texts, "/", i + 1)) >= 0:  # a scan in C: '/' tokens are few
        if i + 1 < len(found) and found[i + 1] == ("", "*"):
            return i
    return -1


def _findall(pattern: re.Pattern[str], text: str) -> list[tuple[str, str]]:
    """(blanks, token) pairs, the last (trailing blanks, "") for the end of the text."""
    found = pattern.findall(text)
    if len(found) > 1 and found[-2][1] == "":  # after trailing blanks, \Z matched once more
        found.pop()
    return found


def _index(items: list[str], item: str, start: int) -> int:
    try:
        return items.index(item, start)
    except ValueError:
        return -1


def _first_gap(text: str) -> int:
    """Where the first text no token matches begins (only called for bad text)."""
    i = 0
    while (m := _TOKEN.match(text, i)) is not None and m.end() > i:
        i = m.end()
    return i


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
