"""CompareBrakingTorque (MSL 4.1.0) against the closed forms of spec §7.5.

Four independent inertias (J = 1, w(0) = 100 rad/s) are braked by four torque laws:

* inertia1, SignTorque (Linear): w = 100 − 100·t until |w| = w0 = 1 at t = 0.99, then
  w = exp(−100·(t − 0.99));
* inertia2, LinearSpeedDependentTorque: w = 100·exp(−t);
* inertia3, QuadraticSpeedDependentTorque: w = 100/(1 + t);
* inertia4, InverseSpeedDependentTorque: w' = −1e4/w, so w = 100·sqrt(1 − 2·t) until
  |w| = 1 at t = 0.49995, then w = exp(−100·(t − 0.49995)); the torque jumps from −1e4 to
  −100 N·m there.

Tolerances come from the run's Tolerance = 1e-6 (the model file's, as in MSL) on the
100 rad/s scale: a local error of 1e-6·100 = 1e-4 rad/s per step, and a global error that
an error-controlled integrator keeps within a few times that on these contracting or
neutral dynamics.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

MODEL = MSL_EXAMPLES / "CompareBrakingTorque.toml"
RUN_TOLERANCE = 1e-6
W_SCALE = 100.0  # rad/s
T1 = 0.99  # inertia1 reaches |w| = w0 = 1: 100 − 100·t = 1
T4 = 0.49995  # inertia4 reaches |w| = 1: 1e4·(1 − 2·t) = 1
# Pointwise speed tolerance: Tolerance × scale, the local error the integrator allows.
# The laws of inertia1–3 are contracting or linear, so the global error stays below it
# (measured ≤ 5.3e-6 rad/s).
W_TOL = RUN_TOLERANCE * W_SCALE


@cache
def _result() -> st.Result:
    return st.Model.load(MODEL).simulate()


def _exact(k: int, t: np.ndarray) -> np.ndarray:
    if k == 1:
        return np.where(t < T1, 100.0 - 100.0 * t, np.exp(-100.0 * (t - T1)))
    if k == 2:
        return 100.0 * np.exp(-t)
    if k == 3:
        return 100.0 / (1.0 + t)
    return np.where(t < T4, 100.0 * np.sqrt(np.clip(1.0 - 2.0 * t, 0.0, None)), np.exp(-100.0 * (t - T4)))


def _event_times(r: st.Result) -> np.ndarray:
    """Event instants: times written twice (left and right value), the last row aside."""
    t = r.time[:-1]
    return np.unique(t[1:][np.diff(t) == 0.0])


def test_run_uses_the_model_tolerance() -> None:
    """The experiment runs at Tolerance 1e-6, the setting the tolerances below assume."""
    assert st.Model.load(MODEL).experiment["Tolerance"] == RUN_TOLERANCE
    r = _result()
    assert r.time[0] == 0.0 and r.time[-1] == pytest.approx(5.0)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_speed_follows_the_closed_form(k: int) -> None:
    """inertia1–3 follow their closed-form speeds within Tolerance × 100 rad/s."""
    r = _result()
    err = np.abs(r[f"inertia{k}.w"] - _exact(k, r.time))
    assert err.max() < W_TOL, (k, err.max(), r.time[np.argmax(err)])


def test_final_speeds_of_the_smooth_laws() -> None:
    """At 5 s: linear law 100·e⁻⁵ ≈ 0.6738 rad/s, quadratic law 100/6 ≈ 16.667 rad/s."""
    r = _result()
    assert r["inertia2.w"][-1] == pytest.approx(100.0 * np.exp(-5.0), abs=W_TOL)
    assert r["inertia3.w"][-1] == pytest.approx(100.0 / 6.0, abs=W_TOL)


def test_inverse_law_before_its_event_conserves_w_squared_plus_2e4_t() -> None:
    """inertia4 before t = 0.49995: d(w²)/dt = −2e4 exactly, so w² + 2e4·t = 1e4.

    Errors in w are amplified as w falls (δ(w²) = 2·w·δw is what the dynamics carry, so
    δw ∝ 1/w): a pointwise bound on w would have to be loose near the event. The
    invariant w² is the fair yardstick: its error is created at the 100 rad/s scale, where
    Tolerance allows δ(w²) ≈ 2·100·1e-4 = 0.02 per unit of global error; we allow
    10·Tolerance·w0² = 0.1 (measured 0.035). Pointwise, the largest error is 4.8e-4 rad/s
    at t = 0.4999 (w ≈ 1.4), i.e. a time shift δ(w²)/2e4 ≈ 7e-8 s.
    """
    r = _result()
    before = r.time < T4 - 1e-6
    w, t = r["inertia4.w"][before], r.time[before]
    invariant_err = np.abs(w**2 - 1e4 * (1.0 - 2.0 * t))
    assert invariant_err.max() < 10 * RUN_TOLERANCE * W_SCALE**2, invariant_err.max()
    # the same bound, expressed in w: |δw| ≤ 0.1/(2·w) (≈ 5e-4 rad/s at w = 100)
    assert np.all(np.abs(w - _exact(4, t)) < 10 * RUN_TOLERANCE * W_SCALE**2 / (2 * w))


def test_inverse_law_after_its_event_decays_exponentially() -> None:
    """inertia4 after t = 0.49995: w' = −100·w, w = exp(−100·(t − 0.49995))."""
    r = _result()
    after = r.time > T4 + 1e-6
    err = np.abs(r["inertia4.w"][after] - _exact(4, r.time[after]))
    # A time shift δt of the event moves the exponential by 100·w·δt ≤ 100·δt; with
    # δt ≤ 1e-6 s (below) that is ≤ 1e-4 rad/s = W_TOL.
    assert err.max() < W_TOL, err.max()


