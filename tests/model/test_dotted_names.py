"""Hierarchical component names (``front.clutch``, as Modelica tools flatten a user's class)
end to end: built, set, swept, run, read by name, written to TOML, Modelica, CSV, Parquet and
.mat and read back. The dotted model is CoupledClutches with ``clutch1`` -> ``clutch.c1`` and
``J2`` -> ``J2.shaft``: names that sort as the originals do, so the engine (which compiles the
components in sorted order) runs it bit for bit as the original."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from paths import EXAMPLES

import stiction as st
from stiction.model.catalogue import unit_of

COUPLED = EXAMPLES / "msl" / "CoupledClutches.toml"
RENAMES = {"clutch1": "clutch.c1", "J2": "J2.shaft"}


def rename(name: str) -> str:
    """A variable, port or parameter of the original under its dotted name."""
    for old, new in RENAMES.items():
        if name == old or name.startswith(old + "."):
            return new + name[len(old) :]
    return name


def dotted() -> st.Model:
    """CoupledClutches rebuilt through the Python API under the dotted names."""
    original = st.Model.load(COUPLED)
    m = st.Model(original.name)
    for name, comp in original.components.items():
        m.add(rename(name), comp)
    for a, b in original.connections:
        m.connect(rename(a), rename(b))
    m.experiment = dict(original.experiment)
    return m


@cache
def original_result() -> st.Result:
    return st.Model.load(COUPLED).simulate()


def assert_renamed(original: st.Result, result: st.Result) -> None:
    assert result.names == [rename(n) for n in original.names]
    for name in original.names:
        assert np.array_equal(original[name], result[rename(name)]), name


def test_a_dotted_model_runs_as_the_original_with_dotted_variables() -> None:
    r = dotted().simulate()
    assert "clutch.c1.flange_a.tau" in r.names and "J2.shaft.w" in r.names
    assert_renamed(original_result(), r)
    # a variable's unit is found through its component, the longest prefix
    types = {name: c.type for name, c in dotted().components.items()}
    assert unit_of("clutch.c1.flange_a.tau", types) == "N.m"
    assert unit_of("J2.shaft.w", types) == "rad/s"


def test_set_sweep_and_a_running_simulation_take_the_full_dotted_name() -> None:
    m = dotted().set("clutch.c1.fn_max", 35.0).set("J2.shaft.w", 1.5)
    assert m["clutch.c1"].params["fn_max"] == 35.0
    plain = st.Model.load(COUPLED).set("clutch1.fn_max", 35.0).set("J2.w", 1.5)
    assert_renamed(plain.simulate(), m.simulate())
    with pytest.raises(st.ModelError, match=r"parameter 'fnmax'.*did you mean 'fn_max'"):
        dotted().set("clutch.c1.fnmax", 1.0)
    with pytest.raises(st.ModelError, match=r"did you mean .*'clutch.c1'"):
        dotted().set("clutch.c2.fn_max", 1.0)
    swept = st.sweep(dotted(), {"clutch.c1.fn_max": [10.0, 35.0]}, ["max(clutch.c1.w_rel)"], progress=False)
    expected = st.sweep(
        st.Model.load(COUPLED), {"clutch1.fn_max": [10.0, 35.0]}, ["max(clutch1.w_rel)"], progress=False
    )
    got, want = swept.table["max(clutch.c1.w_rel)"], expected.table["max(clutch1.w_rel)"]
    assert list(got) == list(want) and got[0] != got[1]
    sim = dotted().simulation()
    sim.advance_to(0.5)
    sim.set_parameter("clutch.c1.fn_max", 35.0)
    sim.advance_to(1.0)
    assert np.isfinite(sim["clutch.c1.w_rel"])


def test_a_name_that_starts_another_components_path_is_refused_naming_both() -> None:
    m = dotted()
    with pytest.raises(st.ModelError, match=r"'clutch'.*'clutch.c1'"):
        m.add("clutch", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match=r"'J2.shaft.x'.*'J2.shaft'"):
        m.add("J2.shaft.x", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match="path of them"):
        m.add("front..clutch", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match=r"'clutch2.extra'.*'clutch2'"):
        m.add("clutch2.extra", st.Inertia(J=1.0))
    m.add("clutch.c10", st.Inertia(J=1.0))  # clutch.c1 starts its text, not its path
    # a name written directly into the dict is refused by the engine, naming both
    bad = dotted()
    bad.components["clutch"] = st.Inertia(J=1.0)
    with pytest.raises(st.ModelError, match=r"'clutch'.*'clutch.c1'"):
        bad.simulate()


def test_toml_and_modelica_round_trips_keep_the_dotted_names(tmp_path: Path) -> None:
    m = dotted().variable("slip", "clutch.c1.w_rel - 2*J2.shaft.w")
    text = m.to_toml()
    assert '\n"clutch.c1" = { type = "Clutch"' in text and '"clutch.c1.flange_b"' in text
    m.save(tmp_path / "m.toml")
    assert st.Model.load(tmp_path / "m.toml") == m
    # a table per component, as a user may write it
    tables = text.replace('"clutch.c1" = { type = "Clutch", peak = 1.1, fn_max = 20.0 }\n', "")
    tables += '\n[components."clutch.c1"]\ntype = "Clutch"\npeak = 1.1\nfn_max = 20.0\n'
    assert st.Model.loads(tables).components == m.components
    mo = m.to_modelica()
    assert "Clutch 'clutch.c1'(" in mo and "connect('clutch.c1'.flange_b, 'J2.shaft'.flange_a)" in mo
    assert "Real slip = 'clutch.c1'.w_rel - 2*'J2.shaft'.w;" in mo
    again = st.Model.from_modelica(mo)
    assert list(again.components) == list(m.components) and again.connections == m.connections
    a, b = m.simulate(), again.simulate()
    for name in ("clutch.c1.w_rel", "J2.shaft.w", "slip"):
        assert np.array_equal(a[name], b[name]), name


@pytest.mark.parametrize("suffix", [".csv", ".mat", ".parquet"])
def test_result_files_carry_the_dotted_names(tmp_path: Path, suffix: str) -> None:
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    r = dotted().simulate()
    path = tmp_path / f"r{suffix}"
    r.save(path, outputs=["clutch.c1.*", "J2.shaft.w"])
    back = st.Result.load(path)
    assert "clutch.c1.flange_a.tau" in back.names and "J2.shaft.w" in back.names
    for name in ("clutch.c1.w_rel", "clutch.c1.flange_a.tau", "J2.shaft.w"):
        assert np.array_equal(back[name], r[name]), name
