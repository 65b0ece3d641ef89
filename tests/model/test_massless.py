"""Shafts without inertia whose speed a damper determines (issue 14).

Such a shaft's angle is a state and its speed algebraic, from its torque balance 0 = Σ τ, as a
Modelica tool has it after index reduction. The oracles are the hand-written equations: a matrix
exponential for the linear spring–damper series, scipy's `solve_ivp` at 1e-12 with the
stick/slip phases done by hand for the clutch line.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

import stiction as st

TOL = 1e-10


def _energy_drift(r: st.Result) -> float:
    """max |E(t) − E(0)| over the energy scale, E = KE + PE + dissipated − source work."""
    terms = ("system.kineticEnergy", "system.potentialEnergy", "system.dissipatedEnergy", "system.sourceWork")
    total = r[terms[0]] + r[terms[1]] + r[terms[2]] - r[terms[3]]
    scale = max(float(np.abs(r[n]).max()) for n in terms)
    return float(np.abs(total - total[0]).max()) / scale


# --- 1. a spring in series with a damper ------------------------------------------------------

J, C, D, W0 = 2.0, 400.0, 30.0, 10.0


def _spring_damper_series() -> st.Model:
    """J1 (w0) —spring c— n —damper d— housing; n has no inertia."""
    m = st.Model("series")
    m.add("J1", st.Inertia(J=J, phi=0.0, w=W0))
    m.add("spring", st.Spring(c=C, phi_rel=0.0))
    m.add("damper", st.Damper(d=D))
    m.add("fixed", st.Fixed())
    m.connect("J1.flange_b", "spring.flange_a")
    m.connect("spring.flange_b", "damper.flange_a")
    m.connect("damper.flange_b", "fixed.flange")
    m.experiment.update(StopTime=1.0, Interval=1e-3, Tolerance=TOL)
    return m


def _series_exact(t: np.ndarray) -> np.ndarray:
    """(φ1, w1, φn) from y' = A·y: J·w1' = −c(φ1 − φn), d·φn' = c(φ1 − φn)."""
    a = np.array([[0.0, 1.0, 0.0], [-C / J, 0.0, C / J], [C / D, 0.0, -C / D]])
    y0 = np.array([0.0, W0, 0.0])
    step = expm(a * 1e-3)  # the rows are the 1 ms grid: propagate exactly from row to row
    assert np.allclose(np.diff(t), 1e-3, rtol=0.0, atol=1e-12)
    y = [y0]
    for _ in t[1:]:
        y.append(step @ y[-1])
    return np.array(y)


def test_spring_in_series_with_a_damper_matches_the_closed_form() -> None:
    r = _spring_damper_series().simulate()
    y = _series_exact(r.time)
    phi1, w1, phin = y.T
    wn = C * (phi1 - phin) / D  # the damper's speed: algebraic, from the node's balance
    scale = W0
    assert np.abs(r["J1.w"] - w1).max() < 1e-7 * scale
    assert np.abs(r["J1.phi"] - phi1).max() < 1e-7
    assert np.abs(r["damper.phi_rel"] + phin).max() < 1e-7
    assert np.abs(r["damper.w_rel"] + wn).max() < 1e-6 * scale
    # the acceleration of the massless node is the derivative of its algebraic speed
    an = C * (w1 - wn) / D
    assert np.abs(r["damper.a_rel"] + an).max() < 1e-5 * np.abs(an).max()
    # torque balance of the massless node: spring and damper carry the same torque
    assert np.abs(r["spring.tau"] - r["damper.tau"]).max() < 1e-9 * np.abs(r["spring.tau"]).max()
    assert _energy_drift(r) < 1e-7


