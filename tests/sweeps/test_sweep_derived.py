"""Derived variables (``Model.variable``, ``[variables]``) in sweeps: the core computes them
as result variables, so a sweep's metric of one equals ``Result.metric`` and NumPy over
``r[name]`` of the single run to the last bit, its trajectory is the single run's column on the
grid, and a sweep over a top-level parameter a derived variable reads moves the variable too."""

from __future__ import annotations

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st


def coupled() -> st.Model:
    m = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    m.parameters["k"] = 2.0
    m.variable("slip", "J1.w - J2.w")
    m.variable("kslip", "k * abs(slip) + der(J1.phi)")
    m.variable("heat", "clutch1.tau * der(clutch1.phi_rel)")
    return m


METRICS = ["max(slip)", "min(slip)", "integral(kslip)", "integral(heat)", "time_of(slip < 5)", "final(kslip)"]


def test_sweep_metrics_of_derived_variables_equal_the_single_runs() -> None:
    m = coupled()
    variants = st.grid({"clutch1.fn_max": [10.0, 30.0], "k": [1.0, 3.0]})
    result = st.sweep(m, variants, METRICS, outputs=["slip", "kslip"], progress=False, workers=2)
    assert list(result.table["status"]) == ["ok"] * 4
    grid = result.time
    for i, row in result.table.iterrows():
        r = m.simulate(params={"clutch1.fn_max": row["clutch1.fn_max"], "k": row["k"]})
        for metric in METRICS:
            assert row[metric] == r.metric(metric), metric  # to the last bit
        assert 0 < row["time_of(slip < 5)"] < 3
        assert row["max(slip)"] == np.max(r["slip"]) and row["min(slip)"] == np.min(r["slip"])
        assert row["integral(heat)"] == pytest.approx(np.trapezoid(r["heat"], r.time), rel=1e-12)
        np.testing.assert_array_equal(r["slip"], r["J1.w"] - r["J2.w"])
        np.testing.assert_array_equal(r["kslip"], row["k"] * np.abs(r["slip"]) + r["J1.w"])
        np.testing.assert_array_equal(r["heat"], r["clutch1.tau"] * r["clutch1.w_rel"])
        # the grid's value: the last row at each instant
        rows = [np.flatnonzero(np.abs(r.time - tg) <= 1e-12 * max(1.0, abs(tg)))[-1] for tg in grid]
        for name in ("slip", "kslip"):
            np.testing.assert_array_equal(result.trajectories[name][i], r[name][rows])


def test_a_run_reads_derived_variables_from_the_core() -> None:
    m = coupled()
    r = m.simulate(params={"k": 5.0})
    assert r.names[-3:] == ["slip", "kslip", "heat"]
    np.testing.assert_array_equal(r["kslip"], 5.0 * np.abs(r["slip"]) + r["J1.w"])
    np.testing.assert_array_equal(m.simulate()["kslip"], 2.0 * np.abs(r["slip"]) + r["J1.w"])
    np.testing.assert_array_equal(r.data[:, -3], r["slip"])
    assert not r.to_pandas()["heat"].isna().any()
    live = m.simulate(params={"k": 5.0}, record="all")  # the table computed while the run goes
    np.testing.assert_array_equal(live.data, r.data)
    sim = m.simulation()
    sim.advance_to(0.3)
    assert sim.get("slip") == sim.get("J1.w") - sim.get("J2.w")


def test_a_derived_variable_the_core_cannot_compute_is_a_model_error() -> None:
    m = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    m.variable("m", "der(clutch1.mode)")
    with pytest.raises(st.ModelError, match=r"variable 'm' = \"der\(clutch1.mode\)\": der\(clutch1.mode\)"):
        m.check()
    with pytest.raises(st.ModelError, match="variable 'm'"):
        st.sweep(m, st.grid({"clutch1.fn_max": [10.0]}), ["max(J1.w)"], progress=False)
    m = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    m.variable("x", "J1.ww * 2")
    with pytest.raises(st.ModelError, match=r"unknown variable 'J1.ww' \(variables of J1: J1.phi"):
        m.simulate()


def test_the_core_knows_every_function_and_constant_of_the_expression_language() -> None:
    """The engine evaluates derived variables; the Python evaluator (parameters) lists the same
    functions and constants, and both compute the same values (to libm's rounding)."""
    from stiction.expressions.evaluate import CONSTANTS, FUNCTIONS

    m = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    names = {}
    for k, (func, f) in enumerate(FUNCTIONS.items()):
        two = func.split(".")[-1] in ("atan2", "max", "min")
        m.variable(f"f{k}", f"{func}(0.05 * J1.w, 0.1 * J2.w)" if two else f"{func}(0.05 * J1.w)")
        names[f"f{k}"] = (f, two)
    for k, name in enumerate(CONSTANTS):
        m.variable(f"c{k}", name)
    r = m.simulate()
    x, y = 0.05 * r["J1.w"], 0.1 * r["J2.w"]
    for var, (f, two) in names.items():
        with np.errstate(all="ignore"):
            expected = f(x, y) if two else f(x)
        np.testing.assert_allclose(r[var], expected, rtol=1e-15, atol=0, equal_nan=True, err_msg=var)
    for k, value in enumerate(CONSTANTS.values()):
        assert np.all(r[f"c{k}"] == value)
