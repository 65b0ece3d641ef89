"""The Modelica lexer: its one-pass scanner gives exactly the tokens, kinds and places of the
careful two-pass one (graphical annotations blanked first) wherever it answers, and text the
two could read differently goes the careful way; comments at the end of a file are blanks."""

from __future__ import annotations

import random

import pytest
from paths import MSL_EXAMPLES

import stiction as st
from stiction.expressions import lexer
from stiction.expressions.lexer import ModelicaError

EXAMPLES = MSL_EXAMPLES
TEXTS = {p.stem: p.read_text(encoding="utf-8") for p in sorted(EXAMPLES.glob("*.mo"))}
# Pieces that stress what separates the two scanners: annotations with and without an
# experiment, quoted identifiers, open comments and strings, a stray character.
PIECES = [
    "annotation(",
    " annotation (Line(points={{0,0},{1,0}}))",
    "annotation(experiment(StopTime=1))",
    "experiment",
    "'q'",
    "'",
    "/*",
    "*/",
    "//",
    '"',
    "(",
    ")",
    ".5",
    "a.5",
    "./",
    "xannotation(",
    "1annotation()",
    ";",
    "$",
    "\n",
]


def _same(fast: lexer.Tokens, careful: lexer.Tokens) -> None:
    assert fast.texts == careful.texts
    assert fast.kinds == careful.kinds
    places = range(len(fast.texts))
    assert [fast.where(i) for i in places] == [careful.where(i) for i in places]


@pytest.mark.parametrize("name", sorted(TEXTS))
def test_one_pass_reads_every_example_as_the_careful_pass(name: str) -> None:
    fast = lexer._fast_tokens(TEXTS[name], name)
    assert fast is not None  # MSL-style text takes the one pass
    _same(fast, lexer._careful_tokens(TEXTS[name], name))


def test_one_pass_agrees_on_damaged_text_or_leaves_it_to_the_careful_pass() -> None:
    rng = random.Random(11)
    answered = 0
    for text in TEXTS.values():
        for _ in range(60):
            damaged = text
            for _ in range(rng.randrange(1, 4)):
                k = rng.randrange(len(damaged) + 1)
                damaged = damaged[:k] + rng.choice(PIECES) + damaged[k + rng.randrange(0, 3) :]
            fast = lexer._fast_tokens(damaged, "x")
            try:
                careful = lexer._careful_tokens(damaged, "x")
            except ModelicaError:
                assert fast is None  # the careful pass places every lexical error
                continue
            if fast is not None:
                _same(fast, careful)
                answered += 1
    assert answered > 300  # most damage leaves a text the one pass reads


@pytest.mark.parametrize("tail", ["// the end.", "/* the end */", "// no ';' here;\n\n"])
def test_a_comment_at_the_end_of_the_file_is_blank(tail: str) -> None:
    text = TEXTS["First"]
    # these used to read the comment's last characters as tokens (a backtracking blank match)
    assert st.Model.from_modelica(text + tail).to_toml() == st.Model.from_modelica(text).to_toml()


def test_a_semicolon_in_a_trailing_comment_does_not_end_the_class() -> None:
    text = TEXTS["First"].rstrip().removesuffix(";") + " // ;\n"
    with pytest.raises(st.ModelError, match="expected ';'"):
        st.Model.from_modelica(text)


def test_two_type_prefixes_read_as_the_first() -> None:
    body = TEXTS["First"].replace("equation", "  parameter input Real k = 2;\nequation", 1)
    assert st.Model.from_modelica(body).parameters["k"] == 2.0