def test_the_recorded_speed_of_the_massless_shaft_is_the_algebraic_one() -> None:
    """Read directly from the rows (no evaluation): the rows hold the solved speed."""
    r = _spring_damper_series().simulate()
    y = _series_exact(r.time)
    wn = C * (y[:, 0] - y[:, 2]) / D
    assert np.abs(r["spring.flange_b.phi"] - y[:, 2]).max() < 1e-7
    assert np.abs(r["damper.w_rel"] + wn).max() < 1e-6 * W0


# --- 2. clutch – IdealGear – SpringDamper, no gear inertia ------------------------------------

J1, J2, T_DRIVE, W1 = 1.0, 2.0, 2.0, 10.0
RATIO, C2, D2 = 2.0, 200.0, 5.0
FN, MU, PEAK = 20.0, 0.5, 1.5
TF = MU * FN  # sliding torque (cgeo = 1)
T_PRESS = 0.1  # before it, the clutch is open and the gear shafts rest with J2


def _clutch_gear_line(release: float | None = None) -> st.Model:
    """torque → J1 → clutch → gear (ratio, no inertia) → spring/damper → J2; the clutch is
    pressed at T_PRESS (so the start is unambiguous: open, the gear shafts turn with J2)."""
    m = st.Model("clutch_gear")
    m.add("drive", st.ConstantTorque(tau_constant=T_DRIVE))
    m.add("J1", st.Inertia(J=J1, phi=0.0, w=W1))
    m.add("clutch", st.Clutch(fn_max=FN, peak=PEAK))
    if release is None:
        m.add("press", st.Step(height=1.0, startTime=T_PRESS))
    else:  # pressed from T_PRESS to `release`
        width = 100.0 * (release - T_PRESS) / 10.0
        m.add("press", st.Pulse(period=10.0, width=width, nperiod=1, startTime=T_PRESS))
    m.add("gear", st.IdealGear(ratio=RATIO))
    m.add("sd", st.SpringDamper(c=C2, d=D2, phi_rel=0.0))
    m.add("J2", st.Inertia(J=J2, phi=0.0, w=0.0))
    m.connect("drive.flange", "J1.flange_a")
    m.connect("J1.flange_b", "clutch.flange_a")
    m.connect("press.y", "clutch.f_normalized")
    m.connect("clutch.flange_b", "gear.flange_a")
    m.connect("gear.flange_b", "sd.flange_a")
    m.connect("sd.flange_b", "J2.flange_a")
    m.experiment.update(StopTime=1.5, Interval=1e-3, Tolerance=TOL)
    return m


def _slip(_t: float, y: np.ndarray) -> list[float]:
    """Slipping (J1 faster): the clutch passes TF; the gear's flange_b speed solves
    ratio·TF = c(φb − φ2) + d(wb − w2)."""
    _phi1, w1, phib, phi2, w2 = y
    wb = w2 + (RATIO * TF - C2 * (phib - phi2)) / D2
    tau_sd = RATIO * TF
    return [w1, (T_DRIVE - TF) / J1, wb, w2, tau_sd / J2]


def _slip_ends(t: float, y: np.ndarray) -> float:
    return y[1] - RATIO * _slip(t, y)[2]


_slip_ends.terminal = True  # type: ignore[attr-defined]


def _locked(_t: float, y: np.ndarray) -> list[float]:
    """Locked: the gear turns with J1 (wb = w1/ratio); J1 passes τ_sd/ratio to it."""
    _phi1, w1, phib, phi2, w2 = y
    tau_sd = C2 * (phib - phi2) + D2 * (w1 / RATIO - w2)
    return [w1, (T_DRIVE - tau_sd / RATIO) / J1, w1 / RATIO, w2, tau_sd / J2]


def _clutch_oracle() -> tuple[float, object, object]:
    """Open until T_PRESS (J1 accelerates alone, the rest at rest), slipping, then locked."""
    w1 = W1 + T_DRIVE / J1 * T_PRESS
    y0 = [W1 * T_PRESS + 0.5 * T_DRIVE / J1 * T_PRESS**2, w1, 0.0, 0.0, 0.0]
    opts = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12, "dense_output": True}
    slip = solve_ivp(_slip, (T_PRESS, 1.5), y0, events=_slip_ends, **opts)
    t_lock = float(slip.t_events[0][0])
    locked = solve_ivp(_locked, (t_lock, 1.5), slip.y[:, -1], **opts)
    return t_lock, slip.sol, locked.sol


