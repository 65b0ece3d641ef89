"""Inputs that used to abort, hang or mislead: each now runs correctly or fails with a reason.

Found in review: a Pulse with a tiny period scheduled billions of events; time events a
rounding error apart aborted the integrator; a massless shaft held by a locked brake was
reported singular; an overflow returned NaN silently; a fixed temperature's heat flow had the
wrong sign; a TimeTable leaked its table before startTime.
"""

from __future__ import annotations

import numpy as np
import pytest
from paths import REPO

import stiction as st
from stiction import _core


def _driven(source: st.Component) -> st.Model:
    """A free inertia J = 1 driven by the signal of `source` as a torque."""
    m = st.Model("driven")
    m.add("src", source)
    m.add("drive", st.Torque())
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.connect("src.y", "drive.tau")
    m.connect("drive.flange", "J.flange_a")
    return m


def test_a_pulse_far_shorter_than_the_run_is_refused() -> None:
    """A 1 ns period over 1 s is 2e9 time events: refused at once, naming the block."""
    with pytest.raises(st.ModelError, match=r"'src'.*time events"):
        _driven(st.Pulse(period=1e-9)).simulate(StopTime=1.0)


def test_time_events_a_rounding_error_apart_are_one_event() -> None:
    """Ramp end 0.1 + 0.2 and a Step at 0.3 differ by one ulp; the run must go through.

    Ramp height 1 over [0.1, 0.3] plus a unit Step at 0.3: w(1) = ∫ torque = 0.1 + 0.7 + 0.7.
    """
    m = st.Model("close")
    m.add("ramp", st.Ramp(height=1.0, duration=0.2, startTime=0.1))
    m.add("step", st.Step(startTime=0.3))
    m.add("sum", st.Add())
    m.add("drive", st.Torque())
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.connect("ramp.y", "sum.u1")
    m.connect("step.y", "sum.u2")
    m.connect("sum.y", "drive.tau")
    m.connect("drive.flange", "J.flange_a")
    r = m.simulate(StopTime=1.0, Interval=0.01, Tolerance=1e-10)
    assert r["J.w"][-1] == pytest.approx(0.1 + 0.7 + 0.7, rel=1e-9)


def test_a_pulse_of_full_width_runs() -> None:
    """width = 100 %: each pulse ends where the next begins (one ulp apart): constant 1."""
    r = _driven(st.Pulse(period=0.1, width=100.0)).simulate(StopTime=1.0, Interval=0.01)
    np.testing.assert_allclose(r["J.w"], r.time, rtol=0, atol=1e-9)


def test_a_massless_shaft_held_by_a_locked_brake_runs() -> None:
    """Inertia – spring – brake: the spring's far end has no inertia, but the brake holds it."""
    m = st.Model("held")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=1.0))
    m.add("s", st.Spring(c=100.0))
    m.add("b", st.Brake(fn_max=100.0))
    m.add("f", st.Constant(k=1.0))
    m.connect("J.flange_b", "s.flange_a")
    m.connect("s.flange_b", "b.flange_a")
    m.connect("f.y", "b.f_normalized")
    r = m.simulate(StopTime=1.0, Interval=0.01, Tolerance=1e-8)
    assert set(np.unique(r["b.mode"])) == {0.0}  # the spring never exceeds 50 N·m
    # J oscillates on the spring: w = cos(10 t)
    np.testing.assert_allclose(r["J.w"], np.cos(10.0 * r.time), atol=1e-6)


def test_an_overflow_is_an_error_not_nan() -> None:
    """A torque of 1e300 on J = 1e-300 overflows: the run stops with a reason."""
    m = st.Model("overflow")
    m.add("src", st.ConstantTorque(tau_constant=1e300))
    m.add("J", st.Inertia(J=1e-300, phi=0.0, w=0.0))
    m.connect("src.flange", "J.flange_a")
    with pytest.raises(RuntimeError, match="infinite or NaN"):
        m.simulate(StopTime=1.0)


def test_heat_flows_of_a_connection_set_add_up_to_zero() -> None:
    """HeatLosses: the ambient's port takes what convection.fluid gives (Σ Q_flow = 0)."""
    r = st.Model.load(REPO / "examples" / "msl" / "HeatLosses.toml").simulate(StopTime=0.2)
    total = r["TAmbient.port.Q_flow"] + r["convection.fluid.Q_flow"]
    np.testing.assert_allclose(total, 0.0, atol=1e-12)
    assert r["TAmbient.port.Q_flow"].max() > 0.0  # heat flows into the ambient


def test_time_table_outputs_its_offset_before_start_time() -> None:
    """MSL CombiTimeTable: y = offset for t < startTime, then the table shifted by startTime."""
    table = st.TimeTable(table=[[0.0, 1.0], [1.0, 3.0]], offset=0.5, startTime=0.4)
    r = _driven(table).simulate(StopTime=1.0, Interval=0.01)
    t, y = r.time, r["src.y"]
    before, after = t < 0.4, t > 0.4
    np.testing.assert_allclose(y[before], 0.5)
    np.testing.assert_allclose(y[after], 0.5 + 1.0 + 2.0 * (t[after] - 0.4), atol=1e-12)


def test_the_same_connection_twice_is_harmless() -> None:
    """Modelica allows repeating a connect; the result is the same as connecting once."""
    text = (REPO / "examples" / "msl" / "CoupledClutches.toml").read_text()
    twice = text.replace(
        '["sin1.y", "torque.tau"],', '["sin1.y", "torque.tau"],\n  ["sin1.y", "torque.tau"],'
    )
    assert twice != text
    # the engine itself (the Python Model refuses a repeated connect as a likely slip)
    r1 = _core.simulate(text, ".", {"StopTime": 0.1})
    r2 = _core.simulate(twice, ".", {"StopTime": 0.1})
    np.testing.assert_array_equal(r1.column("J1.w"), r2.column("J1.w"))


def test_an_output_grid_that_cannot_fit_in_memory_is_refused() -> None:
    """Interval 1e-12 over 1.5 s would be 1.5e12 rows: a clear error, not an abort."""
    m = st.Model.load(REPO / "examples" / "msl" / "CoupledClutches.toml")
    with pytest.raises(st.ModelError, match="Interval"):
        m.simulate(Interval=1e-9)


def test_a_brake_pressed_beyond_floating_point_is_an_error_not_a_spin() -> None:
    """Found by fuzzing the FMU's calls (an input set to 1e300): the flywheel's deceleration,
    1e302 rad/s², overflows the integrator's error norm, its starting step was 0 and zero
    steps were accepted until the 5e6-step limit (minutes). Now the first one stops the run."""
    m = st.Model("pressed")
    m.add("J", st.Inertia(J=2.0, phi=0.0, w=5.0))
    m.add("brake", st.Brake(fn_max=50.0))
    m.add("press", st.Constant(k=1e300))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    with pytest.raises(st.IntegratorError, match="step size fell to 0"):
        m.simulate(params={"max_steps": 1000})  # the limit would be reached first otherwise
    pressed = m.simulate(params={"press.k": 1e100})  # far, but within floating point: it stops
    assert pressed.events[-1].new_mode == 0 and pressed.events[-1].time < 1e-99
