"""Energy audit: kinetic + potential + dissipated − source work is the initial energy.

Friction (brakes, clutches) and dampers only turn kinetic or potential energy into heat,
and sources only add their work, so E(t) = KE + PE + ∫Σ lossPower − ∫source power is
constant. The engine reports the four terms as `system.*` columns.

Tolerance: the runs use Tolerance = 1e-8; we require |E(t) − E(0)| ≤ 1e-6 of the energy
scale (the largest of the four terms). Energy is quadratic in the speeds, so a relative
speed error ε gives ≈ 2ε in energy, and the global error of an error-controlled
integrator over a run with a dozen restarts stays within ~10–50 local tolerances: 1e-6 =
100·Tolerance covers that with room (measured worst: 2.3e-8, CoupledClutches).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from paths import EXAMPLES as ALL_EXAMPLES
from paths import MSL_EXAMPLES

import stiction as st

EXAMPLES = MSL_EXAMPLES
TOL = 1e-8
ENERGY_REL_TOL = 1e-6


def _braked_flywheel_with_spring() -> st.Model:
    """J1 —spring/damper— J2 —brake; the brake is pressed at 0.1 s and stops J2.

    J1 then rings on the spring against the held J2 and the damper takes the rest.
    """
    m = st.Model("spring_flywheel")
    m.add("J1", st.Inertia(J=2.0, phi=0.0, w=10.0))
    m.add("spring", st.SpringDamper(c=500.0, d=2.0))
    m.add("J2", st.Inertia(J=0.5, phi=0.0, w=10.0))
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=[[0.0, 0.5], [10.0, 0.4]], peak=1.2))
    m.add("press", st.Step(height=1.0, startTime=0.1))
    m.connect("J1.flange_b", "spring.flange_a")
    m.connect("spring.flange_b", "J2.flange_a")
    m.connect("J2.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment.update(StopTime=3.0, Interval=1e-3)
    return m


CASES: dict[str, tuple[Callable[[], st.Model], float]] = {
    # name: (model, initial energy ½·Σ J·w² in J, from the start values)
    "CoupledClutches": (lambda: st.Model.load(EXAMPLES / "CoupledClutches.toml"), 0.5 * 1.0 * 10.0**2),
    "Friction": (
        lambda: st.Model.load(EXAMPLES / "Friction.toml"),
        0.5 * (1.0 * 100.0**2 + 0.05 * 90.0**2 + 1.0 * 90.0**2),
    ),
    "spring_flywheel": (_braked_flywheel_with_spring, 0.5 * (2.0 * 10.0**2 + 0.5 * 10.0**2)),
}


@cache
def _run(name: str) -> st.Result:
    return CASES[name][0]().simulate(Tolerance=TOL)


def _scale(r: st.Result) -> float:
    terms = ("system.kineticEnergy", "system.potentialEnergy", "system.dissipatedEnergy", "system.sourceWork")
    return max(float(np.abs(r[n]).max()) for n in terms)


def _total_loss_power(r: st.Result) -> np.ndarray:
    names = [n for n in r.names if n.endswith(".lossPower")]
    assert names
    return np.sum([r[n] for n in names], axis=0)


@pytest.mark.parametrize("name", list(CASES))
def test_energy_balance_holds(name: str) -> None:
    """KE + PE + dissipated − source work equals the initial kinetic energy at all times."""
    r = _run(name)
    e0 = CASES[name][1]
    total = (
        r["system.kineticEnergy"]
        + r["system.potentialEnergy"]
        + r["system.dissipatedEnergy"]
        - r["system.sourceWork"]
    )
    assert total[0] == pytest.approx(e0, rel=1e-14)
    drift = np.abs(total - e0).max() / _scale(r)
    assert drift < ENERGY_REL_TOL, drift


@pytest.mark.parametrize("name", list(CASES))
def test_energy_really_flows(name: str) -> None:
    """The audit is not vacuous: most of the energy ends up dissipated, and never returns."""
    r = _run(name)
    diss = r["system.dissipatedEnergy"]
    assert diss[0] == 0.0 and r["system.sourceWork"][0] == 0.0
    assert diss[-1] > 0.5 * CASES[name][1]
    # Friction and damping only dissipate: while stuck, lossPower = sa·w with w only
    # drifting by the integration error, so allow that drift's tiny negative share.
    assert np.diff(diss).min() > -1e-9 * _scale(r)


def _trapezoid_error_bound(t: np.ndarray, p: np.ndarray) -> float:
    """Leading Euler–Maclaurin error of the trapezoid rule on each smooth piece.

    On a piece with step h the error is ≈ h²/12·(p'(end) − p'(start)); pieces are split
    at event instants (a repeated time), where p may jump. Summing |p'| at both ends of
    every piece, plus one more max|p'| for a partial piece, bounds the running error.
    """
    cuts = np.flatnonzero(np.diff(t) == 0.0) + 1
    bound, slope_max, h_max = 0.0, 0.0, 0.0
    for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, t.size], strict=True):
        ts, ps = t[lo:hi], p[lo:hi]
        if ts.size < 3:
            continue
        h = float(np.diff(ts).max())
        slopes = np.diff(ps) / np.diff(ts)
        bound += h * h / 12.0 * (abs(slopes[0]) + abs(slopes[-1]))
        slope_max, h_max = max(slope_max, float(np.abs(slopes).max())), max(h_max, h)
    return bound + h_max * h_max / 12.0 * slope_max


@pytest.mark.parametrize("name", list(CASES))
def test_dissipated_energy_is_the_integral_of_the_loss_powers(name: str) -> None:
    """system.dissipatedEnergy = ∫Σ lossPower dt, checked with the trapezoid rule.

    Looser than the audit: the trapezoid rule on the output grid has its own error, which
    we bound from the data (Euler–Maclaurin leading term, doubled for the higher terms).
    """
    r = _run(name)
    t, p = r.time, _total_loss_power(r)
    running = np.concatenate([[0.0], np.cumsum(np.diff(t) * (p[1:] + p[:-1]) / 2.0)])
    err = np.abs(running - r["system.dissipatedEnergy"]).max()
    bound = 2.0 * _trapezoid_error_bound(t, p) + 1e-9 * _scale(r)
    assert err < bound, (err, bound)
    assert bound < 1e-4 * _scale(r)  # and the check still means something


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_element_balances_its_power_and_none_that_is_passive_delivers_energy(path: Path) -> None:
    """`r.audit()`: for every component, the power entering at its flanges equals what its own
    equations take (inertia J·w·a, laws tau·w_rel, friction lossPower) at every row, and no
    passive element dissipates negative power at any row (the MSL examples never dip)."""
    model = st.Model.load(path)
    audit = model.simulate().audit()
    assert audit.ok(), str(audit)
    assert len(audit.elements) >= 2  # EddyCurrentBrake: a brake and an inertia
    dips = [e.component for e in audit.elements if e.passive and e.min_dissipation < -audit.allowed(e)]
    assert dips == []
    storing_nothing = ("Brake", "Clutch", "OneWayClutch", "BearingFriction", "LossyGear", "Damper")
    for e in audit.elements:  # what enters an element that stores nothing is dissipated
        if model.components[e.component].type in storing_nothing:
            assert e.energy_in == pytest.approx(e.dissipated, rel=1e-6, abs=1e-9 * audit.scale)


def test_the_audit_names_an_element_whose_balance_does_not_close() -> None:
    """The audit can fail: a balance off by 1 mW in a 1 W model, or a passive element that
    delivers net energy, is reported with its name."""
    from stiction.results.audit import ElementBalance, EnergyAudit

    good = ElementBalance("J1", 1e-15, 1.0, 1.0, True, 0.0, 0.5, 0.0)
    off = ElementBalance("spring", 1e-3, 1.0, 1.0, True, 0.0, 0.1, 0.0)
    delivering = ElementBalance("clutch", 1e-15, 1.0, 1.0, True, -1e-3, -0.2, -0.2)
    assert EnergyAudit([good]).ok()
    assert not EnergyAudit([good, off]).ok() and EnergyAudit([good, off]).worst == off
    assert EnergyAudit([good, delivering]).delivering() == [delivering]
    assert "clutch delivered" in str(EnergyAudit([good, delivering]))
    assert "spring is off by" in str(EnergyAudit([good, off]))


def test_the_summary_names_the_element_that_fails_not_the_largest_residual() -> None:
    """Issue 29: the summary said "worst brake, 3.19e-08 W" (the largest residual, within its
    bound) while the clutch delivered energy; it names the clutch first."""
    from stiction.results.audit import ElementBalance, EnergyAudit

    brake = ElementBalance("brake", 3.19e-8, 1e3, 10.0, True, 0.0, 5.0, 5.0)
    clutch = ElementBalance("clutch", 1e-12, 1e3, 10.0, True, -50.0, -22.6e6, -22.6e6)
    summary = str(EnergyAudit([brake, clutch], span=10.0))
    assert summary.splitlines()[0] == "energy audit DOES NOT CLOSE: clutch fails"
    assert "clutch delivered 2.26e+07 J" in summary and "brake" not in summary
    assert str(EnergyAudit([brake], span=10.0)).startswith("energy audit closes: largest residual brake")


def test_a_withheld_power_is_judged_against_the_torque_times_the_slip_bound() -> None:
    """A one-way clutch's withheld power (tau·w_rel while MSL's lossPower is 0) closes while
    its slip is within ``slip_bound`` and is reported beyond it."""
    from stiction.results.audit import ElementBalance, EnergyAudit

    def one_way(withheld: float) -> ElementBalance:
        return ElementBalance("c4", 1e-15, 1.0, 10.0, True, 0.0, 0.5, 0.5, withheld, slip_bound=1e-6)

    assert EnergyAudit([one_way(0.9e-5)]).ok()
    assert not EnergyAudit([one_way(2e-5)]).ok()
    assert "c4 is off by 2e-05 W" in str(EnergyAudit([one_way(2e-5)]))


def test_a_stop_hitting_mass_counts_its_resets_in_its_own_dissipated() -> None:
    """MSL's translational HeatLosses: the MassWithStopAndFriction hits its stop twice, and
    each `reinit` takes its kinetic energy in an instant. The element's `dissipated` is its
    friction loss plus those resets (`reset_loss`, the kinetic energy jump over each event's
    two rows), and its energy balance over the run closes to the trapezoid rule's error on
    the 1 ms grid only with them counted."""
    r = st.Model.load(ALL_EXAMPLES / "msl-translational" / "HeatLosses.toml").simulate()
    mass = next(e for e in r.audit().elements if e.component == "massWithStopAndFriction")
    hits = [e.time for e in r.events if e.component == mass.component and "hard stop" in e.cause]
    assert len(hits) == 2
    t, v = r.time, r["massWithStopAndFriction.v"]
    jumps = [
        0.5 * (v[i] ** 2 - v[i + 1] ** 2) for i in range(len(t) - 1) if t[i] == t[i + 1] and t[i] in hits
    ]
    assert len(jumps) == 2 and min(jumps) > 0.1
    assert mass.reset_loss == pytest.approx(sum(jumps), rel=1e-12)
    friction = np.trapezoid(r["massWithStopAndFriction.lossPower"], t)
    assert mass.dissipated == pytest.approx(friction + mass.reset_loss, rel=1e-12)
    gained = 0.5 * (v[-1] ** 2 - v[0] ** 2)  # m = 1
    closes = mass.energy_in - mass.dissipated - gained
    assert abs(closes) < 1e-4 * mass.energy_in
    assert abs(closes + mass.reset_loss) > 0.4 * mass.energy_in  # not without the resets
    # no other element resets
    assert all(
        e.reset_loss == 0.0 for e in r.audit().elements if e is not mass and e.component != mass.component
    )