def test_clutch_gear_line_without_inertia_slips_then_locks_as_the_hand_written_equations() -> None:
    t_lock, slip, locked = _clutch_oracle()
    r = _clutch_gear_line().simulate()
    # the lock instant, located as for any clutch
    assert r.lock_times("clutch") == [pytest.approx(t_lock, abs=1e-8)]
    t = r.time[r.time > T_PRESS]
    r_at = {name: r[name][r.time > T_PRESS] for name in r.names}
    after = t > t_lock
    y = np.where(after, locked(np.where(after, t, t_lock)), slip(np.where(after, t_lock, t)))
    for name, k in (("J1.w", 1), ("J2.w", 4), ("J2.phi", 3), ("sd.flange_a.phi", 2)):
        assert np.abs(r_at[name] - y[k]).max() < 1e-6 * W1, name
    wb = np.where(after, y[1] / RATIO, y[4] + (RATIO * TF - C2 * (y[2] - y[3])) / D2)
    assert np.abs((r_at["J2.w"] - r_at["sd.w_rel"]) - wb).max() < 1e-6 * W1  # the gear's speed
    # open: the gear shafts rest with J2 (the relaxed spring/damper holds them there)
    before = r.time < T_PRESS
    assert np.all(np.abs(r["sd.w_rel"][before]) < 1e-12) and np.all(np.abs(r["J2.w"][before]) < 1e-12)
    # the oracle's locked phase never needs more than the clutch can hold
    tau_sd = C2 * (y[2] - y[3]) + D2 * (y[1] / RATIO - y[4])
    assert np.abs(tau_sd[after] / RATIO).max() < PEAK * TF
    assert _energy_drift(r) < 1e-7


def test_tiny_gear_inertia_agrees_as_a_sanity_check() -> None:
    """The same line with 1e-6 kg·m² on the gear shafts (a stiff ODE, not the oracle)."""
    exact = _clutch_gear_line().simulate()
    m = _clutch_gear_line()
    m.add("Jg", st.Inertia(J=1e-6))
    m.connect("gear.flange_b", "Jg.flange_a")
    r = m.simulate(Solver="bdf", Tolerance=1e-8)
    assert r.lock_times("clutch")[0] == pytest.approx(exact.lock_times("clutch")[0], abs=1e-4)
    end = r["J2.w"][-1]
    assert end == pytest.approx(exact["J2.w"][-1], rel=1e-4)


def test_a_released_clutch_leaves_the_gear_shafts_to_their_damper() -> None:
    """Locked, then opened at 1.1 s: the gear shafts are massless again, and their speed jumps
    to the one the open balance gives, c(φb − φ2) + d(wb − w2) = 0; J2 then coasts and the
    spring relaxes as exp(−c·t/d)."""
    t_release = 1.1
    t_lock, _, locked = _clutch_oracle()
    r = _clutch_gear_line(release=t_release).simulate()
    assert r.lock_times("clutch") == [pytest.approx(t_lock, abs=1e-8)]
    _phi1, w1, phib, phi2, w2 = locked(t_release)
    after = r.time > t_release
    t = r.time[after] - t_release
    stretch = (phi2 - phib) * np.exp(-C2 / D2 * t)  # sd.phi_rel
    assert np.abs(r["sd.phi_rel"][after] - stretch).max() < 1e-6
    assert np.abs(r["sd.w_rel"][after] + C2 / D2 * stretch).max() < 1e-5 * W1
    assert np.abs(r["J2.w"][after] - w2).max() < 1e-6 * W1
    assert np.abs(r["J1.w"][after] - (w1 + T_DRIVE / J1 * t)).max() < 1e-6 * W1
    # at the release the gear's speed jumps: from J1's (over the ratio) to the open balance's
    rows = np.flatnonzero(r.time == t_release)
    wb = r["J2.w"][rows] - r["sd.w_rel"][rows]
    assert wb[0] == pytest.approx(w1 / RATIO, rel=1e-7)
    assert wb[-1] == pytest.approx(w2 - C2 * (phib - phi2) / D2, rel=1e-6)
    assert _energy_drift(r) < 1e-7


