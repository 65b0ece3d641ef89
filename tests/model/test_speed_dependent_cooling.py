"""Cooling that depends on speed (issue 32): a SpeedSensor's w through Abs into a
CombiTable1Ds of Gc over |w|, fed to a Convection, so a disc cools faster while the wheel
turns; and BodyRadiation, ``Q_flow = Gr·σ·(T_a⁴ − T_b⁴)``.

Closed forms: at constant speed the disc (HeatCapacitor C) cools as
``T_a + (T0 − T_a)·exp(−Gc·t/C)`` with Gc the table's value at that speed; once the wheel has
stopped, with the table's value at rest. Radiation alone to a fixed temperature a solves
``C·dT/dt = −Gr·σ·(T⁴ − a⁴)`` implicitly: ``F(T) − F(T0) = −Gr·σ·t/C`` with
``F(T) = (ln((T − a)/(T + a)) − 2·atan(T/a))/(4a³)``."""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

SIGMA = 5.670374419e-8
C, T0, TA = 500.0, 600.0, 300.0
TABLE = [[0.0, 2.0], [100.0, 12.0]]  # Gc [W/K] over |w| [rad/s]


def gc(w: float) -> float:
    return float(np.interp(abs(w), [r[0] for r in TABLE], [r[1] for r in TABLE]))


def cooled_disc(name: str, **table: object) -> st.Model:
    """A disc's heat capacity convecting to 300 K through a Gc tabled over the wheel's |w|."""
    m = st.Model(name)
    m.add("wheel", st.Inertia(J=1.0))
    m.add("sensor", st.SpeedSensor())
    m.add("abs1", st.Abs())
    m.add("gcTable", st.CombiTable1Ds(table=TABLE, **table))
    m.add("convection", st.Convection())
    m.add("disc", st.HeatCapacitor(C=C, T=T0))
    m.add("ambient", st.FixedTemperature(T=TA))
    m.connect("wheel.flange_b", "sensor.flange")
    m.connect("sensor.w", "abs1.u")
    m.connect("abs1.y", "gcTable.u")
    m.connect("gcTable.y[1]", "convection.Gc")
    m.connect("disc.port", "convection.solid")
    m.connect("convection.fluid", "ambient.port")
    return m


@pytest.mark.parametrize("w", [50.0, -50.0, 150.0])
def test_a_disc_cools_at_the_tabled_conductance_of_its_constant_speed(w: float) -> None:
    """|w| through Abs (−50 gives 50's Gc); 150 rad/s is beyond the table: HoldLastPoint
    holds 12 W/K (LastTwoPoints would extrapolate to 17)."""
    m = cooled_disc("constant_speed", extrapolation="HoldLastPoint")
    m.add("drive", st.ConstantSpeed(w_fixed=w))
    m.connect("drive.flange", "wheel.flange_a")
    r = m.simulate(StopTime=300.0, Interval=1.0, Tolerance=1e-12)
    g = gc(w)
    np.testing.assert_allclose(r["convection.Gc"], g, rtol=1e-15)
    expected = TA + (T0 - TA) * np.exp(-g * r.time / C)
    np.testing.assert_allclose(r["disc.T"], expected, rtol=1e-8, atol=0)


def test_last_two_points_extrapolates_the_conductance_linearly() -> None:
    m = cooled_disc("extrapolated")
    m.add("drive", st.ConstantSpeed(w_fixed=150.0))
    m.connect("drive.flange", "wheel.flange_a")
    r = m.simulate(StopTime=10.0, Interval=1.0)
    np.testing.assert_allclose(r["convection.Gc"], 17.0, rtol=1e-15)


