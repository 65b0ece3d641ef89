"""Fuzzing the Modelica importer (Hypothesis; the core's model files are fuzzed by proptest in
``crates/stiction-core/tests/fuzz.rs``). The corpus is every ``.mo`` file shipped in
``examples/msl``; each case mutates one of them — lines dropped, duplicated or swapped, a number
replaced by an extreme or non-finite value, a token deleted, repeated hundreds of times or
inserted where it does not belong, the text cut short, a character replaced — and reads it.

Whatever comes in, the importer answers with a model or a ``ModelError`` that starts with
``<modelica>:line:column``, and a model it returns runs to a result or a typed
``StictionError``: never another exception, never a hang (each case carries an alarm; runs are
short and carry a step limit and a wall-clock timeout). CI runs a fixed budget;
``STICTION_FUZZ=20000 pytest tests/properties/test_fuzz_modelica.py`` runs a long campaign."""

from __future__ import annotations

import os
import re
import signal
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as hs
from paths import MSL_EXAMPLES

import stiction as st

CASES = int(os.environ.get("STICTION_FUZZ", "300"))
CORPUS = sorted(p for p in MSL_EXAMPLES.glob("*.mo"))
TEXTS = [p.read_text(encoding="utf-8") for p in CORPUS]
# a token of the language, a number, a string or a comment (the lexer's own split is the
# thing under test, so this one is deliberately rough)
TOKEN = re.compile(r'"(?:[^"\\]|\\.)*"|//[^\n]*|/\*.*?\*/|\d[\w.]*(?:[eE][+-]?\d+)?|\w+|\S', re.DOTALL)
NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d*)?(?:[eE][+-]?\d+)?")
EXTREMES = [
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "1e309",
    "nan",
    "inf",
    "-inf",
    "9" * 400,
    "1e",
    "0x10",
    "1.2.3",
]
INSERTS = ["(", ")", "{", "}", "[", "]", ";", ",", "=", ":=", '"', "/*", "//", ".", "end", "model", "connect"]
INSERTS += [
    "equation",
    "parameter",
    "extends",
    "annotation",
    "if",
    "then",
    "else",
    "Real",
    "'q'",
    "\u00e9",
    "\x00",
]
PROMPT = 10.0  # seconds a case may take before it counts as a hang


def _lines(draw: Any, text: str) -> str:
    lines = text.split("\n")  # never empty: "".split gives [""]
    i, j = draw(hs.integers(0, len(lines) - 1)), draw(hs.integers(0, len(lines) - 1))
    how = draw(hs.sampled_from(["drop", "duplicate", "swap"]))
    if how == "drop":
        del lines[i]
    elif how == "duplicate":
        lines.insert(i, lines[i])
    else:
        lines[i], lines[j] = lines[j], lines[i]
    return "\n".join(lines)


def _number(draw: Any, text: str) -> str:
    spans = [m.span() for m in NUMBER.finditer(text)]
    if not spans:  # an earlier mutation left none
        return text
    a, b = draw(hs.sampled_from(spans))
    return text[:a] + draw(hs.sampled_from(EXTREMES)) + text[b:]


def _token(draw: Any, text: str) -> str:
    spans = [m.span() for m in TOKEN.finditer(text)]
    if not spans:
        return text
    a, b = draw(hs.sampled_from(spans))
    how = draw(hs.sampled_from(["delete", "repeat", "insert"]))
    if how == "delete":
        return text[:a] + text[b:]
    if how == "repeat":  # deep nesting and long runs: a recursive parser's limits
        return text[:a] + text[a:b] * draw(hs.integers(2, 3000)) + text[b:]
    return text[:a] + draw(hs.sampled_from(INSERTS)) + " " + text[a:]


def _characters(draw: Any, text: str) -> str:
    if not text:
        return draw(hs.characters())
    at = draw(hs.integers(0, len(text) - 1))
    if draw(hs.booleans()):
        return text[:at]  # cut short
    return text[:at] + draw(hs.characters()) + text[at + 1 :]


@hs.composite
def mutated_sources(draw: Any) -> str:
    """One shipped Modelica example with one to three mutations."""
    text = draw(hs.sampled_from(TEXTS))
    for _ in range(draw(hs.integers(1, 3))):
        mutate = draw(hs.sampled_from([_lines, _number, _token, _characters]))
        text = mutate(draw, text)
    return text


class Hang(Exception):
    """A case that did not answer within ``PROMPT`` seconds."""


@contextmanager
def _alarm(seconds: float) -> Iterator[None]:
    def _raise(signum: int, frame: object) -> None:
        raise Hang(f"no answer within {seconds} s")

    previous = signal.signal(signal.SIGALRM, _raise)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


LOCATED = re.compile(r"^<modelica>:\d+:\d+: \S")
SHORT_RUN = {"max_steps": 20_000, "max_events": 2_000, "timeout": 2.0}


@settings(
    max_examples=CASES,
    deadline=None,
    derandomize=CASES <= 1000,  # CI replays a fixed sequence: no flakiness
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(mutated_sources())
def test_a_mutated_modelica_source_reads_to_a_model_or_a_located_error(text: str) -> None:
    note(text)
    with _alarm(PROMPT):
        try:
            model = st.Model.from_modelica(text)
        except st.ModelError as error:
            assert LOCATED.match(str(error)), f"an import error without line and column: {error}"
            return
        try:
            stop = min(float(model.experiment.get("StopTime", 1.0)), 1.0)
            model.simulate(StopTime=stop if stop > 0 else None, params=SHORT_RUN)
        except st.StictionError:
            pass  # a typed error (an invalid value, a limit, a failed run) is an answer


def test_the_corpus_is_every_shipped_modelica_example() -> None:
    assert len(CORPUS) >= 10
    for text in TEXTS:  # unmutated, every one reads and runs: the mutations start from valid models
        st.Model.from_modelica(text).simulate(StopTime=0.01)