MU_TABLE = [[0.0, 0.6], [5.0, 0.4], [20.0, 0.3]]


def test_a_speed_dependent_friction_table_on_the_massless_shaft() -> None:
    """The clutch's mu falls with the slip speed, so the balance of the gear shafts is not
    affine in their speed (solved by Newton steps): the oracle solves
    c(φb − φ2) + d(wb − w2) = ratio·fn·mu(w1 − ratio·wb) by brentq at every evaluation."""
    from scipy.optimize import brentq

    def mu(w: float) -> float:
        return float(np.interp(abs(w), [p[0] for p in MU_TABLE], [p[1] for p in MU_TABLE]))

    def gear_speed(y: np.ndarray) -> float:
        _phi1, w1, phib, phi2, w2 = y

        def balance(wb: float) -> float:
            return C2 * (phib - phi2) + D2 * (wb - w2) - RATIO * FN * mu(w1 - RATIO * wb)

        return brentq(balance, -1e3, 1e3, xtol=1e-14, rtol=1e-15)  # monotone: d > ratio²·fn·|mu'|

    def slip(_t: float, y: np.ndarray) -> list[float]:
        w1, w2 = y[1], y[4]
        tf = FN * mu(w1 - RATIO * gear_speed(y))
        return [w1, (T_DRIVE - tf) / J1, gear_speed(y), w2, RATIO * tf / J2]

    def ends(_t: float, y: np.ndarray) -> float:
        return y[1] - RATIO * gear_speed(y)

    ends.terminal = True  # type: ignore[attr-defined]
    w1 = W1 + T_DRIVE / J1 * T_PRESS
    y0 = [W1 * T_PRESS + 0.5 * T_DRIVE / J1 * T_PRESS**2, w1, 0.0, 0.0, 0.0]
    oracle = solve_ivp(
        slip, (T_PRESS, 1.0), y0, events=ends, method="DOP853", rtol=1e-11, atol=1e-11, dense_output=True
    )
    t_lock = float(oracle.t_events[0][0])

    m = _clutch_gear_line()
    m.components["clutch"].params["mu_pos"] = MU_TABLE
    r = m.simulate()
    assert r.lock_times("clutch") == [pytest.approx(t_lock, abs=1e-7)]
    sliding = (r.time > T_PRESS) & (r.time < t_lock)
    y = oracle.sol(r.time[sliding])
    for name, k in (("J1.w", 1), ("J2.w", 4), ("sd.flange_a.phi", 2)):
        assert np.abs(r[name][sliding] - y[k]).max() < 1e-6 * W1, name
    wb = np.array([gear_speed(yk) for yk in y.T])
    assert np.abs((r["J2.w"] - r["sd.w_rel"])[sliding] - wb).max() < 1e-6 * W1
    assert _energy_drift(r) < 1e-7


# --- a chain of them: the banded solve --------------------------------------------------------

N_CHAIN, C3, D3 = 15, 100.0, 2.0


