"""The Brake (spec §3, §5.1) in small models with closed-form solutions.

Every model runs at Tolerance = 1e-8. Unless a test says otherwise, speed checks allow
W_TOL = 10·Tolerance·(the model's speed scale): the integrator keeps each step's local
error below Tolerance·|w| and the global error of these contracting or constant-
acceleration problems stays within a few local errors. A time found from a speed
crossing is then good to W_TOL/|dw/dt| at the crossing.

Sign conventions (spec §5.1): the brake applies −tau to the shaft, tau = mu(w)·cgeo·fn
while sliding forward, and tau = the constraint torque while stuck.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

TOL = 1e-8


def _trapezoid(y: np.ndarray, t: np.ndarray) -> float:
    """∫y dt over the result rows (a repeated event time adds a zero-width interval)."""
    return float(np.sum(np.diff(t) * (y[1:] + y[:-1]) / 2.0))


def _events_of(r: st.Result, name: str) -> list[tuple[float, int, int]]:
    return [(e.time, e.old_mode, e.new_mode) for e in r.events if e.component == name]


def _flywheel(
    mu_pos: list[list[float]], *, J: float, w0: float, fn_max: float, f: float, cgeo: float = 1.0
) -> st.Model:
    """A flywheel J spinning at w0 with a brake pressed at a constant f_normalized."""
    m = st.Model("flywheel")
    m.add("J", st.Inertia(J=J, phi=0.0, w=w0))
    m.add("brake", st.Brake(fn_max=fn_max, mu_pos=mu_pos, cgeo=cgeo))
    m.add("press", st.Constant(k=f))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


# --- (a) braked flywheel ------------------------------------------------------------------
def test_constant_mu_stops_in_closed_form_time_and_angle() -> None:
    """J·w' = −mu·cgeo·fn: stop at J·w0/(mu·cgeo·fn), after J·w0²/(2·mu·cgeo·fn) rad."""
    J, w0, fn_max, mu = 2.0, 10.0, 100.0, 0.5
    r = _flywheel([[0.0, mu]], J=J, w0=w0, fn_max=fn_max, f=1.0).simulate(
        StopTime=2.0, Interval=1e-3, Tolerance=TOL
    )
    torque = mu * 1.0 * fn_max  # 50 N·m
    t_stop = J * w0 / torque  # 0.4 s
    angle = J * w0**2 / (2 * torque)  # 2 rad
    w_tol = 10 * TOL * w0
    assert _events_of(r, "brake")[0][1:] == (3, 1)  # starts sliding forward (w > 0 at t0)
    (stop,) = [e for e in _events_of(r, "brake") if e[0] > 0]
    assert stop[1:] == (1, 0)
    # the speed is linear in t; the crossing w = 0 is located to w_tol/(torque/J)
    assert stop[0] == pytest.approx(t_stop, abs=w_tol / (torque / J))
    sliding = r.time < t_stop - 1e-9
    np.testing.assert_allclose(r["J.w"][sliding], w0 - torque / J * r.time[sliding], rtol=0, atol=w_tol)
    np.testing.assert_allclose(r["brake.tau"][sliding], torque, rtol=1e-12)
    # angle: the integral of a speed error ≤ w_tol over ≤ 2 s
    assert r["J.phi"][-1] == pytest.approx(angle, abs=2.0 * w_tol)


def test_stopped_flywheel_stays_stuck_without_chattering() -> None:
    """After the stop: mode 0, w ≈ 0, no torque to hold, and no further events (1.6 s)."""
    r = _flywheel([[0.0, 0.5]], J=2.0, w0=10.0, fn_max=100.0, f=1.0).simulate(
        StopTime=2.0, Interval=1e-3, Tolerance=TOL
    )
    t_stop = max(e.time for e in r.events)
    assert t_stop == pytest.approx(0.4, abs=1e-6)
    assert len(r.events) == 2  # initialization and the stop: nothing after it
    after = r.time > t_stop
    assert after.sum() > 1500
    assert np.all(r["brake.mode"][after] == 0) and np.all(r["brake.locked"][after] == 1)
    # Locked means a = 0 (spec §3.3), so w keeps its value at the event: ≈ 0 to the
    # precision of the crossing, and with nothing to hold, no torque.
    assert np.abs(r["J.w"][after]).max() < 10 * TOL * 10.0
    assert np.abs(r["brake.tau"][after]).max() < 1e-9
    assert np.ptp(r["J.phi"][after]) < 1e-9  # it really stands still


