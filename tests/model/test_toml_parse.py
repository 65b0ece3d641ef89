"""The engine's TOML parser gives what ``tomllib`` gives (``modelfile`` uses it for speed)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import pytest
from paths import REPO

from stiction import _core
from stiction.testing import chain_toml, ladder_toml

EXAMPLES = sorted((REPO / "examples").rglob("*.toml"))


def _same(a: Any, b: Any) -> bool:
    """Equal with types and key order, NaN equal to NaN."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and math.isnan(a):
        return math.isnan(b)
    return bool(a == b)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_example_files_parse_as_tomllib_parses_them(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    assert _same(_core.parse_toml(text), tomllib.loads(text))


def test_generated_models_and_special_values() -> None:
    for text in (chain_toml(20), ladder_toml(20)):
        assert _same(_core.parse_toml(text), tomllib.loads(text))
    text = 'a = nan\nb = -inf\nc = [1, 2.5, "x", true]\n[t.u]\nv = { w = 1e-3, z = [] }\n'
    assert _same(_core.parse_toml(text), tomllib.loads(text))


def test_what_it_does_not_give_as_tomllib_is_left_to_tomllib() -> None:
    assert _core.parse_toml("a = = 1") is None  # invalid: tomllib writes the message
    assert _core.parse_toml("d = 1979-05-27T07:32:00Z") is None  # a date: tomllib's datetime