def braked_wheel() -> st.Model:
    """The wheel spins at 50 rad/s and a brake (torque 1 N·m) stops it at t = 50 s."""
    m = cooled_disc("stopping")
    m.components["wheel"].params["w"] = {"start": 50.0, "fixed": True}
    m.add("brake", st.Brake(mu_pos=[[0.0, 0.5]], fn_max=2.0, cgeo=1.0))
    m.add("press", st.Constant(k=1.0))
    m.connect("wheel.flange_a", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


def on_grid(r: st.Result, *names: str) -> list[np.ndarray]:
    """Time and the named variables without the second row of each event (for gradients)."""
    keep = np.diff(r.time, prepend=-np.inf) > 0
    return [r.time[keep], *(r[n][keep] for n in names)]


def test_a_disc_cools_slower_once_the_wheel_has_stopped() -> None:
    r = braked_wheel().simulate(StopTime=200.0, Interval=0.5, Tolerance=1e-12)
    t, temp, w = on_grid(r, "disc.T", "wheel.w")
    stops = [e.time for e in r.events if e.component == "brake" and e.new_mode == 0]
    assert stops and abs(stops[0] - 50.0) < 1e-6, r.events
    # every row: the disc's rate is the tabled Gc at the wheel's speed
    rate = np.gradient(temp, t)
    inside = (np.abs(t - 50.0) > 2.0) & (t > 1.0) & (t < 199.0)
    expected = -np.array([gc(x) for x in w]) * (temp - TA) / C
    np.testing.assert_allclose(rate[inside], expected[inside], rtol=2e-4)
    # after the stop: the exponential of the conductance at rest, from the stop on
    after = t >= 50.0
    t_s = t[after][0]
    k_s = np.searchsorted(t, t_s)
    closed = TA + (temp[k_s] - TA) * np.exp(-gc(0.0) * (t[after] - t_s) / C)
    np.testing.assert_allclose(temp[after], closed, rtol=1e-8)
    # slower than it was while turning (2 W/K against up to 7 W/K), and slower than if the
    # wheel had kept turning at its last tabled speed
    slope_turning = -rate[(t > 5) & (t < 10)].mean() / (temp[(t > 5) & (t < 10)].mean() - TA)
    slope_stopped = -rate[(t > 100) & (t < 150)].mean() / (temp[(t > 100) & (t < 150)].mean() - TA)
    assert slope_stopped < 0.4 * slope_turning
    np.testing.assert_allclose(slope_stopped, gc(0.0) / C, rtol=1e-3)


def _f(temp: np.ndarray, a: float) -> np.ndarray:
    return (np.log((temp - a) / (temp + a)) - 2.0 * np.arctan(temp / a)) / (4.0 * a**3)


def radiating(gr: float) -> st.Model:
    m = st.Model("radiation")
    m.add("disc", st.HeatCapacitor(C=100.0, T=800.0))
    m.add("radiation", st.BodyRadiation(Gr=gr))
    m.add("ambient", st.FixedTemperature(T=TA))
    m.connect("disc.port", "radiation.port_a")
    m.connect("radiation.port_b", "ambient.port")
    return m


def test_radiation_follows_its_implicit_closed_form() -> None:
    gr, c = 0.05, 100.0
    r = radiating(gr).simulate(StopTime=600.0, Interval=2.0, Tolerance=1e-12)
    temp, t = r["disc.T"], r.time
    assert temp[-1] < 450.0  # cooled most of the way
    residual = _f(temp, TA) - _f(np.array([800.0]), TA) + gr * SIGMA * t / c
    # the residual in F is a temperature error times F'(T) = 1/(T⁴ − a⁴)
    error = residual * (temp**4 - TA**4)
    assert np.max(np.abs(error) / temp) < 1e-8, np.max(np.abs(error) / temp)
    q = gr * SIGMA * (temp**4 - TA**4)
    np.testing.assert_allclose(r["radiation.Q_flow"], q, rtol=1e-13)
    np.testing.assert_allclose(r["radiation.port_b.Q_flow"], -q, rtol=1e-13)
    np.testing.assert_allclose(r["radiation.dT"], temp - TA, rtol=1e-13)


def test_radiation_from_an_algebraic_heat_port_is_refused_by_name() -> None:
    """A brake's heat port with no capacity has an algebraic temperature: with radiation its
    balance is quartic, which the thermal network does not solve."""
    m = st.Model("quartic")
    m.add("J", st.Inertia(J=1.0, w=10.0))
    m.add("brake", st.Brake(mu_pos=[[0.0, 0.5]], fn_max=2.0, useHeatPort=True))
    m.add("press", st.Constant(k=1.0))
    m.add("radiation", st.BodyRadiation(Gr=0.5))
    m.add("ambient", st.FixedTemperature(T=TA))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "radiation.port_a")
    m.connect("radiation.port_b", "ambient.port")
    with pytest.raises(st.ModelError, match=r"radiation.*brake\.heatPort.*nonlinear"):
        m.simulate(StopTime=1.0)
    with pytest.raises(st.ModelError, match="Gr"):
        radiating(-1.0).simulate(StopTime=1.0)


def test_bad_tables_are_refused_by_name() -> None:
    m = cooled_disc("bad", columns=[3])
    m.add("drive", st.ConstantSpeed(w_fixed=1.0))
    m.connect("drive.flange", "wheel.flange_a")
    with pytest.raises(st.ModelError, match="gcTable.*columns"):
        m.simulate(StopTime=1.0)
    m = cooled_disc("bad2")
    m.components["gcTable"].params["table"] = [[1.0, 2.0], [0.0, 3.0]]
    m.add("drive", st.ConstantSpeed(w_fixed=1.0))
    m.connect("drive.flange", "wheel.flange_a")
    with pytest.raises(st.ModelError, match="gcTable.*table.*increasing"):
        m.simulate(StopTime=1.0)