@pytest.mark.parametrize(
    "mu_pos",
    [
        [[0.0, 0.5], [10.0, 0.4]],  # mu falls with speed (design doc example)
        [[0.0, 0.3], [10.0, 0.6]],  # mu rises with speed
    ],
)
def test_linear_mu_of_w_gives_exponential_braking(mu_pos: list[list[float]]) -> None:
    """J·w' = −cgeo·fn·(a + b·w): w = (w0 + a/b)·exp(−k·b·t) − a/b with k = cgeo·fn/J.

    The stop is at t_s = ln(1 + b·w0/a)/(k·b), after phi_s = (w0 − k·a·t_s)/(k·b).
    cgeo and f_normalized are not 1 so that both factors of the torque are exercised.
    """
    J, w0, fn_max, f, cgeo = 2.0, 10.0, 100.0, 0.75, 0.8
    a = mu_pos[0][1]
    b = (mu_pos[1][1] - mu_pos[0][1]) / (mu_pos[1][0] - mu_pos[0][0])
    fn = fn_max * f
    k = cgeo * fn / J
    t_s = math.log(1 + b * w0 / a) / (k * b)
    phi_s = (w0 - k * a * t_s) / (k * b)
    r = _flywheel(mu_pos, J=J, w0=w0, fn_max=fn_max, f=f, cgeo=cgeo).simulate(
        StopTime=1.5, Interval=1e-3, Tolerance=TOL
    )
    w_tol = 10 * TOL * w0
    (stop,) = [e for e in _events_of(r, "brake") if e[0] > 0]
    assert stop[1:] == (1, 0)
    # at the stop |w'| = k·a
    assert stop[0] == pytest.approx(t_s, abs=w_tol / (k * a))
    t = r.time
    exact = np.where(t < t_s, (w0 + a / b) * np.exp(-k * b * t) - a / b, 0.0)
    np.testing.assert_allclose(r["J.w"], exact, rtol=0, atol=w_tol)
    sliding = t < t_s - 1e-6
    np.testing.assert_allclose(r["brake.mu"][sliding], a + b * r["J.w"][sliding], rtol=1e-12)
    np.testing.assert_allclose(r["brake.tau"][sliding], cgeo * fn * r["brake.mu"][sliding], rtol=1e-12)
    assert r["brake.fn"][0] == fn
    assert r["J.phi"][-1] == pytest.approx(phi_s, abs=t_s * w_tol)
    assert np.all(r["brake.mode"][t > t_s + 1e-6] == 0)


