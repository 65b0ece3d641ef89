"""HeatLosses (spec §7.2): every lossy element heats one thermal node without capacity.

No reference trajectory exists (MAP-LIB stores HeatLosses only as a Git-LFS .mat file), so
the checks are the physics of the example: the thermal algebra of the node, the heat balance
against the loss powers and the mechanical energy audit, the absence of chattering, the
number of state events and the modes at t0. The model runs twice, each result cached for the
module: with its own experiment (Tolerance 1e-6, as the Dymola reference runs) and at
Tolerance 1e-8 for the energy balances.
"""

from __future__ import annotations

from collections import defaultdict
from functools import cache

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

MODEL = MSL_EXAMPLES / "HeatLosses.toml"
LOSSY = (
    "damper",
    "springDamper",
    "elastoBacklash",
    "bearingFriction",
    "lossyGear",
    "clutch",
    "oneWayClutch",
    "brake",
)
T_AMBIENT = 298.15  # K: TAmbient is 25 °C
GC = 20.0  # W/K: const.k → convection.Gc
STOP = 1.0  # s
TOL = 1e-8
ENERGY_REL_TOL = 1e-6  # of the energy scale, as in test_energy.py
BACKLASH_C, BACKLASH_B = 1e5, 0.001  # elastoBacklash c [N·m/rad] and b [rad]


@cache
def _msl_run() -> st.Result:
    """The model file's own experiment (StopTime 1, Tolerance 1e-6)."""
    return st.Model.load(MODEL).simulate()


@cache
def _tight_run() -> st.Result:
    return st.Model.load(MODEL).simulate(Tolerance=TOL)


def _total_loss(r: st.Result) -> np.ndarray:
    return np.sum([r[f"{n}.lossPower"] for n in LOSSY], axis=0)