MSL_STYLE = """
model CoolingWheel "A braked wheel whose disc cools faster while it turns"
  Modelica.Mechanics.Rotational.Components.Inertia wheel(J=1, w(start=50, fixed=true));
  Modelica.Mechanics.Rotational.Components.Brake brake(mu_pos=[0, 0.5], fn_max=2, cgeo=1);
  Modelica.Blocks.Sources.Constant press(k=1);
  Modelica.Mechanics.Rotational.Sensors.SpeedSensor sensor;
  Modelica.Blocks.Math.Abs abs1;
  Modelica.Blocks.Tables.CombiTable1Ds gcTable(table=[0, 2; 100, 12],
    extrapolation=Modelica.Blocks.Types.Extrapolation.HoldLastPoint);
  Modelica.Thermal.HeatTransfer.Components.Convection convection;
  Modelica.Thermal.HeatTransfer.Components.BodyRadiation radiation(Gr=0.02);
  Modelica.Thermal.HeatTransfer.Components.HeatCapacitor disc(C=500, T(start=600, fixed=true));
  Modelica.Thermal.HeatTransfer.Sources.FixedTemperature ambient(T=300);
equation
  connect(wheel.flange_a, brake.flange_a);
  connect(press.y, brake.f_normalized);
  connect(wheel.flange_b, sensor.flange);
  connect(sensor.w, abs1.u);
  connect(abs1.y, gcTable.u);
  connect(gcTable.y[1], convection.Gc);
  connect(disc.port, convection.solid);
  connect(convection.fluid, ambient.port);
  connect(disc.port, radiation.port_a);
  connect(radiation.port_b, ambient.port);
  annotation (experiment(StopTime=200, Interval=0.5));
end CoolingWheel;
"""


def test_an_msl_style_model_imports_exports_and_imports_to_the_same_result() -> None:
    m = st.Model.from_modelica(MSL_STYLE)
    types = {n: c.type for n, c in m.components.items()}
    assert types["gcTable"] == "CombiTable1Ds" and types["abs1"] == "Abs"
    assert types["radiation"] == "BodyRadiation"
    r = m.simulate()
    text = m.to_modelica()
    for cls in (
        "Modelica.Blocks.Tables.CombiTable1Ds",
        "Modelica.Blocks.Math.Abs",
        "Modelica.Thermal.HeatTransfer.Components.BodyRadiation",
        "Modelica.Blocks.Types.Extrapolation.HoldLastPoint",
    ):
        assert cls in text, cls
    assert "gcTable.y[1]" in text
    back = st.Model.from_modelica(text)
    r2 = back.simulate()
    for name in ("disc.T", "convection.Gc", "radiation.Q_flow", "wheel.w"):
        np.testing.assert_array_equal(r[name], r2[name])
    # and the same as the TOML it writes
    again = st.Model.loads(m.to_toml()).simulate()
    np.testing.assert_array_equal(r["disc.T"], again["disc.T"])
    # the disc lost heat to both, and cooled slower after the wheel stopped at 50 s
    t, temp = on_grid(r, "disc.T")
    rate = -np.gradient(temp, t)
    assert math.isfinite(rate[-1]) and rate[(t > 55) & (t < 60)].mean() < rate[(t > 40) & (t < 45)].mean()


def test_a_table_of_several_columns_outputs_each_and_round_trips() -> None:
    """``columns = {2, 3}``: outputs y[1] and y[2], each linear in its column (u = 2·t)."""
    m = st.Model("two_columns")
    m.add("ramp", st.Ramp(height=2.0, duration=1.0))
    m.add("t", st.CombiTable1Ds(table=[[0, 0, 10], [1, 1, 20], [2, 4, 30]], columns=[2, 3]))
    m.add("g1", st.Gain(k=1.0))
    m.add("g2", st.Gain(k=1.0))
    m.connect("ramp.y", "t.u")
    m.connect("t.y[1]", "g1.u")
    m.connect("t.y[2]", "g2.u")
    r = m.simulate(StopTime=1.0, Interval=0.25)
    np.testing.assert_allclose(r["g1.y"], [0.0, 0.5, 1.0, 2.5, 4.0], rtol=1e-15)
    np.testing.assert_allclose(r["g2.y"], [10.0, 15.0, 20.0, 25.0, 30.0], rtol=1e-15)
    text = m.to_modelica()
    assert "connect(t.y[2], g2.u);" in text and "columns={2, 3}" in text
    back = st.Model.from_modelica(text)
    np.testing.assert_array_equal(back.simulate(StopTime=1.0, Interval=0.25)["g2.y"], r["g2.y"])
    with pytest.raises(st.ModelError, match=r"y\[3\]"):
        m.connect("t.y[3]", "g2.u")