# --- (b) breakaway under a rising torque -------------------------------------------------
def test_breakaway_at_peak_static_torque_then_sliding_with_mu_of_w() -> None:
    """A ramp torque R·t against a stuck brake (peak 1.5, mu = 0.4 + 0.01·w).

    The brake holds (w = 0, tau = R·t) until R·t reaches peak·mu(0)·cgeo·fn = 60 N·m at
    t_b = 0.6 s; then it slides with tau = mu(w)·cgeo·fn, so
    J·w' = R·t − c·(a + b·w) (c = cgeo·fn), whose solution from w(t_b) = 0 is
    w = α·t + β − (α·t_b + β)·exp(−k·(t − t_b)), k = c·b/J, α = R/(c·b),
    β = −(c·a/J + α)/k.
    """
    J, fn_max, a, b, peak, R = 2.0, 100.0, 0.4, 0.01, 1.5, 100.0
    m = st.Model("breakaway")
    m.add("J", st.Inertia(J=J, phi=0.0, w=0.0))
    m.add("brake", st.Brake(fn_max=fn_max, mu_pos=[[0.0, a], [10.0, a + 10 * b]], peak=peak))
    m.add("press", st.Constant(k=1.0))
    m.add("ramp", st.Ramp(height=2 * R, duration=2.0))  # R·t for t ≤ 2 s
    m.add("torque", st.Torque())
    m.connect("ramp.y", "torque.tau")
    m.connect("torque.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    r = m.simulate(StopTime=1.5, Interval=1e-3, Tolerance=TOL)

    c = 1.0 * fn_max
    tau0, tau0_max = a * c, peak * a * c  # 40 and 60 N·m
    t_b = tau0_max / R
    events = _events_of(r, "brake")
    assert [e[1:] for e in events] == [(3, 0), (0, 1)]  # stuck at t0, then forward sliding
    # The breakaway is the zero of sa − tau0_max with sa = R·t: root finding on a linear
    # function; 1e-6 s is the brief's bar, the crossing itself is found to ~1e-12 s.
    assert events[1][0] == pytest.approx(t_b, abs=1e-6)

    t = r.time
    held = t < t_b - 1e-9
    assert np.all(r["brake.mode"][held] == 0) and np.all(r["brake.locked"][held] == 1)
    assert np.all(r["J.w"][held] == 0.0)  # locked: a = 0 exactly, nothing drifts
    np.testing.assert_allclose(r["brake.tau"][held], R * t[held], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r["brake.tau0_max"], tau0_max, rtol=1e-12)
    np.testing.assert_allclose(r["brake.tau0"], tau0, rtol=1e-12)
    # at the breakaway instant the torque drops from the static peak to the sliding value
    at_b = np.flatnonzero(np.abs(t - t_b) <= 1e-6)
    assert r["brake.tau"][at_b].max() == pytest.approx(tau0_max, abs=R * 1e-6)
    assert r["brake.tau"][at_b[-1]] == pytest.approx(tau0, abs=1e-6)

    k, alpha = c * b / J, R / (c * b)
    beta = -(c * a / J + alpha) / k
    exact = np.where(t < t_b, 0.0, alpha * t + beta - (alpha * t_b + beta) * np.exp(-k * (t - t_b)))
    w_scale = float(exact.max())  # ≈ 33 rad/s at 1.5 s
    np.testing.assert_allclose(r["J.w"], exact, rtol=0, atol=10 * TOL * w_scale)
    sliding = t > t_b + 1e-6
    assert np.all(r["brake.mode"][sliding] == 1)
    np.testing.assert_allclose(r["brake.tau"][sliding], c * (a + b * r["J.w"][sliding]), rtol=1e-12)


# --- (c) brake housing on a free inertia -------------------------------------------------
def test_brake_with_free_housing_conserves_momentum_and_locks_at_common_speed() -> None:
    """Shaft J1 and housing J2 (useSupport): the relative speed falls at T·(1/J1 + 1/J2).

    The brake torque is internal, so J1·w1 + J2·w2 is constant; both end at
    (J1·w1 + J2·w2)/(J1 + J2) at t_s = (w1 − w2)/(T·(1/J1 + 1/J2)), T = mu·cgeo·fn.
    """
    J1, J2, w1, w2, fn_max, mu = 2.0, 3.0, 10.0, -2.0, 100.0, 0.5
    m = st.Model("housing")
    m.add("J1", st.Inertia(J=J1, phi=0.0, w=w1))
    m.add("J2", st.Inertia(J=J2, phi=0.0, w=w2))
    m.add("brake", st.Brake(fn_max=fn_max, mu_pos=[[0.0, mu]], useSupport=True))
    m.add("press", st.Constant(k=1.0))
    m.connect("J1.flange_b", "brake.flange_a")
    m.connect("brake.support", "J2.flange_a")
    m.connect("press.y", "brake.f_normalized")
    r = m.simulate(StopTime=1.0, Interval=1e-3, Tolerance=TOL)

    T = mu * fn_max
    t_s = (w1 - w2) / (T * (1 / J1 + 1 / J2))  # 0.288 s
    w_common = (J1 * w1 + J2 * w2) / (J1 + J2)  # 2.8 rad/s
    w_tol = 10 * TOL * (w1 - w2)
    (stop,) = [e for e in _events_of(r, "brake") if e[0] > 0]
    assert stop[1:] == (1, 0)
    assert stop[0] == pytest.approx(t_s, abs=w_tol / (T * (1 / J1 + 1 / J2)))
    t = r.time
    np.testing.assert_allclose(r["J1.w"], np.where(t < t_s, w1 - T / J1 * t, w_common), rtol=0, atol=w_tol)
    np.testing.assert_allclose(r["J2.w"], np.where(t < t_s, w2 + T / J2 * t, w_common), rtol=0, atol=w_tol)
    # momentum: only internal torques act (round-off level, the states are exact here)
    momentum = J1 * r["J1.w"] + J2 * r["J2.w"]
    np.testing.assert_allclose(momentum, J1 * w1 + J2 * w2, rtol=1e-10)
    # the brake's speed is relative to its housing, and the reaction goes into it
    np.testing.assert_allclose(r["brake.w"], r["J1.w"] - r["J2.w"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["brake.support.tau"], -r["brake.tau"], rtol=0, atol=1e-12)
    assert np.all(r["brake.mode"][t > t_s + 1e-6] == 0)


# --- (d) release and re-application ------------------------------------------------------
J_D, W0_D, TORQUE_D = 2.0, 10.0, 50.0  # mu 0.5 · cgeo 1 · fn 100 N → 50 N·m, 25 rad/s²
T_OFF, T_ON = 0.1, 0.3
W_OFF = W0_D - TORQUE_D / J_D * T_OFF  # 7.5 rad/s while released
T_STOP = T_ON + W_OFF / (TORQUE_D / J_D)  # 0.6 s


def _release_model(source: str) -> st.Model:
    """Flywheel braked, released on [0.1, 0.3) and braked again: f from Steps or a table."""
    m = st.Model("reapply")
    m.add("J", st.Inertia(J=J_D, phi=0.0, w=W0_D))
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=[[0.0, 0.5]]))
    m.connect("J.flange_b", "brake.flange_a")
    if source == "steps":
        m.add("release", st.Step(height=-1.0, offset=1.0, startTime=T_OFF))
        m.add("apply", st.Step(height=1.0, startTime=T_ON))
        m.add("press", st.Add())
        m.connect("release.y", "press.u1")
        m.connect("apply.y", "press.u2")
    else:  # MSL TimeTable: a repeated time is a jump (a time event)
        table = [[0.0, 1.0], [T_OFF, 1.0], [T_OFF, 0.0], [T_ON, 0.0], [T_ON, 1.0], [1.0, 1.0]]
        m.add("press", st.TimeTable(table=table))
    m.connect("press.y", "brake.f_normalized")
    return m