def _running_trapezoid(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """∫y dt from t0 to every row (an event's two rows add a zero-width interval)."""
    return np.concatenate([[0.0], np.cumsum(np.diff(t) * (y[1:] + y[:-1]) / 2.0)])


def _running_trapezoid_error(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A running bound on the trapezoid rule's error for y on the result rows.

    Events split the rows into pieces (an event instant is written twice), and y is smooth
    on each piece except for a few noEvent kinks of the ElastoBacklash soft contact (spec
    §5.6: the min/max of spring and damper torque), which the output grid does not resolve.
    On an interval of width h the trapezoid error is ≈ h·|Δ²y|/12 where Δ²y is the second
    difference at its ends; we sum h·|Δ²y|/2 (6× that) so that the unresolved kinks, where
    the second difference underestimates the local curvature, are covered too.
    """
    h = np.diff(t)
    err = np.zeros(h.size)
    cuts = np.flatnonzero(h == 0.0) + 1
    for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, t.size], strict=True):
        if hi - lo < 3:
            continue
        d2 = np.abs(np.diff(y[lo:hi], 2))
        ends = np.zeros(hi - lo - 1)
        ends[:-1] = d2
        ends[1:] = np.maximum(ends[1:], d2)
        err[lo : hi - 1] = h[lo : hi - 1] * ends / 2.0
    return np.concatenate([[0.0], np.cumsum(err)])


def _energy_scale(r: st.Result) -> float:
    terms = ("system.kineticEnergy", "system.potentialEnergy", "system.dissipatedEnergy", "system.sourceWork")
    return max(float(np.abs(r[n]).max()) for n in terms)


# --- (a) thermal algebra -------------------------------------------------------------------
def test_node_temperature_is_ambient_plus_total_loss_over_gc() -> None:
    """convection.solid.T = 298.15 K + Σ lossPower/20 W/K at every row (no heat capacity).

    Algebraic: T is computed near 298 K, where one ulp is 5.7e-14 K; we allow 8 ulps. The
    eight heat ports sit on that node and each carries Q_flow = −lossPower (spec §2.4).
    """
    r = _msl_run()
    assert sorted(n for n in r.names if n.endswith(".lossPower")) == sorted(f"{n}.lossPower" for n in LOSSY)
    total = _total_loss(r)
    node = r["convection.solid.T"]
    np.testing.assert_allclose(node, T_AMBIENT + total / GC, rtol=0, atol=8 * np.spacing(T_AMBIENT))
    for name in LOSSY:
        np.testing.assert_array_equal(r[f"{name}.heatPort.T"], node, err_msg=name)
        np.testing.assert_allclose(
            r[f"{name}.heatPort.Q_flow"], -r[f"{name}.lossPower"], rtol=0, atol=1e-15, err_msg=name
        )
    assert r["convection.fluid.T"][0] == T_AMBIENT and np.ptp(r["convection.fluid.T"]) == 0.0
    assert node.max() - T_AMBIENT > 0.05  # K: it really heats up (≈ 1.75 W peak → 0.088 K)
    assert total.min() >= -1e-12  # every element only dissipates (stuck ones drift ≈ 0)


# --- (b) heat balance ------------------------------------------------------------------------
def test_heat_to_the_environment_is_the_integral_of_the_loss_powers() -> None:
    """−∫convection.fluid.Q_flow dt = ∫Σ lossPower dt: all heat leaves through the convection.

    Both integrals use the trapezoid rule on the same rows, so its quadrature error cancels and
    only the per-row round-off is left: Q_flow = Gc·(T_solid − T_fluid) with T_solid rounded
    near 298 K, i.e. ≤ Gc·8 ulp(298.15) ≈ 9e-12 W per row, ≈ 9e-12 J over the 1 s run.
    """
    r = _tight_run()
    t = r.time
    heat = _running_trapezoid(t, -r["convection.fluid.Q_flow"])
    loss = _running_trapezoid(t, _total_loss(r))
    per_row = GC * 8 * np.spacing(T_AMBIENT)
    np.testing.assert_allclose(-r["convection.fluid.Q_flow"], _total_loss(r), rtol=0, atol=per_row)
    np.testing.assert_allclose(heat, loss, rtol=0, atol=per_row * STOP)
    assert heat[-1] > 0.3  # J: ≈ 0.328 J leave the drive train as heat


def test_dissipated_energy_is_the_heat_plus_the_backlash_separation_loss() -> None:
    """system.dissipatedEnergy ≥ the heat, and the excess is the ElastoBacklash separation loss.

    The audit integrates the power every element takes out of the drive train. For the
    ElastoBacklash that is tau·w_rel − d/dt(½·c·(|phi_rel| − b/2)²); it exceeds lossPower by
    (tau − tau_c)·w_rel − lossPower, which is 0 in the gap and while pushing, and
    −tau_c·w_rel ≥ 0 where MSL cuts a pulling contact torque to 0: the spring energy released
    there is not in any lossPower (spec §5.6). So dissipatedEnergy = ∫(Σ lossPower + that) dt.

    Tolerance: the trapezoid error bound of _running_trapezoid_error on the rows, plus the
    audit's own integration error, 10·Tolerance·(energy scale).
    """
    r = _tight_run()
    t = r.time
    diss = r["system.dissipatedEnergy"]
    loss = _total_loss(r)
    heat = _running_trapezoid(t, -r["convection.fluid.Q_flow"])
    solver = 10 * TOL * _energy_scale(r)
    bound = _running_trapezoid_error(t, loss) + solver
    assert np.all(diss >= heat - bound), float((diss - heat + bound).min())

    phi, w_rel, tau = r["elastoBacklash.phi_rel"], r["elastoBacklash.w_rel"], r["elastoBacklash.tau"]
    half = BACKLASH_B / 2
    tau_c = np.where(
        phi > half, BACKLASH_C * (phi - half), np.where(phi < -half, BACKLASH_C * (phi + half), 0.0)
    )
    separation = (tau - tau_c) * w_rel - r["elastoBacklash.lossPower"]
    assert separation.min() >= -1e-9 * np.abs(tau * w_rel).max()  # only ever a loss
    audit = _running_trapezoid(t, loss + separation)
    bound_all = _running_trapezoid_error(t, loss + separation) + solver
    assert np.all(np.abs(diss - audit) <= bound_all), float((np.abs(diss - audit) / bound_all).max())
    # The separation loss is real (≈ 0.26 % of the heat), larger than the checks' tolerance.
    assert diss[-1] - heat[-1] > max(1e-4, 2 * bound_all[-1])


# --- (c) energy closure ----------------------------------------------------------------------
def test_energy_closure_at_tolerance_1e_8() -> None:
    """kinetic + potential + dissipated − source work stays at its initial value 0.

    Everything starts at rest and unstretched. Drift bound 1e-6 of the energy scale, as in
    test_energy.py (global error of an error-controlled integrator over a run with ~120
    restarts, each energy term quadratic in the states): measured 2.6e-7.
    """
    r = _tight_run()
    total = (
        r["system.kineticEnergy"]
        + r["system.potentialEnergy"]
        + r["system.dissipatedEnergy"]
        - r["system.sourceWork"]
    )
    assert total[0] == 0.0
    drift = np.abs(total - total[0]).max() / _energy_scale(r)
    assert drift < ENERGY_REL_TOL, drift
    assert r["system.sourceWork"][-1] > 0.3  # J: the drive really does work
    assert r["system.dissipatedEnergy"][-1] > 0.8 * r["system.sourceWork"][-1]


# --- (d) no chattering -----------------------------------------------------------------------
RUNS = {"msl": _msl_run, "tight": _tight_run}


@pytest.mark.parametrize("run", list(RUNS))
def test_no_element_chatters(run: str) -> None:
    """No element changes its mode more than 4 times within 1e-6 s, and every logged event is
    a real change. (A transition such as Forward → Stuck → Backward may take two changes at
    one instant; an event iteration that cannot settle would log many more.)"""
    r = RUNS[run]()
    times: dict[str, list[float]] = defaultdict(list)
    for e in r.events:
        assert e.old_mode != e.new_mode, e
        times[e.component].append(e.time)
    assert set(times) == {"bearingFriction", "lossyGear", "clutch", "oneWayClutch", "brake"}
    for name, ts in times.items():
        ts_sorted = np.sort(ts)
        burst = np.searchsorted(ts_sorted, ts_sorted + 1e-6, side="right") - np.arange(ts_sorted.size)
        assert burst.max() <= 4, (name, float(ts_sorted[burst.argmax()]), int(burst.max()))


# --- (e) state events and modes over time ----------------------------------------------------
def test_state_event_count_and_modes_over_time() -> None:
    """About as many state events as Dymola logged (126), and every kind of mode occurs.

    The event count depends on the tool (which crossings are separate, which coincide), so
    only its magnitude is checked: 80…200. HeatLosses has no Step/Ramp/Pulse, hence no time
    events. The modes: bearing and gear turn both ways and stick; the clutch starts free and
    then slides both ways and sticks; the brake only brakes forward, because inertia6 is
    driven only through the freewheel, which can only push it forward (so w ≥ 0); the
    freewheel alternates between stuck and overrunning.
    """
    r = _msl_run()
    assert 80 <= r.stats["state_events"] <= 200, r.stats
    assert r.stats["time_events"] == 0, r.stats
    t = r.time
    expected = {
        "bearingFriction.mode": {-1, 0, 1},
        "lossyGear.mode": {-1, 0, 1},
        "clutch.mode": {-1, 0, 1, 2},
        "brake.mode": {0, 1, 2},
        "oneWayClutch.stuck": {0, 1},
    }
    for name, values in expected.items():
        y = r[name]
        assert set(np.unique(y).astype(int).tolist()) == values, name
        # discrete signals change only at event instants (rows written twice)
        for i in np.flatnonzero(np.diff(y) != 0.0):
            assert t[i] == t[i + 1], (name, t[i])
    assert r["inertia6.w"].min() > -1e-9
    assert np.all(r["oneWayClutch.w_rel"] >= -1e-6)
    # every logged mode change is at an event instant of the rows
    event_rows = set(t[np.flatnonzero(np.diff(t) == 0.0)].tolist())
    assert all(e.time in event_rows for e in r.events if e.time > 0.0)


# --- (f) modes at t0 -------------------------------------------------------------------------
def test_modes_at_t0_follow_the_spec() -> None:
    """At t0 (spec §7.2): bearingFriction and lossyGear stuck (0), clutch and brake free (2,
    because sine2 = 0 gives fn = 0), oneWayClutch stuck. Right after t0 sine2 > 0: clutch and
    brake become active, and everything being at rest, they stick (0)."""
    r = _msl_run()
    first = {n: r[n][0] for n in ("bearingFriction.mode", "lossyGear.mode", "clutch.mode", "brake.mode")}
    assert first == {"bearingFriction.mode": 0, "lossyGear.mode": 0, "clutch.mode": 2, "brake.mode": 2}
    assert r["oneWayClutch.stuck"][0] == 1 and r["oneWayClutch.locked"][0] == 1
    assert r["sine2.y"][0] == 0.0 and r["clutch.fn"][0] == 0.0 and r["brake.fn"][0] == 0.0
    init = {e.component: (e.old_mode, e.new_mode) for e in r.events if e.cause == "initialization"}
    assert init["bearingFriction"] == (3, 0) and init["lossyGear"] == (2, 0)  # pre-modes: §10.1
    assert init["clutch"] == (3, 2) and init["brake"] == (3, 2)
    for name in ("clutch", "brake"):
        engage = next(e for e in r.events if e.component == name and e.cause != "initialization")
        assert engage.time < 1e-9 and (engage.old_mode, engage.new_mode) == (2, 0), engage
    soon = (r.time > 1e-9) & (r.time < 0.03)  # before anything breaks away (≈ 0.034 s)
    assert soon.sum() > 100
    for name in ("clutch.mode", "brake.mode", "bearingFriction.mode", "lossyGear.mode"):
        assert np.all(r[name][soon] == 0), name
    assert np.all(r["oneWayClutch.stuck"][soon] == 1)


def test_the_freewheel_released_for_a_millisecond_slides_and_locks_again_exactly() -> None:
    """At 0.521094 s the clutch locks and the freewheel's constraint torque flips past its
    static limit: it starts forward, its slip rises and falls back to zero within one
    integrator step. The slip crossing the event band is an event (found at the slip's peak
    on the dense output), so it slides and locks again with its slip inside the band, and
    its balance closes (before: it locked at a slip of 8e-6 rad/s and kept it for 9 ms)."""
    r = _msl_run()
    starts = [e.time for e in r.events if e.component == "oneWayClutch" and "sliding forward" in str(e)]
    assert any(abs(t - 0.521094) < 1e-5 for t in starts), starts
    locked = r["oneWayClutch.locked"] == 1.0
    assert np.abs(r["oneWayClutch.w_rel"][locked]).max() <= 2e-10
    assert r.audit().ok()
