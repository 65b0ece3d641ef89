"""Fade (issue 32, beyond MSL; docs/fade.md) through Python: the adiabatic stop's closed form,
the energy audit with fade on, a sweep over a ``mu_T`` cell, the ``.mo`` round trip through the
``Stiction.Components.Brake`` extension, and bad input refused by name before any run."""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

J, W0, FN, C, T0, MU0, BETA = 2.0, 100.0, 500.0, 1000.0, 293.15, 0.4, 0.01
T1 = T0 + 20.0  # the run heats the disc by J·w0²/(2·C) = 10 K: the table covers it


def _mu_t(beta: float = BETA) -> list[list[float]]:
    """mu = mu0 − beta·(T − T0) as a factor on mu0, exactly linear over [T0, T1]."""
    return [[T0, 1.0], [T1, 1.0 - beta / MU0 * (T1 - T0)]]


def _adiabatic(beta: float = BETA) -> st.Model:
    """A disc J at w0 braked by a constant normal force, its loss heating the capacity C."""
    m = st.Model("fade")
    m.add("disc", st.Inertia(J=J, w=W0))
    m.add("brake", st.Brake(fn_max=FN, mu_pos=[[0.0, MU0]], useHeatPort=True, mu_T=_mu_t(beta)))
    m.add("press", st.Constant(k=1.0))
    m.add("cap", st.HeatCapacitor(C=C, T={"start": T0, "fixed": True}))
    m.connect("disc.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "cap.port")
    m.experiment.update(StopTime=2.0, Interval=0.125, Tolerance=1e-12)
    return m


def _t_stop(beta: float = BETA) -> float:
    """`J·w' = −cgeo·fn·(A + B·w²)` (cgeo = 1) with `T = T0 + J·(w0² − w²)/(2·C)`."""
    a, b = MU0 - beta * J * W0**2 / (2 * C), beta * J / (2 * C)
    return J / (FN * math.sqrt(a * b)) * math.atan(W0 * math.sqrt(b / a))


def test_the_adiabatic_stop_with_linear_fade_and_its_energy_audit() -> None:
    r = _adiabatic().simulate()
    locked = np.asarray(r["brake.locked"]) > 0.5
    assert float(np.asarray(r.time)[locked.argmax()]) == pytest.approx(_t_stop(), rel=1e-8)
    w, temp = np.asarray(r["disc.w"]), np.asarray(r["cap.T"])
    np.testing.assert_allclose(temp, T0 + J * (W0**2 - w**2) / (2 * C), rtol=1e-10)
    audit = r.audit()
    assert audit.ok(), str(audit)
    # the heat the disc took is the kinetic energy the brake took away
    assert C * (temp[-1] - T0) == pytest.approx(0.5 * J * W0**2, rel=1e-10)


def test_a_sweep_over_the_fade_changes_the_stop_as_the_closed_form_says() -> None:
    """A ``mu_T`` cell as an expression over a top-level parameter (how tables sweep), and the
    whole table as a swept value: the stop time follows beta."""
    m = _adiabatic()
    m.parameters["fade_end"] = 1.0
    m.components["brake"].params["mu_T"] = [[T0, 1.0], [T1, "fade_end"]]
    ends = [_mu_t(beta)[1][1] for beta in (0.0, 0.01)]
    result = st.sweep(m, {"fade_end": ends}, ["time_of(brake.locked)"], progress=False)
    got = list(result.table["time_of(brake.locked)"])
    assert got[0] == pytest.approx(J * W0 / (MU0 * FN), rel=1e-8)  # no fade: J·w0/(mu0·fn)
    assert got[1] == pytest.approx(_t_stop(), rel=1e-8)
    tables = [_mu_t(beta) for beta in (0.005, 0.01)]
    result = st.sweep(_adiabatic(), {"brake.mu_T": tables}, ["time_of(brake.locked)"], progress=False)
    got = list(result.table["time_of(brake.locked)"])
    assert got == pytest.approx([_t_stop(0.005), _t_stop(0.01)], rel=1e-8)


def test_a_faded_brake_round_trips_through_modelica_as_a_stiction_class() -> None:
    model = _adiabatic()
    text = model.to_modelica()
    assert "  Stiction.Components.Brake brake(" in text and "mu_T=[" in text
    back = st.Model.from_modelica(text)
    assert back.components["brake"].type == "Brake"
    assert back.components["brake"].params == model.components["brake"].params
    r, r_back = model.simulate(), back.simulate()
    np.testing.assert_array_equal(r.data, r_back.data)
    plain = st.Model("plain")  # without fade: MSL's own class
    plain.add("brake", st.Brake(fn_max=1.0))
    assert "Modelica.Mechanics.Rotational.Components.Brake brake(" in plain.to_modelica()


def test_a_clutch_with_mu_table_and_mu_fn_round_trips_too() -> None:
    m = st.Model("clutch_fade")
    m.add("a", st.Inertia(J=1.0, w=50.0))
    m.add("b", st.Inertia(J=1.0, w=0.0))
    table = [[0.0, 293.15, 400.0], [0.0, 0.4, 0.3], [100.0, 0.35, 0.25]]
    m.add(
        "clutch",
        st.Clutch(fn_max=100.0, useHeatPort=True, mu_table=table, mu_fn=[[0.0, 1.0], [200.0, 0.8]]),
    )
    m.add("press", st.Constant(k=1.0))
    m.add("cap", st.HeatCapacitor(C=50.0, T={"start": 293.15, "fixed": True}))
    for a, b in [
        ("a.flange_b", "clutch.flange_a"),
        ("clutch.flange_b", "b.flange_a"),
        ("press.y", "clutch.f_normalized"),
        ("clutch.heatPort", "cap.port"),
    ]:
        m.connect(a, b)
    m.experiment.update(StopTime=2.0, Interval=0.01)
    text = m.to_modelica()
    assert "Stiction.Components.Clutch clutch(" in text
    back = st.Model.from_modelica(text)
    r, r_back = m.simulate(), back.simulate()
    np.testing.assert_array_equal(r.data, r_back.data)
    assert r["clutch.locked"][-1] == 1.0  # the clutch locks the two discs together
    assert r.audit().ok()


@pytest.mark.parametrize(
    ("params", "name", "words"),
    [
        ({"mu_T": [[300.0, 1.0], [400.0, -0.5]]}, "mu_T", "factors must be >= 0"),
        ({"mu_T": [[400.0, 1.0], [300.0, 0.5]]}, "mu_T", "strictly increasing"),
        ({"mu_table": [[0.0, 300.0], [0.0, 0.5], [0.0, 0.4]]}, "mu_table", "strictly increasing"),
        ({"mu_table": [[0.0, 300.0, 400.0], [0.0, 0.5]]}, "mu_table", "columns"),
    ],
)
def test_bad_fade_tables_are_refused_by_name_before_any_run(params: dict, name: str, words: str) -> None:
    m = _adiabatic()
    with pytest.raises(st.ModelError, match=rf"brake.*{name}.*{words}|{name}.*brake.*{words}"):
        m.components["brake"].params.update(params)
        m.compile()


def test_a_fade_without_its_heat_port_is_refused_by_name() -> None:
    m = st.Model("no_port")
    m.add("disc", st.Inertia(J=1.0, w=1.0))
    m.add("brake", st.Brake(fn_max=10.0, mu_T=[[300.0, 1.0]]))
    m.add("press", st.Constant(k=1.0))
    m.connect("disc.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    with pytest.raises(st.ModelError, match=r"brake.*mu_T.*useHeatPort = true"):
        m.simulate()


def test_a_unit_fade_leaves_coupled_clutches_bit_identical() -> None:
    """The fade path with factors of exactly 1 computes MSL's values to the bit (and without
    fade parameters the path is not taken at all: the MSL examples are bit-identical)."""
    from paths import MSL_EXAMPLES

    plain = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    faded = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    for name in ("clutch1", "clutch2", "clutch3"):
        faded.components[name].params["mu_fn"] = [[0.0, 1.0]]
    assert "Stiction.Components.Clutch clutch1(" in faded.to_modelica()
    np.testing.assert_array_equal(plain.simulate().data, faded.simulate().data)


def test_a_translational_brake_with_mu_table_round_trips_and_heats_by_the_energy_it_takes() -> None:
    m = st.Model("sliding_block")
    m.add("mass", st.translational.Mass(m=2.0, v=10.0))
    table = [[0.0, 293.15, 313.15], [0.0, 0.5, 0.3], [5.0, 0.45, 0.25]]
    m.add("brake", st.translational.Brake(fn_max=10.0, useHeatPort=True, mu_table=table))
    m.add("press", st.Constant(k=1.0))
    m.add("cap", st.HeatCapacitor(C=5.0, T={"start": 293.15, "fixed": True}))
    for a, b in [
        ("mass.flange_b", "brake.flange_a"),
        ("press.y", "brake.f_normalized"),
        ("brake.heatPort", "cap.port"),
    ]:
        m.connect(a, b)
    m.experiment.update(StopTime=3.0, Interval=0.01, Tolerance=1e-10)
    text = m.to_modelica()
    assert "  Stiction.Components.Translational.Brake brake(" in text
    back = st.Model.from_modelica(text)
    r = m.simulate()
    np.testing.assert_array_equal(r.data, back.simulate().data)
    v, temp = np.asarray(r["mass.v"]), np.asarray(r["cap.T"])
    np.testing.assert_allclose(5.0 * (temp - 293.15), 0.5 * 2.0 * (100.0 - v**2), rtol=1e-8, atol=1e-9)
    assert r.audit().ok()