def test_state_events_at_w0() -> None:
    """Exactly two state events, at |w| = w0: t = 0.49995 (inertia4) and t = 0.99 (inertia1).

    inertia1: |δt| = |δw|/|w'| ≤ W_TOL/100 = 1e-6 s. inertia4: |δt| = δ(w²)/2e4 ≤ 0.1/2e4 =
    5e-6 s; we ask for 1e-6 s (measured ≈ 7e-8 s).
    """
    r = _result()
    times = _event_times(r)
    assert times.size == 2, times
    assert times[0] == pytest.approx(T4, abs=1e-6)
    assert times[1] == pytest.approx(T1, abs=1e-6)
    assert r.stats["state_events"] == 2
    assert r.events == []  # no friction element, so no mode changes in the log


def test_speed_is_w0_at_each_event() -> None:
    """At each event row (both sides) the braked inertia's speed is w0 = 1 rad/s."""
    r = _result()
    t4, t1 = _event_times(r)
    for name, te in (("inertia4.w", t4), ("inertia1.w", t1)):
        rows = r.time == te
        assert rows.sum() == 2
        # located to rtol-level precision on the event function |w| − w0
        np.testing.assert_allclose(r[name][rows], 1.0, rtol=0, atol=1e-6)


def test_inverse_law_torque_jumps_at_its_event() -> None:
    """InverseSpeedDependentTorque(TorqueDirection=false) jumps from −1e4 to −100 N·m."""
    r = _result()
    t4, _ = _event_times(r)
    left, right = r["inverseSpeedDependentTorque.tau"][r.time == t4]
    assert left == pytest.approx(-1e4, rel=1e-6)  # tau_nominal·w_nominal/w at w = 1
    assert right == pytest.approx(-100.0, rel=1e-6)  # tau_nominal·w/w0 at w = 1
    # and the sign law is continuous there (Linear regularisation: −100·sign(w) = −100·w/w0)
    left1, right1 = r["signTorque.tau"][r.time == _event_times(r)[1]]
    assert left1 == pytest.approx(-100.0, rel=1e-6) and right1 == pytest.approx(-100.0, rel=1e-6)