def _release_run(source: str = "steps") -> st.Result:
    return _release_model(source).simulate(StopTime=1.0, Interval=1e-3, Tolerance=TOL)


def test_release_and_reapplication_follow_the_closed_form() -> None:
    """Slide at −25 rad/s² to 7.5 rad/s, free (constant w) on [0.1, 0.3), slide, stop at 0.6."""
    r = _release_run()
    w_tol = 10 * TOL * W0_D
    events = _events_of(r, "brake")
    assert [e[1:] for e in events] == [(3, 1), (1, 2), (2, 1), (1, 0)]
    assert events[1][0] == T_OFF and events[2][0] == T_ON  # time events: exact instants
    assert events[3][0] == pytest.approx(T_STOP, abs=w_tol / (TORQUE_D / J_D))
    t, w = r.time, r["J.w"]
    exact = np.interp(t, [0.0, T_OFF, T_ON, T_STOP, 1.0], [W0_D, W_OFF, W_OFF, 0.0, 0.0])
    np.testing.assert_allclose(w, exact, rtol=0, atol=w_tol)
    free = (t > T_OFF) & (t < T_ON)
    assert np.all(r["brake.mode"][free] == 2) and np.all(r["brake.free"][free] == 1)
    assert np.all(r["brake.tau"][free] == 0.0) and np.all(r["brake.fn"][free] == 0.0)
    assert np.ptp(w[free]) == 0.0  # no torque at all: the speed is exactly constant
    assert np.all(r["brake.mode"][t > T_STOP + 1e-6] == 0)