def test_a_chain_of_massless_links_matches_the_closed_form() -> None:
    """15 inertias linked by a spring then a damper (14 massless shafts between them): 29 nodes
    and 14 rows `Nᵀa = 0`, past the 40 unknowns where the banded LU takes over."""
    m = st.Model("chain")
    for i in range(N_CHAIN):
        m.add(f"J{i}", st.Inertia(J=1.0, phi=0.0, w=1.0 if i == 0 else 0.0))
    for i in range(N_CHAIN - 1):
        m.add(f"s{i}", st.Spring(c=C3, phi_rel=0.0))
        m.add(f"d{i}", st.Damper(d=D3))
        m.connect(f"J{i}.flange_b", f"s{i}.flange_a")
        m.connect(f"s{i}.flange_b", f"d{i}.flange_a")
        m.connect(f"d{i}.flange_b", f"J{i + 1}.flange_a")
    m.experiment.update(StopTime=2.0, Interval=1e-2, Tolerance=TOL)
    r = m.simulate()
    # states (φ_J, w_J, φ_m); w_m,i = w_J,i+1 − c(φ_m,i − φ_J,i)/d from each massless shaft
    n, k = N_CHAIN, N_CHAIN - 1
    a = np.zeros((2 * n + k, 2 * n + k))
    for i in range(n):
        a[i, n + i] = 1.0
    for i in range(k):
        pj, pm = i, 2 * n + i
        # w_m,i as a row over the states
        wm = np.zeros(2 * n + k)
        wm[n + i + 1], wm[pm], wm[pj] = 1.0, -C3 / D3, C3 / D3
        a[pm] += wm
        a[n + i, pm] += C3  # spring i on J_i
        a[n + i, pj] -= C3
        a[n + i + 1] -= D3 * (np.eye(2 * n + k)[n + i + 1] - wm)  # damper i on J_i+1
    y0 = np.zeros(2 * n + k)
    y0[n] = 1.0
    step = expm(a * 1e-2)
    y = [y0]
    for _ in r.time[1:]:
        y.append(step @ y[-1])
    y = np.array(y)
    for i in (0, n // 2, n - 1):
        assert np.abs(r[f"J{i}.w"] - y[:, n + i]).max() < 1e-7, i
    assert np.abs(r["d3.phi_rel"] - (y[:, 4] - y[:, 2 * n + 3])).max() < 1e-7
    assert _energy_drift(r) < 1e-7


# --- a shaft nothing determines ---------------------------------------------------------------


def test_two_springs_in_series_fail_in_check_with_the_shafts_named() -> None:
    m = st.Model("undetermined")
    m.add("J1", st.Inertia(J=1.0, w=1.0))
    m.add("s1", st.Spring(c=10.0))
    m.add("s2", st.Spring(c=10.0))
    m.add("fixed", st.Fixed())
    m.connect("J1.flange_b", "s1.flange_a")
    m.connect("s1.flange_b", "s2.flange_a")
    m.connect("s2.flange_b", "fixed.flange")
    with pytest.raises(st.ModelError, match=r"not determined: \[s1\.flange_b, s2\.flange_a\]"):
        m.check()
    with pytest.raises(st.SingularSystemError, match=r"s1\.flange_b, s2\.flange_a"):
        m.simulate(StopTime=0.1)


def test_check_passes_a_massless_shaft_a_damper_determines() -> None:
    _spring_damper_series().check()
    _clutch_gear_line().check()


# --- unconnected flanges ------------------------------------------------------------------------


def test_an_unconnected_flange_has_exactly_zero_torque() -> None:
    m = st.Model("open_end")
    m.add("drive", st.ConstantTorque(tau_constant=3.0))
    m.add("J1", st.Inertia(J=1.0))
    m.add("sd", st.SpringDamper(c=50.0, d=1.0))
    m.add("J2", st.Inertia(J=0.5))
    m.connect("drive.flange", "J1.flange_a")
    m.connect("J1.flange_b", "sd.flange_a")
    m.connect("sd.flange_b", "J2.flange_a")
    r = m.simulate(StopTime=1.0)
    assert np.all(r["J2.flange_b.tau"] == 0.0)
    # the connected flange carries the rest: J2's balance
    assert np.abs(r["J2.flange_a.tau"] - 0.5 * r["J2.a"]).max() < 1e-9
