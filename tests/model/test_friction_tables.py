"""Friction tables never make friction deliver energy (issue 29).

A negative coefficient in ``mu_pos`` (or torque in ``tau_pos``) is refused on every path a
model takes: built in Python, read from TOML or Modelica, changed by ``Model.set`` or in a
running ``Simulation``. A table whose linear extrapolation past its last row (MSL's rule)
reaches a negative coefficient during a run stops the run at that instant with
``NegativeFrictionError``, naming the element, the slip speed and the table, unless
``extrapolation = "HoldLastPoint"`` holds the last row's value.
"""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st
from stiction.model.catalogue import describe

FRICTION = ("Brake", "Clutch", "OneWayClutch", "BearingFriction")


def _table(type_name: str) -> str:
    return "tau_pos" if type_name == "BearingFriction" else "mu_pos"


@pytest.mark.parametrize("type_name", FRICTION)
def test_the_catalogue_gives_each_table_a_range_and_the_option(type_name: str) -> None:
    info = describe(type_name)
    table = info.parameter(_table(type_name))
    assert table.range == ("torques >= 0" if type_name == "BearingFriction" else "coefficients >= 0")
    assert "linear between rows" in table.description and "extrapolation" in table.description
    option = info.parameter("extrapolation")
    assert option.default == "LastTwoPoints"
    assert option.choices == ("LastTwoPoints", "HoldLastPoint")


@pytest.mark.parametrize("type_name", FRICTION)
def test_building_a_component_refuses_a_negative_value(type_name: str) -> None:
    table = _table(type_name)
    what = "torques" if type_name == "BearingFriction" else "coefficients"
    params = {table: [[0, 0.4], [10, -0.1]]}
    if type_name != "BearingFriction":
        params["fn_max"] = 10.0
    with pytest.raises(
        st.ModelError,
        match=rf"^{type_name}: parameter '{table}': {what} must be >= 0, got -0.1 in row \[10, -0.1\]$",
    ):
        st.Component(type_name, params)


def _flywheel(**brake: object) -> st.Model:
    m = st.Model("flywheel")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=10.0))
    m.add("brake", st.Brake(fn_max=10.0, **brake))
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


def test_set_a_model_file_and_modelica_refuse_it_in_the_engines_words() -> None:
    m = _flywheel()
    with pytest.raises(
        st.ModelError,
        match=r"component 'brake' \(Brake\): parameter 'mu_pos': coefficients must be >= 0, got -0.2 in row \[5, -0.2\]",
    ):
        m.set("brake.mu_pos", [[0, 0.5], [5, -0.2]])
    text = m.to_toml().replace('type = "Brake"', 'type = "Brake", mu_pos = [[0, 0.5], [5, -0.2]]')
    assert "[5, -0.2]" in text
    with pytest.raises(st.ModelError, match=r"parameter 'mu_pos': coefficients must be >= 0"):
        st.Model.loads(text)
    mo = m.to_modelica().replace("fn_max=10.0", "fn_max=10.0, mu_pos=[0, 0.5; 5, -0.2]")
    assert "mu_pos=[0, 0.5; 5, -0.2]" in mo
    with pytest.raises(st.ModelError, match=r"parameter 'mu_pos': coefficients must be >= 0"):
        st.Model.from_modelica(mo)


def test_a_running_simulation_refuses_it_and_goes_on() -> None:
    sim = _flywheel().simulation(StopTime=1.0)
    sim.advance_to(0.1)
    with pytest.raises(st.ModelError, match=r"'mu_pos': coefficients must be >= 0, got -0.2"):
        sim.set_parameter("brake.mu_pos", [[0, 0.5], [5, -0.2]])
    sim.run()
    assert sim.result()["J.w"][-1] == pytest.approx(_flywheel().simulate(StopTime=1.0)["J.w"][-1])


def test_a_table_extrapolating_below_zero_at_w_0_is_refused() -> None:
    # rows from 10 rad/s rising: linear through the first two rows, mu(0) = -0.1
    with pytest.raises(
        st.ModelError, match=r"'mu_pos': coefficients must be >= 0, but the table extrapolates to"
    ):
        _flywheel(mu_pos=[[10, 0.1], [20, 0.3]]).compile()


def _runaway(**clutch: object) -> st.Model:
    """The issue's case: a clutch table 0.35 -> 0.30 at 100 rad/s, a motor that drives the
    slip far past it (about 130 rad/s^2: 700 rad/s at 5.4 s)."""
    m = st.Model("runaway")
    m.add("J1", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.add("J2", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.add("motor", st.ConstantTorque(tau_constant=200.0))
    m.add("clutch", st.Clutch(fn_max=100.0, mu_pos=[[0, 0.35], [100, 0.30]], **clutch))
    m.add("press", st.Constant(k=1.0))
    m.connect("motor.flange", "J1.flange_a")
    m.connect("J1.flange_b", "clutch.flange_a")
    m.connect("clutch.flange_b", "J2.flange_a")
    m.connect("press.y", "clutch.f_normalized")
    return m


def test_a_coefficient_extrapolated_below_zero_stops_the_run_there() -> None:
    with pytest.raises(st.NegativeFrictionError) as caught:
        _runaway().simulate(StopTime=10.0)
    message = str(caught.value)
    assert isinstance(caught.value, st.SimulationError)
    assert "'clutch' slips at 700" in message and "mu_pos" in message
    assert "[100, 0.3]" in message and 'extrapolation = "HoldLastPoint"' in message
    t = float(message.split("at t = ")[1].split(":")[0])
    # the slip is w_rel = -130 t^2/2 ... measured: it reaches 700 rad/s where the run stopped
    r = _runaway().simulate(StopTime=t * (1 - 1e-9))
    assert abs(r["clutch.w_rel"][-1]) == pytest.approx(700.0, rel=1e-6)
    assert abs(r["clutch.mu"][-1]) < 1e-6  # the coefficient just before: still not negative
    assert r["clutch.mu"][-1] * r["clutch.w_rel"][-1] >= 0.0


def test_hold_last_point_holds_the_last_rows_value() -> None:
    r = _runaway(extrapolation="HoldLastPoint").simulate(StopTime=10.0)
    slip = np.abs(r["clutch.w_rel"])
    assert slip[-1] > 1000.0
    far = slip > 100.0
    assert np.allclose(np.abs(r["clutch.mu"][far]), 0.30, rtol=0, atol=1e-15)
    assert r.energy("clutch") > 0.0
    assert r.audit().ok()


def test_the_option_goes_through_toml_and_modelica() -> None:
    m = _runaway(extrapolation="HoldLastPoint")
    assert 'extrapolation = "HoldLastPoint"' in m.to_toml()
    assert st.Model.loads(m.to_toml()) == m
    mo = m.to_modelica()
    assert "extrapolation=Modelica.Blocks.Types.Extrapolation.HoldLastPoint" in mo
    back = st.Model.from_modelica(mo)
    assert back.components["clutch"].params["extrapolation"] == "HoldLastPoint"


def test_a_valid_table_runs_as_before() -> None:
    # a falling table whose extrapolation stays positive over the run: no error, MSL's values
    r = _runaway().simulate(StopTime=2.0)
    slip = np.abs(r["clutch.w_rel"])
    assert slip[-1] > 100.0  # past the last row, extrapolated
    last = slip[-1]
    assert abs(r["clutch.mu"][-1]) == pytest.approx(0.35 - 0.05 * last / 100.0, rel=1e-12)
