"""BearingFriction, OneWayClutch, ElastoBacklash and IdealPlanetary in small closed-form models.

Spec §5.3 (OneWayClutch), §5.4 (BearingFriction), §5.6 (ElastoBacklash), §5.8 (IdealPlanetary).
Every model runs at Tolerance = 1e-8 unless a test says otherwise. As in
test_brake_closed_form.py, speed checks allow W_TOL = 10·Tolerance·(the model's speed scale):
the integrator keeps each step's local error below Tolerance·|w|, and the global error of these
contracting or piecewise constant-acceleration problems stays within a few local errors. A time
found from a speed crossing is then good to W_TOL/|dw/dt| at the crossing. Relations that are
algebraic at every row (torque balances, gear kinematics) are checked to round-off (1e-12).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

TOL = 1e-8


def _events_of(r: st.Result, name: str) -> list[tuple[float, int, int]]:
    return [(e.time, e.old_mode, e.new_mode) for e in r.events if e.component == name]


def _event_rows(r: st.Result) -> np.ndarray:
    """Times written twice (left and right limit): the event instants of the run."""
    t = r.time
    return t[np.flatnonzero(np.diff(t) == 0.0)]


# --- BearingFriction (spec §5.4) -----------------------------------------------------------
def _bearing_flywheel(tau_pos: list[list[float]], *, J: float, w0: float, peak: float = 1.0) -> st.Model:
    """A flywheel J spinning at w0 in a bearing with friction torque tau_pos(|w|)."""
    m = st.Model("bearing_flywheel")
    m.add("J", st.Inertia(J=J, phi=0.0, w=w0))
    m.add("bearing", st.BearingFriction(tau_pos=tau_pos, peak=peak))
    m.connect("J.flange_b", "bearing.flange_a")
    return m


@pytest.mark.parametrize("w0", [8.0, -8.0])
def test_bearing_friction_constant_torque_stops_the_flywheel_and_holds_it(w0: float) -> None:
    """J·w' = −tau·sign(w): stop at J·|w0|/tau = 2 s, then stuck (mode 0) with no torque.

    Both directions: the table holds only w ≥ 0 and the element mirrors it (spec §4.1), so
    backward sliding (mode −1) must brake exactly like forward sliding.
    """
    J, tau = 0.5, 2.0
    r = _bearing_flywheel([[0.0, tau]], J=J, w0=w0).simulate(StopTime=3.0, Interval=1e-3, Tolerance=TOL)
    s = math.copysign(1.0, w0)
    t_stop = J * abs(w0) / tau
    w_tol = 10 * TOL * abs(w0)
    assert [e[1:] for e in _events_of(r, "bearing")] == [(3, int(s)), (int(s), 0)]
    assert _events_of(r, "bearing")[1][0] == pytest.approx(t_stop, abs=w_tol / (tau / J))
    t = r.time
    exact = np.where(t < t_stop, w0 - s * tau / J * t, 0.0)
    np.testing.assert_allclose(r["J.w"], exact, rtol=0, atol=w_tol)
    sliding = t < t_stop - 1e-6
    np.testing.assert_allclose(r["bearing.tau"][sliding], s * tau, rtol=1e-12)
    np.testing.assert_allclose(r["bearing.lossPower"][sliding], s * tau * r["J.w"][sliding], rtol=1e-12)
    after = t > t_stop + 1e-6
    assert after.sum() > 900
    assert np.all(r["bearing.mode"][after] == 0) and np.all(r["bearing.locked"][after] == 1)
    assert np.abs(r["bearing.tau"][after]).max() < 1e-9  # nothing to hold
    assert np.ptp(r["J.phi"][after]) < 1e-9  # it really stands still
    assert r["J.phi"][-1] == pytest.approx(J * w0 * abs(w0) / (2 * tau), abs=3.0 * w_tol)


@pytest.mark.parametrize("w0", [8.0, -8.0])
def test_bearing_friction_linear_characteristic_gives_exponential_decay(w0: float) -> None:
    """tau_pos = [[0, 0.5], [1, 1]]: sliding torque 0.5 + 0.5·|w|, extrapolated beyond 1 rad/s.

    For w > 0, J·w' = −(0.5 + 0.5·w), so w = (w0 + 1)·exp(−t/(2J)) − 1, and the flywheel stops
    at t_s = 2J·ln(1 + w0). Backward is the mirror image. Starting at |w0| = 8 exercises the
    linear extrapolation of the two-row table (spec §4.1: no clamping).
    """
    J = 0.5
    r = _bearing_flywheel([[0.0, 0.5], [1.0, 1.0]], J=J, w0=w0).simulate(
        StopTime=3.0, Interval=1e-3, Tolerance=TOL
    )
    s = math.copysign(1.0, w0)
    t_s = 2 * J * math.log(1 + abs(w0))  # ≈ 2.197 s
    w_tol = 10 * TOL * abs(w0)
    events = _events_of(r, "bearing")
    assert [e[1:] for e in events] == [(3, int(s)), (int(s), 0)]
    assert events[1][0] == pytest.approx(t_s, abs=w_tol / (0.5 / J))  # |w'| = 0.5/J at the stop
    t = r.time
    exact = np.where(t < t_s, s * ((abs(w0) + 1) * np.exp(-t / (2 * J)) - 1), 0.0)
    np.testing.assert_allclose(r["J.w"], exact, rtol=0, atol=w_tol)
    sliding = t < t_s - 1e-6
    w = r["J.w"][sliding]
    np.testing.assert_allclose(r["bearing.tau"][sliding], s * (0.5 + 0.5 * np.abs(w)), rtol=1e-12)
    assert np.all(r["bearing.mode"][t > t_s + 1e-6] == 0)
    assert np.all(r["bearing.tau0"] == 0.5) and np.all(r["bearing.tau0_max"] == 0.5)


def test_bearing_friction_breaks_away_at_peak_times_tau0() -> None:
    """A ramp torque R·t against a bearing at rest (tau_pos 1 N·m, peak 1.5).

    It holds (w = 0, tau = R·t) until R·t = peak·tau0 = 1.5 N·m at t_b = 1.5 s, then slides
    with the sliding torque 1 N·m: J·w' = R·t − 1, so w = (R·(t² − t_b²)/2 − (t − t_b))/J.
    """
    J, R, peak = 2.0, 1.0, 1.5
    m = _bearing_flywheel([[0.0, 1.0]], J=J, w0=0.0, peak=peak)
    m.add("ramp", st.Ramp(height=3.0 * R, duration=3.0))
    m.add("torque", st.Torque())
    m.connect("ramp.y", "torque.tau")
    m.connect("torque.flange", "J.flange_a")
    r = m.simulate(StopTime=2.5, Interval=1e-3, Tolerance=TOL)
    t_b = peak * 1.0 / R
    events = _events_of(r, "bearing")
    assert [e[1:] for e in events] == [(3, 0), (0, 1)]
    # the breakaway is the zero of the linear sa − tau0_max: found to far better than 1e-6 s
    assert events[1][0] == pytest.approx(t_b, abs=1e-6)
    t = r.time
    held = t < t_b - 1e-9
    assert np.all(r["J.w"][held] == 0.0) and np.all(r["bearing.mode"][held] == 0)
    np.testing.assert_allclose(r["bearing.tau"][held], R * t[held], rtol=1e-12, atol=1e-12)
    exact = np.where(t < t_b, 0.0, (R * (t**2 - t_b**2) / 2 - (t - t_b)) / J)
    np.testing.assert_allclose(r["J.w"], exact, rtol=0, atol=10 * TOL * float(exact.max()))
    sliding = t > t_b + 1e-6
    np.testing.assert_allclose(r["bearing.tau"][sliding], 1.0, rtol=1e-12)


# --- OneWayClutch (spec §5.3) -------------------------------------------------------------
J_IN, J_OUT, AMPLITUDE = 1.0, 2.0, 10.0  # drive torque B + 10·sin(2π·t) on inertiaIn
MU0, CGEO, FN_MAX = 0.4, 2.0, 500.0
TAU0_MAX_LOW = 1e-4 * MU0 * CGEO * FN_MAX  # 0.04 N·m: the disengaged release threshold


def _freewheel(offset: float) -> st.Model:
    """inertiaIn, driven by offset + 10·sin(2π·t), pushes a free inertiaOut through a freewheel.

    The clutch part is never engaged (f_normalized = 0), so the element is the bare freewheel
    with its tiny release threshold tau0_max_low = 1e-4·mu0·cgeo·fn_max. cgeo and mu0 are
    not 1 so that every factor of that threshold is exercised.
    """
    m = st.Model("freewheel")
    m.add("wave", st.Sine(amplitude=AMPLITUDE, f=1.0, offset=offset))
    m.add("drive", st.Torque())
    m.add("inertiaIn", st.Inertia(J=J_IN, phi=0.0, w=0.0))
    m.add(
        "oneWayClutch",
        st.OneWayClutch(
            mu_pos=[[0.0, MU0]],
            cgeo=CGEO,
            fn_max=FN_MAX,
            startForward={"start": False, "fixed": True},
            stuck={"start": False, "fixed": True},
        ),
    )
    m.add("inertiaOut", st.Inertia(J=J_OUT, phi=0.0, w=0.0))
    m.add("off", st.Constant(k=0.0))
    m.connect("wave.y", "drive.tau")
    m.connect("drive.flange", "inertiaIn.flange_a")
    m.connect("inertiaIn.flange_b", "oneWayClutch.flange_a")
    m.connect("oneWayClutch.flange_b", "inertiaOut.flange_a")
    m.connect("off.y", "oneWayClutch.f_normalized")
    return m


def _freewheel_times(offset: float) -> tuple[float, float]:
    """Release t_r and relock t_l of the freewheel in closed form.

    Locked, both inertias share a = T/(J_IN + J_OUT) and the element holds inertiaOut with
    tau = −J_OUT·T/(J_IN + J_OUT) (it exerts −tau on flange_b). It releases when that torque
    exceeds tau0_max_low, i.e. when T < −k with k = TAU0_MAX_LOW·(J_IN + J_OUT)/J_OUT:
    t_r = 0.5 + asin((B + k)/A)/(2π). Then inertiaOut coasts and inertiaIn catches up again
    when ∫_{t_r}^{t} T dt = 0: g(t) = B·(t − t_r) + A/(2π)·(cos 2πt_r − cos 2πt) = 0
    (bisection; for B = 0 the root is 2 − t_r by symmetry).
    """
    k = TAU0_MAX_LOW * (J_IN + J_OUT) / J_OUT
    t_r = 0.5 + math.asin((offset + k) / AMPLITUDE) / (2 * math.pi)

    def g(t: float) -> float:
        return offset * (t - t_r) + AMPLITUDE / (2 * math.pi) * (
            math.cos(2 * math.pi * t_r) - math.cos(2 * math.pi * t)
        )

    lo, hi = t_r + 0.5, t_r + 0.999  # g < 0 half a period after the release, > 0 just before t_r + 1
    assert g(lo) < 0.0 < g(hi)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < 0.0 else (lo, mid)
    return t_r, hi


def test_freewheel_carries_only_pushing_torque_and_releases_at_tau0_max_low() -> None:
    """Pure sine drive, first 1.2 s: locked while the driver pushes, released past tau0_max_low.

    Locked phase: w_in = w_out = A·(1 − cos 2πt)/(2π·(J_IN + J_OUT)) and the element's torque
    is −J_OUT·T/(J_IN + J_OUT) (negative = pushing inertiaOut forward). The release is not at
    the zero of the drive (0.5 s) but 0.95 ms later, where the pull reaches tau0_max_low
    (spec §5.3); after it inertiaOut coasts at constant speed and the element carries nothing.
    """
    r = _freewheel(0.0).simulate(StopTime=1.2, Interval=1e-3, Tolerance=TOL)
    t_r, _ = _freewheel_times(0.0)
    assert t_r - 0.5 > 9e-4  # the threshold matters: 0.95 ms ≫ the event accuracy below
    events = _events_of(r, "oneWayClutch")
    assert [e[2] for e in events] == [0, 1]  # stuck at t0 (w_rel = 0), released once
    # sa − tau0_max is a smooth function of time crossing with slope ≈ 2π·A·J_OUT/(J_IN+J_OUT)
    assert events[1][0] == pytest.approx(t_r, abs=1e-6)

    t, tau = r.time, r["oneWayClutch.tau"]
    drive = r["wave.y"]
    np.testing.assert_allclose(r["oneWayClutch.tau0_max"], TAU0_MAX_LOW, rtol=1e-12)
    assert np.all(r["oneWayClutch.u"] == 0.0) and np.all(r["oneWayClutch.lossPower"] == 0.0)
    w_scale = AMPLITUDE / (math.pi * (J_IN + J_OUT))  # the peak common speed, ≈ 1.06 rad/s
    w_tol = 10 * TOL * w_scale
    locked = t < t_r - 1e-9
    w_common = AMPLITUDE * (1 - np.cos(2 * np.pi * t)) / (2 * np.pi * (J_IN + J_OUT))
    np.testing.assert_allclose(r["inertiaIn.w"][locked], w_common[locked], rtol=0, atol=w_tol)
    np.testing.assert_allclose(r["inertiaOut.w"][locked], w_common[locked], rtol=0, atol=w_tol)
    np.testing.assert_allclose(tau[locked], -J_OUT * drive[locked] / (J_IN + J_OUT), rtol=1e-9, atol=1e-12)
    assert np.all(r["oneWayClutch.stuck"][locked] == 1)
    # stuck ends when w_rel clears the 1e-10 rad/s event hysteresis, 1.7e-9 s after the release
    free = t > t_r + 1e-8
    w_r = AMPLITUDE * (1 - math.cos(2 * math.pi * t_r)) / (2 * math.pi * (J_IN + J_OUT))
    assert np.all(tau[free] == 0.0) and np.all(r["oneWayClutch.stuck"][free] == 0)
    np.testing.assert_allclose(r["inertiaOut.w"][free], w_r, rtol=0, atol=w_tol)
    w_in = w_r + AMPLITUDE * (math.cos(2 * math.pi * t_r) - np.cos(2 * np.pi * t[free])) / (2 * np.pi * J_IN)
    np.testing.assert_allclose(r["inertiaIn.w"][free], w_in, rtol=0, atol=w_tol)
    # It never pulls: a positive (pulling) torque above the release threshold never occurs,
    # and it only carries torque while stuck. (The release fires once the pull clears the
    # threshold by the 1e-10 N·m event hysteresis.)
    assert tau.max() <= TAU0_MAX_LOW + 2e-10
    assert np.all(r["oneWayClutch.stuck"][tau != 0.0] == 1)
    assert tau.min() < -5.0  # and it really carries the push (up to 2/3 of 10 N·m)
    assert r["oneWayClutch.w_rel"].min() >= -1e-6


@pytest.mark.parametrize("offset", [3.0, 0.0])
def test_freewheel_relocks_when_the_driver_catches_up(offset: float) -> None:
    """After a release the freewheel locks again where w_in catches up with w_out.

    It must never slide backward: w_rel = w_out − w_in ≥ 0 up to the solver tolerance
    (−1e-6 rad/s is ≈ 10× W_TOL). With offset 3 N·m the catch-up happens with the driver
    pushing hard (12.6 N·m); with the pure sine (offset 0) w_in catches up at 2 − t_r,
    1.9 ms before the drive reverses, where w_rel falls through 0 at 0.06 rad/s²: the element
    must lock there and release again at t_r + 1, where the pull reaches tau0_max_low again.
    """
    r = _freewheel(offset).simulate(StopTime=1.7, Interval=1e-3, Tolerance=TOL)
    t_r, t_l = _freewheel_times(offset)
    assert r["oneWayClutch.w_rel"].min() >= -1e-6, (
        f"w_rel = {r['oneWayClutch.w_rel'].min():.3g} rad/s: the freewheel slid backward "
        f"(expected to lock at t = {t_l:.6f} s)"
    )
    events = _events_of(r, "oneWayClutch")
    assert [e[2] for e in events] == [0, 1, 0, 1]  # stuck, released, relocked, released
    # Release: as in the test above. Relock: w_rel crosses 0 at T(t_l)/J_IN ≥ 0.06 rad/s², so
    # W_TOL/0.06 ≈ 2e-6 s; we allow 1e-5 s.
    assert [e[0] for e in events[1:]] == pytest.approx([t_r, t_l, t_r + 1.0], abs=1e-5)


# --- ElastoBacklash (spec §5.6) -----------------------------------------------------------
J_A, J_B, V0, C_BL, B_BL = 1.0, 3.0, 1.0, 1e4, 0.02  # backlash b = 0.02 rad (±0.01 rad)


def _backlash(d: float) -> st.Model:
    """Ja at rest and Jb at V0 on both sides of an ElastoBacklash (flange_a — Ja, flange_b — Jb).

    phi_rel = phi_b − phi_a grows at V0 from 0: the gap closes at t_c = (b/2)/V0 = 0.01 s
    into the positive contact, where the spring c = 1e4 N·m/rad is compressed.
    """
    m = st.Model("backlash")
    m.add("Ja", st.Inertia(J=J_A, phi=0.0, w=0.0))
    m.add("backlash", st.ElastoBacklash(c=C_BL, d=d, b=B_BL))
    m.add("Jb", st.Inertia(J=J_B, phi=0.0, w=V0))
    m.connect("Ja.flange_b", "backlash.flange_a")
    m.connect("backlash.flange_b", "Jb.flange_a")
    return m


def test_backlash_contact_is_free_in_the_gap_then_continuous_and_only_pushes() -> None:
    """d = 20: no torque while |phi_rel| < b/2, then a contact torque that starts from 0.

    The soft contact (spec §5.6) limits the damping torque to the spring torque, so
    0 ≤ tau ≤ 2·tau_c with tau_c = c·(phi_rel − b/2), and a torque that would pull (the
    linear law tau_c + d·w_rel < 0 while rebounding) is replaced by 0.
    """
    d = 20.0
    r = _backlash(d).simulate(StopTime=0.05, Interval=1e-4, Tolerance=TOL)
    t, phi, tau = r.time, r["backlash.phi_rel"], r["backlash.tau"]
    t_c = B_BL / 2 / V0
    # the first event is the contact, found on the linear phi_rel = V0·t
    events = _event_rows(r)
    assert events.size >= 2 and events[0] == pytest.approx(t_c, abs=1e-9)
    gap = t < t_c
    assert np.all(tau[gap] == 0.0)
    assert np.all(r["Ja.w"][gap] == 0.0) and np.all(r["Jb.w"][gap] == V0)
    # continuous start: both limits at the contact instant are (nearly) zero torque
    peak = tau.max()
    assert peak > 10.0  # a real impact (≈ 40 N·m)
    at_contact = np.flatnonzero(t == events[0])
    assert at_contact.size == 2 and np.abs(tau[at_contact]).max() < 1e-9 * peak
    # only pushes, never more than twice the spring torque, zero inside the gap
    inside = np.abs(phi) <= B_BL / 2
    assert np.all(tau[inside] == 0.0)
    tau_c = C_BL * (phi - B_BL / 2)
    contact = phi > B_BL / 2
    # the switch to "no pulling" is an event located where the pull passes the relations'
    # band (1e-10 N·m, as every relation's): until then it may pull that much, no more
    band = 1e-10
    assert tau.min() >= -band
    assert np.all(tau[contact] <= 2 * tau_c[contact] * (1 + 1e-12))
    # the "pulling" branch really occurs on the rebound, and it is cut to zero there
    pulling = contact & (tau_c + d * r["backlash.w_rel"] < 0)
    assert pulling.sum() >= 3 and np.all(np.abs(tau[pulling]) <= band)
    # the damper took energy out: kinetic energy after the impact is below the initial one
    ke = r["system.kineticEnergy"]
    assert ke[-1] < 0.95 * ke[0]


def test_elastic_backlash_contact_conserves_kinetic_energy() -> None:
    """d = 0: the contact is a linear spring, so the impact is elastic.

    After separation the speeds are those of an elastic collision,
    w_a = 2·J_B·V0/(J_A + J_B) = 1.5 and w_b = (J_B − J_A)·V0/(J_A + J_B) = 0.5 rad/s, the
    spring is unloaded again and kinetic energy is conserved. Contact lasts half a period of
    the relative oscillation, π·sqrt(μ/c) with μ = J_A·J_B/(J_A + J_B).

    Run at Tolerance 1e-10: half an oscillation over ~60 steps accumulates a global error of a
    few local errors (measured 4e-10 relative at 1e-10, 1.6e-7 at 1e-8); we allow 1e-8 = 100×.
    """
    tol = 1e-10
    r = _backlash(0.0).simulate(StopTime=0.05, Interval=1e-4, Tolerance=tol)
    t_c = B_BL / 2 / V0
    mu = J_A * J_B / (J_A + J_B)
    t_sep = t_c + math.pi * math.sqrt(mu / C_BL)  # ≈ 0.0372 s; next contact only at ≈ 0.057 s
    events = _event_rows(r)
    assert events.size == 2
    assert events[0] == pytest.approx(t_c, abs=1e-9)
    # phi_rel leaves the contact at |w_rel| = V0, so its error (≪ 1e-8 rad) shifts it ≪ 1e-6 s
    assert events[1] == pytest.approx(t_sep, abs=1e-6)
    after = r.time > t_sep + 1e-6
    ke0 = 0.5 * J_B * V0**2
    np.testing.assert_allclose(r["Ja.w"][after], 2 * J_B * V0 / (J_A + J_B), rtol=1e-8)
    np.testing.assert_allclose(r["Jb.w"][after], (J_B - J_A) * V0 / (J_A + J_B), rtol=1e-8)
    np.testing.assert_allclose(r["system.kineticEnergy"][after], ke0, rtol=1e-8)
    assert np.all(r["backlash.tau"][after] == 0.0)
    assert np.all(r["backlash.lossPower"] == 0.0)  # d = 0: nothing is dissipated
    # Energy really went into the spring: at the deepest compression both turn at the common
    # speed J_B·V0/(J_A + J_B), with kinetic energy J_B/(J_A + J_B)·ke0 = 1.125 J. The output
    # rows (1e-4 s) sample that minimum of a 115 rad/s oscillation to ≈ (115·5e-5)²/2 ≈ 2e-5.
    ke_min = J_B / (J_A + J_B) * ke0
    assert r["system.kineticEnergy"].min() == pytest.approx(ke_min, rel=1e-4)
    assert r["system.potentialEnergy"].max() == pytest.approx(ke0 - ke_min, rel=1e-3)


# --- IdealPlanetary (spec §5.8) -----------------------------------------------------------
def test_planetary_with_the_ring_held_is_a_reduction_by_one_plus_ratio() -> None:
    """Ring on a Fixed: carrier.w = sun.w/(1 + ratio), ring.tau = ratio·sun.tau and
    carrier.tau = −(1 + ratio)·sun.tau.

    A constant torque T on the sun shaft (J_s) drives the carrier shaft (J_c): the sun
    accelerates at T/(J_s + J_c/(1 + ratio)²), and the sun flange carries the carrier
    inertia referred to the sun, sun.tau = J_c·a_sun/(1 + ratio)².
    """
    ratio, J_s, J_c, T, w0 = 2.5, 0.2, 3.0, 4.0, 1.0
    m = st.Model("planetary")
    m.add("drive", st.ConstantTorque(tau_constant=T))
    m.add("sunShaft", st.Inertia(J=J_s, phi=0.0, w=w0))
    m.add("planetary", st.IdealPlanetary(ratio=ratio))
    m.add("ground", st.Fixed())
    m.add("carrierShaft", st.Inertia(J=J_c))
    m.connect("drive.flange", "sunShaft.flange_a")
    m.connect("sunShaft.flange_b", "planetary.sun")
    m.connect("planetary.ring", "ground.flange")
    m.connect("planetary.carrier", "carrierShaft.flange_a")
    r = m.simulate(StopTime=1.0, Interval=1e-2, Tolerance=TOL)

    a_sun = T / (J_s + J_c / (1 + ratio) ** 2)
    w_sun = r["sunShaft.w"]
    np.testing.assert_allclose(w_sun, w0 + a_sun * r.time, rtol=10 * TOL)
    np.testing.assert_allclose(r["carrierShaft.w"], w_sun / (1 + ratio), rtol=1e-12)
    phi = {p: r[f"planetary.{p}.phi"] for p in ("sun", "carrier", "ring")}
    assert np.all(phi["ring"] == 0.0)
    np.testing.assert_allclose(
        (1 + ratio) * phi["carrier"], phi["sun"] + ratio * phi["ring"], rtol=1e-12, atol=1e-15
    )
    tau = {p: r[f"planetary.{p}.tau"] for p in ("sun", "carrier", "ring")}
    np.testing.assert_allclose(tau["sun"], J_c * a_sun / (1 + ratio) ** 2, rtol=1e-9)
    np.testing.assert_allclose(tau["ring"], ratio * tau["sun"], rtol=1e-12)
    np.testing.assert_allclose(tau["carrier"], -(1 + ratio) * tau["sun"], rtol=1e-12)
    np.testing.assert_allclose(r["ground.flange.tau"], -tau["ring"], rtol=1e-12)  # the reaction
