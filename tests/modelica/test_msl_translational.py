"""MSL's Translational examples written in MSL's own style (examples/msl-translational/*.mo):
each imports to the same model as its TOML twin, gives the identical result, and stays in the
2e-3 tube of its MAP-LIB reference (tests/data/msl-translational)."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from paths import DATA, EXAMPLES

import stiction as st

DIR = EXAMPLES / "msl-translational"
REFS = DATA / "msl-translational"
NAMES = sorted(p.stem for p in DIR.glob("*.mo"))


@cache
def _runs(name: str) -> tuple[st.Model, st.Result, st.Model, st.Result]:
    mo = st.Model.from_modelica(DIR / f"{name}.mo")
    toml = st.Model.load(DIR / f"{name}.toml")
    return mo, mo.simulate(), toml, toml.simulate()


def test_the_translational_examples_are_here() -> None:
    assert {"Brake", "PreLoad"} <= set(NAMES)
    assert {p.stem for p in DIR.glob("*.toml")} == set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_modelica_twin_is_the_same_model_with_the_identical_result(name: str) -> None:
    mo, r_mo, toml, r_toml = _runs(name)
    assert list(mo.components) == list(toml.components)
    for comp, c in toml.components.items():
        assert mo.components[comp].type == c.type
    as_sets = lambda m: {frozenset(pair) for pair in m.connections}
    assert as_sets(mo) == as_sets(toml)
    for signal in r_toml.names:
        assert np.array_equal(r_mo[signal], r_toml[signal]), signal


@pytest.mark.parametrize("name", NAMES)
def test_modelica_file_stays_in_the_msl_tube(name: str) -> None:
    _, r_mo, _, _ = _runs(name)
    listed = REFS / f"{name}.signals.txt"
    report = st.compare(r_mo, REFS / f"{name}.csv", tolerance=2e-3, signals=listed)
    assert len(report) == len(listed.read_text().split()) - 1  # minus time
    assert report.passed, str(report)