def test_release_and_reapplication_dissipate_the_kinetic_energy() -> None:
    """∫brake.lossPower dt = ½·J·w0² − ½·J·w_end² (all kinetic energy goes into the brake).

    lossPower = 50·w is linear in t on each phase, so the trapezoid rule over the result
    rows is exact provided each event instant carries its left and right values; what is
    left is the integration error of w: ∫50·|δw| dt ≤ 50·W_TOL·0.6 s = 3e-5 J. We allow
    1e-4 J (1e-6 of the 100 J).
    """
    r = _release_run()
    lost = 0.5 * J_D * (r["J.w"][0] ** 2 - r["J.w"][-1] ** 2)
    assert lost == pytest.approx(0.5 * J_D * W0_D**2, abs=1e-4)
    assert r["system.dissipatedEnergy"][-1] == pytest.approx(lost, abs=1e-4)
    assert _trapezoid(r["brake.lossPower"], r.time) == pytest.approx(lost, abs=1e-4)


def test_time_event_rows_are_the_left_and_right_limits() -> None:
    """The release instant is written twice, as in MSL results: braking, then free.

    The output grid (1e-3 s) contains t = 0.1, so this also checks that a grid point that
    falls on a time event does not add a third row mixing both sides.
    """
    r = _release_run()
    rows = np.flatnonzero(r.time == T_OFF)
    assert rows.size == 2, {n: r[n][rows].tolist() for n in ("brake.fn", "brake.tau", "brake.mode")}
    left, right = rows
    assert (r["brake.fn"][left], r["brake.tau"][left], r["brake.mode"][left]) == (100.0, TORQUE_D, 1.0)
    assert (r["brake.fn"][right], r["brake.tau"][right], r["brake.mode"][right]) == (0.0, 0.0, 2.0)


def test_time_event_is_reached_without_integrating_past_it() -> None:
    """Braking at a constant 25 rad/s² until exactly t = 0.1 leaves exactly 7.5 rad/s.

    The speed is linear in t, which every integrator (BDF, SDIRK, RK) reproduces up to
    round-off (the stop in test (a) is exact to 1e-13). A time event is known in advance:
    the integrator must stop on it, evaluating the brake force as its left limit (fn =
    100 N) up to and including t = 0.1. So w(0.1) = 7.5 to round-off; we allow 1e-10 rad/s.
    """
    r = _release_run()
    rows = np.flatnonzero(r.time == T_OFF)
    assert np.abs(r["J.w"][rows] - W_OFF).max() < 1e-10, r["J.w"][rows] - W_OFF


def test_time_table_with_a_repeated_time_drives_the_same_release() -> None:
    """A TimeTable with a repeated time point is a jump (MSL semantics) and gives the same run."""
    by_table, by_steps = _release_run("table"), _release_run("steps")
    assert [e[1:] for e in _events_of(by_table, "brake")] == [(3, 1), (1, 2), (2, 1), (1, 0)]
    for e_table, e_steps in zip(by_table.events, by_steps.events, strict=True):
        assert e_table.time == pytest.approx(e_steps.time, abs=1e-9)
    np.testing.assert_allclose(by_table["J.w"][-1], by_steps["J.w"][-1], atol=1e-9)
