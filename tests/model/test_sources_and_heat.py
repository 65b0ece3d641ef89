"""Sources, signal blocks and the heat network against closed forms and balances.

ConstantSpeed holds its speed and its torque does the work the damper dissipates; TorqueStep
and a Constant→Gain chain accelerate a free inertia linearly; a TimeTable read from a CSV file
drives a brake through the brake_force_profile example; the braked flywheel's disc heats up by
exactly the brake's losses less what the conductor carries away.
"""

from __future__ import annotations

import numpy as np
import pytest
from paths import REPO

import stiction as st


def test_constant_speed_holds_its_speed_and_does_the_dissipated_work() -> None:
    """w = w_fixed exactly; torque = d·w; source work = dissipated energy = d·w²·t."""
    m = st.Model("speed")
    m.add("src", st.ConstantSpeed(w_fixed=5.0))
    m.add("J", st.Inertia(J=2.0, phi=0.0, w={"start": 0.0, "fixed": False}))
    m.add("d", st.Damper(d=3.0))
    m.add("ground", st.Fixed())
    m.connect("src.flange", "J.flange_a")
    m.connect("J.flange_b", "d.flange_a")
    m.connect("d.flange_b", "ground.flange")
    r = m.simulate(StopTime=2.0, Interval=0.01)
    np.testing.assert_allclose(r["J.w"], 5.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["src.tau"], 15.0, rtol=1e-12)
    t = r.time
    # work and dissipation are integrals of constants: exact up to the integrator's round-off
    np.testing.assert_allclose(r["system.sourceWork"], 75.0 * t, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(r["system.dissipatedEnergy"], 75.0 * t, rtol=1e-9, atol=1e-9)


def test_torque_step_switches_at_its_start_time() -> None:
    """A free J = 1: w = t·offset before startTime, then the step adds; rows at the event."""
    m = st.Model("step")
    m.add("src", st.TorqueStep(stepTorque=10.0, offsetTorque=1.0, startTime=0.3))
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.connect("src.flange", "J.flange_a")
    r = m.simulate(StopTime=1.0, Interval=0.01)
    t, w = r.time, r["J.w"]
    exact = np.where(t < 0.3, t, 0.3 + 11.0 * (t - 0.3))
    # piecewise linear speed: every Runge-Kutta method is exact up to round-off
    np.testing.assert_allclose(w, exact, rtol=0, atol=1e-12)
    rows = np.flatnonzero(t == 0.3)
    assert len(rows) == 2  # the event's left and right values
    assert r["src.tau"][rows].tolist() == [1.0, 11.0]


def test_gain_scales_a_constant_torque() -> None:
    """Constant 2 → Gain 3 → Torque on J = 2: w = 3·t."""
    m = st.Model("gain")
    m.add("c", st.Constant(k=2.0))
    m.add("g", st.Gain(k=3.0))
    m.add("src", st.Torque())
    m.add("J", st.Inertia(J=2.0, phi=0.0, w=0.0))
    m.connect("c.y", "g.u")
    m.connect("g.y", "src.tau")
    m.connect("src.flange", "J.flange_a")
    r = m.simulate(StopTime=1.0, Interval=0.1)
    np.testing.assert_allclose(r["J.w"], 3.0 * r.time, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["g.y"], 6.0)


@pytest.fixture(scope="module")
def profile_run() -> st.Result:
    return st.Model.load(REPO / "examples" / "brake_force_profile.toml").simulate()


def test_time_table_from_a_csv_file_interpolates_the_samples(profile_run: st.Result) -> None:
    """profile.y is the CSV's piecewise-linear curve (samples and midpoints)."""
    samples = np.loadtxt(REPO / "examples" / "brake_force_profile.csv", delimiter=",", skiprows=1)
    t, y = profile_run.time, profile_run["profile.y"]
    exact = np.interp(t, samples[:, 0], samples[:, 1])
    np.testing.assert_allclose(y, exact, rtol=0, atol=1e-12)


def test_measured_profile_brakes_holds_on_the_slope_and_releases(profile_run: st.Result) -> None:
    """Engages at 0.3 s, stops and holds the 60 N·m slope, breaks away when the force drops.

    Breakaway: peak·mu(0)·cgeo·fn_max·f = 60 N·m with f falling linearly from 1 at 4.5 s to 0
    at 4.6 s, so f = 60/(1.2·0.45·0.12·8000) and t = 4.5 + 0.1·(1 − f).
    """
    brake = [(e.time, e.new_mode) for e in profile_run.events if e.component == "brake"]
    modes = [m for _, m in brake]
    assert modes[:4] == [2, 1, 0, -1] and modes[-1] == 2
    f = 60.0 / (1.2 * 0.45 * 0.12 * 8000.0)
    t_break = 4.5 + 0.1 * (1.0 - f)
    assert brake[3][0] == pytest.approx(t_break, abs=1e-9)
    held = (profile_run.time > brake[2][0] + 1e-6) & (profile_run.time < t_break - 1e-6)
    assert np.all(np.abs(profile_run["vehicle.w"][held]) < 1e-9)
    np.testing.assert_allclose(profile_run["brake.tau"][held], -60.0, rtol=1e-9)
    assert profile_run["vehicle.w"][-1] < -1.0  # it rolls back once released


def test_braked_disc_heats_by_the_losses_minus_the_cooling() -> None:
    """C·dT/dt = lossPower − G·(T − T_ambient) at every row; C·ΔT + ∫cooling = kinetic energy."""
    r = st.Model.load(REPO / "examples" / "braked_flywheel.toml").simulate()
    c, g, t_amb = 2300.0, 5.0, 293.15
    temp = r["disc.T"]
    cooling = g * (temp - t_amb)
    np.testing.assert_allclose(r["cooling.Q_flow"], cooling, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(c * r["disc.der_T"], r["brake.lossPower"] - cooling, rtol=1e-9, atol=1e-9)
    t = r.time
    cooled = float(np.sum(0.5 * (cooling[1:] + cooling[:-1]) * np.diff(t)))
    kinetic = 0.5 * 2.0 * 100.0**2
    # the disc's heat plus what left it equals the flywheel's energy; the trapezoid error of
    # the slowly varying cooling term is far below 1e-3 J
    assert c * (temp[-1] - t_amb) + cooled == pytest.approx(kinetic, rel=1e-6, abs=1e-3)
    assert r["flywheel.w"][-1] == pytest.approx(0.0, abs=1e-9)
