"""Property-based tests over random drivetrains (Hypothesis): trees of up to 15 inertias (about
30 elements) joined by clutches, one-way clutches, springs, spring-dampers, elastic backlash,
dampers, ideal and lossy gears, with brakes, bearing friction, a torque source and random
normal-force profiles. For every drawn model, either the run ends or it fails with a typed
``StictionError`` — never another exception — and a finished run: closes its energy audit
(the system's, and every element's, with no passive element delivering net energy), is
bit-identical when run again, keeps every locked element's relative speed inside its relation
band and its torque inside its static limit, lies in the tube of a tight-tolerance run, and —
with nothing acting from outside — conserves angular momentum.

CI runs a fixed budget (about 200 examples in all); ``make soak`` runs 10⁴ (``STICTION_SOAK``)."""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, note, settings
from hypothesis import strategies as hs
from paths import DATA

import stiction as st
from stiction.results.comparison import compare

EXAMPLES = int(os.environ.get("STICTION_SOAK", "100"))
AUDIT = ("system.kineticEnergy", "system.potentialEnergy", "system.dissipatedEnergy", "system.sourceWork")

FREE_COUPLINGS = (
    "Clutch",
    "OneWayClutch",
    "SpringDamper",
    "Spring",
    "ElastoBacklash",
    "ElastoBacklash2",
    "Damper",
)
COUPLINGS = (*FREE_COUPLINGS, "IdealGear", "LossyGear", "Gearbox")


def _force(draw: Any) -> tuple[str, dict[str, float]]:
    """A normalized force profile in [0, 1]: a step on or off, or a slow sine."""
    if draw(hs.booleans()):
        on = draw(hs.booleans())
        return "Step", {
            "height": 1.0 if on else -1.0,
            "offset": 0.0 if on else 1.0,
            "startTime": draw(hs.floats(0.0, 1.0)),
        }
    return "Sine", {"amplitude": 0.5, "offset": 0.5, "f": draw(hs.floats(0.2, 5.0))}


@hs.composite
def drivetrains(draw: Any, free: bool = False) -> st.Model:
    """A tree of inertias: each new one hangs on an earlier one through a coupling, with
    bearing friction, brakes and a driving torque. ``free``: no brakes, bearings, gears or
    drive, so nothing outside acts and the angular momentum Σ J·w is conserved."""
    n = draw(hs.integers(2, 15 if not free else 10))
    m = st.Model("random")
    speeds = [draw(hs.floats(-20.0, 20.0))]  # each inertia's start speed as initialization gives it
    m.add("J0", st.Inertia(J=draw(hs.floats(0.05, 5.0)), phi=0.0, w=speeds[0]))
    kinds = FREE_COUPLINGS if free else COUPLINGS
    for i in range(1, n):
        parent = draw(hs.integers(max(0, i - 3), i - 1))  # mostly chains, some branches
        kind = draw(hs.sampled_from(kinds))
        name, coupling = f"c{i}", _coupling(draw, kind)
        geared = kind in ("IdealGear", "LossyGear")
        if kind == "OneWayClutch":
            w = speeds[parent] + draw(hs.floats(0.0, 10.0))  # a freewheel never starts backward
        elif geared:
            w = speeds[parent] / coupling.params["ratio"]
        else:
            w = draw(hs.floats(-20.0, 20.0))
        speeds.append(w)
        free_start = {"start": w, "fixed": False}  # a gear fixes the speed it passes on
        j = draw(hs.floats(0.05, 5.0))
        m.add(
            f"J{i}", st.Inertia(J=j, phi={"start": 0.0, "fixed": not geared}, w=free_start if geared else w)
        )
        m.add(name, coupling)
        m.connect(f"J{parent}.flange_b", f"{name}.flange_a")
        m.connect(f"{name}.flange_b", f"J{i}.flange_a")
        if kind in ("Clutch", "OneWayClutch"):
            block, params = _force(draw)
            m.add(f"f{i}", getattr(st, block)(**params))
            m.connect(f"f{i}.y", f"{name}.f_normalized")
    if not free:
        _add_outside_torques(draw, m, n)
    m.experiment.update(StopTime=1.0, Interval=1e-3)
    return m


def _add_outside_torques(draw: Any, m: st.Model, n: int) -> None:
    """Up to two brakes, a bearing friction and a sine torque on drawn inertias."""
    for k in draw(hs.sets(hs.integers(0, n - 1), max_size=2)):
        m.add(f"brake{k}", st.Brake(fn_max=draw(hs.floats(1.0, 200.0)), peak=draw(hs.floats(1.0, 1.5))))
        m.connect(f"J{k}.flange_a", f"brake{k}.flange_a")
        if draw(hs.booleans()):  # pressed in proportion to the measured speed squared
            m.add(f"speed{k}", st.SpeedSensor())
            m.add(f"square{k}", st.Product())
            m.add(f"press{k}", st.Gain(k=draw(hs.floats(1e-3, 1e-2))))
            m.connect(f"J{k}.flange_b", f"speed{k}.flange")
            m.connect(f"speed{k}.w", f"square{k}.u1")
            m.connect(f"speed{k}.w", f"square{k}.u2")
            m.connect(f"square{k}.y", f"press{k}.u")
        else:
            block, params = _force(draw)
            m.add(f"press{k}", getattr(st, block)(**params))
        m.connect(f"press{k}.y", f"brake{k}.f_normalized")
    if draw(hs.booleans()):
        k = draw(hs.integers(0, n - 1))
        tau0 = draw(hs.floats(0.1, 5.0))
        m.add(
            "bearing",
            st.BearingFriction(tau_pos=[[0.0, tau0], [10.0, 2 * tau0]], peak=draw(hs.floats(1.0, 1.5))),
        )
        m.connect(f"J{k}.flange_b", "bearing.flange_a")
    m.add("drive", st.Torque())
    m.add("torque", st.Sine(amplitude=draw(hs.floats(0.0, 50.0)), f=draw(hs.floats(0.1, 10.0))))
    m.connect("torque.y", "drive.tau")
    driven = f"J{draw(hs.integers(0, n - 1))}.flange_a"
    if draw(hs.booleans()):  # measured on its way in: the sensor carries the drive's torque
        m.add("meter", st.MultiSensor())
        m.connect("drive.flange", "meter.flange_a")
        m.connect("meter.flange_b", driven)
    else:
        m.connect("drive.flange", driven)


def _coupling(draw: Any, kind: str) -> st.Component:
    friction = {"fn_max": draw(hs.floats(1.0, 100.0)), "peak": draw(hs.floats(1.0, 1.5))}
    if kind == "Clutch":
        return st.Clutch(**friction)
    if kind == "OneWayClutch":
        return st.OneWayClutch(**friction)
    if kind == "SpringDamper":
        return st.SpringDamper(c=draw(hs.floats(10.0, 1e4)), d=draw(hs.floats(0.1, 10.0)))
    if kind == "Spring":
        return st.Spring(c=draw(hs.floats(10.0, 1e4)))
    if kind in ("ElastoBacklash", "ElastoBacklash2"):
        backlash = st.ElastoBacklash if kind == "ElastoBacklash" else st.ElastoBacklash2
        return backlash(c=draw(hs.floats(1e2, 1e4)), d=draw(hs.floats(0.0, 5.0)), b=draw(hs.floats(0.0, 0.2)))
    if kind == "Damper":
        return st.Damper(d=draw(hs.floats(0.1, 10.0)))
    ratio = draw(hs.sampled_from([-3.0, -0.5, 0.5, 2.0, 4.0]))
    if kind == "IdealGear":
        return st.IdealGear(ratio=ratio)
    eta = draw(hs.floats(0.5, 1.0))
    if kind == "Gearbox":  # LossyGear + ElastoBacklash through a shaft without inertia
        elastic = {
            "c": draw(hs.floats(1e2, 1e4)),
            "d": draw(hs.floats(0.0, 5.0)),
            "b": draw(hs.floats(0.0, 0.2)),
        }
        return st.Gearbox(ratio=ratio, lossTable=[[0.0, eta, eta, 0.0, 0.0]], **elastic)
    return st.LossyGear(ratio=ratio, lossTable=[[0.0, eta, eta, 0.0, 0.0]])


def _beyond_static_limit(model: st.Model, r: st.Result) -> list[str]:
    """The clutches and brakes that hold more than their static friction while locked."""
    scale = max(1.0, *(float(np.abs(r[n]).max()) for n in AUDIT))
    found = []
    for name in (n for n, c in model.components.items() if c.type in ("Clutch", "Brake")):
        locked = r[f"{name}.locked"] == 1.0
        excess = np.abs(r[f"{name}.tau"][locked]) - r[f"{name}.tau0_max"][locked]
        if excess.size and excess.max() > 1e-6 * scale:
            found.append(name)
    return found


# CI's budget replays a fixed sequence of examples (no flakiness) and reports a failure as
# found (shrinking one takes minutes); a soak explores at random and shrinks what it finds.
CI = EXAMPLES <= 200
BUDGET = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=CI,
    database=None if CI else settings.default.database,
    phases=[Phase.explicit, Phase.generate] if CI else list(Phase),
    suppress_health_check=[HealthCheck.too_slow],
)
FEWER = settings(BUDGET, max_examples=max(1, EXAMPLES // 3))


def _run(model: st.Model) -> st.Result | None:
    """The run, or None when it failed with a typed error naming what failed (acceptable)."""
    note(model.to_toml())
    try:
        return model.simulate()
    except st.StictionError:
        return None


def _energy_drift(r: st.Result) -> float:
    """How far kinetic + potential + dissipated energy − source work strays, of its scale."""
    total = r[AUDIT[0]] + r[AUDIT[1]] + r[AUDIT[2]] - r[AUDIT[3]]
    scale = max(1.0, *(float(np.abs(r[n]).max()) for n in AUDIT))
    return float(np.abs(total - total[0]).max()) / scale


def _assert_energy_closes(model: st.Model, r: st.Result) -> None:
    """The energies balance to 3e-4 of their scale, or, beyond, converge with the tolerance.

    They drift with the integrator's error: `make soak` found four clutches and a 100 rad/s
    spring off by 1.0e-4 at Tolerance 1e-6 (2.2e-7 at 1e-8), and a 32 Hz spring beside a
    clutch that sticks and slips 102 times in 1 s off by 3.0e-4 (tests/data/fast_spring_drift.toml).
    An error of the engine's (energy made at an event) would not shrink a hundredfold at 1e-8;
    the element audit, asserted besides, finds a passive element that delivers energy."""
    drift = _energy_drift(r)
    if drift < 3e-4:
        return
    tighter = _energy_drift(model.simulate(Tolerance=1e-8))
    assert tighter <= drift / 100, f"energy audit off by {drift:.2e}, {tighter:.2e} at 1e-8"


@pytest.mark.slow
@BUDGET
@given(drivetrains())
def test_random_drivetrains_keep_their_invariants(model: st.Model) -> None:
    r = _run(model)
    if r is None:
        return
    _assert_energy_closes(model, r)
    audit = r.audit()  # element by element: every balance closes, no passive element delivers
    assert audit.ok(), str(audit)
    again = model.simulate()
    np.testing.assert_array_equal(r.data, again.data)
    if "meter" in model.components:  # the cut torque is the drive's, the power its work rate
        tau = -r["drive.flange.tau"]
        np.testing.assert_allclose(r["meter.tau"], tau, rtol=1e-9, atol=1e-9 * max(1.0, np.abs(tau).max()))
        np.testing.assert_allclose(r["meter.power"], r["meter.tau"] * r["meter.w"], rtol=1e-12, atol=1e-12)
    for k in (c[len("speed") :] for c in model.components if c.startswith("speed")):
        np.testing.assert_array_equal(r[f"speed{k}.w"], r[f"J{k}.w"])


@FEWER
@given(drivetrains(free=True))
def test_angular_momentum_is_conserved_when_nothing_outside_acts(model: st.Model) -> None:
    """Clutches, springs, backlash and dampers only pass torque between inertias: Σ J·w is a
    linear invariant, which Runge–Kutta steps and the event iteration keep to round-off."""
    r = _run(model)
    if r is None:
        return
    inertias = [(n, float(c.params["J"])) for n, c in model.components.items() if c.type == "Inertia"]
    momentum = sum(j * r[f"{n}.w"] for n, j in inertias)
    scale = max(1e-3, max(float(np.abs(j * r[f"{n}.w"]).max()) for n, j in inertias))
    drift = float(np.abs(momentum - momentum[0]).max())
    assert drift <= 1e-9 * scale, f"Σ J·w drifts by {drift:.2e} (scale {scale:.3g})"


@FEWER
@given(drivetrains())
def test_a_stuck_element_keeps_its_relative_speed_inside_the_relation_band(model: st.Model) -> None:
    """While a clutch, brake or bearing is locked its relative speed stays where it locked:
    inside the ±1e-10 band its relations switch at, scaled by the gears between them — or,
    where a start with almost no acceleration lasted long enough for the integrator's error
    to move that speed (tests/data/touching_zero_band.toml: 3.2e-7 rad/s at the default
    Tolerance), within that error (Tolerance times the largest speed) and inside the band at
    Tolerance 1e-7."""
    r = _run(model)
    if r is None:
        return
    slips = _locked_slips(model, r)
    beyond = {name: slip for name, slip in slips.items() if slip > 1e-9}
    if not beyond:
        return
    scale = _largest_speed(model, r)
    assert max(beyond.values()) <= 1e-6 * scale, f"locked slips {beyond} beyond the tolerance's reach"
    tighter = _locked_slips(model, model.simulate(Tolerance=1e-7))
    assert all(tighter[name] <= 1e-9 for name in beyond), f"locked slips {beyond}, at 1e-7 {tighter}"


def _locked_slips(model: st.Model, r: st.Result) -> dict[str, float]:
    """The largest relative speed of each clutch, brake or bearing while locked. The band is the
    relations' ±1e-10 rad/s; through a gear's ratio (up to 4 drawn here) an element's own speed
    sits at that band times the ratio (2e-10 behind a 0.5 gear), so 1e-9 is inside it."""
    slips = {}
    for name, comp in model.components.items():
        speed = {"Clutch": "w_rel", "Brake": "w", "BearingFriction": "w"}.get(comp.type)
        if speed is not None:
            locked = r[f"{name}.locked"] == 1.0
            slips[name] = float(np.abs(r[f"{name}.{speed}"][locked]).max(initial=0.0))
    return slips


@FEWER
@given(drivetrains())
def test_a_tight_tolerance_lies_in_the_tube_of_the_default_one(model: st.Model) -> None:
    """The same model at Tolerance 1e-9 stays inside the MSL tube (2e-3) around the default
    run, or — where the default tolerance's global error itself leaves the tube — the run
    converges to it: at Tolerance 1e-8 the same mode changes as at 1e-9, and a tenth of the
    default's error. The default run may decide a near-tie the other way
    (tests/data/near_tie_breakaway.toml); that its own decisions are right to its own
    trajectory is what the invariants above assert.

    Not asked of a drivetrain with an ElastoBacklash: its bouncing can be chaotic (four shafts
    on springs and an undamped backlash, tests/data/chaotic_backlash.toml, are 91 % of a
    speed's range off at 1e-6 and still off at 1e-8), and no fixed tolerance holds such a run
    in a tube, in any tool. The backlash regression tests below show what does hold.

    Nor of a drivetrain at rest to the tolerance's reach (every speed of the 1e-9 run below
    1e-4 rad/s, a hundred times the default absolute tolerance): its motion is the
    integrator's noise, which the explicit method amplifies near rest to about 150 times that
    tolerance (architecture.md, "A stiff oscillation near rest"), and so are the breakaways it
    drives where a normal force falls to zero (tests/data/noise_at_rest.toml)."""
    if any(c.type == "ElastoBacklash" for c in model.components.values()):
        return
    r = _run(model)
    if r is None:
        return
    tight = model.simulate(Tolerance=1e-9)
    if _largest_speed(model, tight) < 1e-4 or not _outside_tube(model, tight, r):
        return
    # About 1 drivetrain in 2000: an oscillation the default tolerance barely resolves
    # (tests/data/coarse_oscillation.toml, 0.22 % of the range off): a wrong stick/slip
    # decision would change the mode changes or keep its error at a tighter tolerance.
    _assert_converges(model, r, tight)


def _assert_converges(model: st.Model, r: st.Result, tight: st.Result) -> None:
    """At Tolerance 1e-8 the mode changes of the tight run, and a tenth of the error of r."""
    closer = model.simulate(Tolerance=1e-8)
    assert _changes(closer) == _changes(tight)
    assert _distance(model, tight, closer) <= _distance(model, tight, r) / 10


def _distance(model: st.Model, tight: st.Result, r: st.Result) -> float:
    """The largest difference of a speed from the tight run's, over the output grid."""
    speeds = [f"{n}.w" for n, c in model.components.items() if c.type == "Inertia"]
    return max(float(np.abs(r[s] - np.interp(r.time, tight.time, tight[s])).max()) for s in speeds)


def _changes(r: st.Result) -> list[tuple[str, int, int]]:
    """The mode changes in order (a backlash's contacts are no mode changes: a grazing one
    may be seen at one tolerance and not at another)."""
    return [(e.component, e.old_mode, e.new_mode) for e in r.events]


def _largest_speed(model: st.Model, r: st.Result) -> float:
    return max(float(np.abs(r[f"{n}.w"]).max()) for n, c in model.components.items() if c.type == "Inertia")


def _outside_tube(model: st.Model, tight: st.Result, r: st.Result) -> list[str]:
    """The speeds of ``r`` outside the tube of ``tight`` (the run at Tolerance 1e-9).

    The tube's height is 2e-3 of each speed's own range as in MSL, but at least 2e-3 of the
    drivetrain's largest speed: the integrator's error is relative to the speeds (Tolerance
    1e-6 of |w|, and 1e-6 rad/s absolute, as Modelica tools set it), so a shaft creeping at a
    few mrad/s beside others turning 10x faster (``tests/data/tiny_speeds.toml``), or a small
    oscillation riding on 1 rad/s, is right to that, not to 0.2 % of its own range. And never
    below ten times the default run's absolute tolerance (1e-6 rad/s): a stiff oscillation near
    rest, below what the error test sees, grows under the explicit method toward that
    tolerance (architecture.md, "A stiff oscillation near rest";
    ``tests/data/speeds_below_tolerance.toml``); beyond it the error must converge."""
    speeds = [f"{n}.w" for n, c in model.components.items() if c.type == "Inertia"]
    scale = _largest_speed(model, tight)
    report = compare(tight, r, tolerance=2e-3, signals=speeds, floor=max(2e-3 * scale, 1e-5))
    return report.failed


@BUDGET
@given(drivetrains())
def test_locked_clutches_and_brakes_hold_no_more_than_their_static_friction(model: st.Model) -> None:
    r = _run(model)
    assert r is None or not _beyond_static_limit(model, r)


def test_a_static_limit_crossed_and_recovered_between_samples_at_the_stop_time_is_found():
    """Found by `make soak` (1 in about 1500 drivetrains): a locked brake whose static limit
    falls below its torque between the last two samples of the final step, while both
    samples stay below. The indicators' rates at the samples (backward differences on the
    dense output) show the rise and fall, and the peak between them is searched."""

    model = st.Model.loads((DATA / "hump_at_stop.toml").read_text())
    r = model.simulate()
    locked = r["brake0.locked"] == 1.0
    excess = (np.abs(r["brake0.tau"]) - r["brake0.tau0_max"])[locked].max()
    assert excess <= 1e-6, f"held {excess:.3f} N·m beyond the static limit"


def test_shafts_creeping_at_a_few_mrad_per_s_are_right_to_the_absolute_tolerance():
    """Found by `make soak` (1 in about 1000 drivetrains): ten clutches on a tree, all at rest,
    a 1 N·m sine on one shaft; most shafts creep at 2-3 mrad/s. At the default Tolerance the
    run made the tight run's 50 mode changes in the same order, and its speeds were off by
    up to 7e-6 rad/s (7x the absolute tolerance, after 50 events): outside 0.2 % of a creeping
    shaft's own range, inside 0.2 % of the drivetrain's. Since steps are at most a quarter of
    the drive's period, the default run lies in each shaft's own tube too."""

    model = st.Model.load(DATA / "tiny_speeds.toml")
    r, tight = model.simulate(), model.simulate(Tolerance=1e-9)
    assert _changes(r) == _changes(tight)
    assert not _outside_tube(model, tight, r)
    speeds = [f"J{k}.w" for k in range(14)]
    assert compare(tight, model.simulate(Tolerance=1e-7), signals=speeds).passed


@pytest.mark.parametrize("case", ["bouncing_backlash", "chaotic_backlash", "damped_backlash"])
def test_a_backlash_amplifies_the_integration_error_that_a_tighter_tolerance_removes(case: str) -> None:
    """Found by `make soak` (about 1 in 1000 drivetrains): shafts bouncing in an ElastoBacklash.
    Undamped, each contact's timing error grows in the next: two bodies (21 contacts in 1 s)
    are 0.8 % of the range off at the default Tolerance, four shafts on springs are chaotic,
    91 % off. Damped (d = 1, 2 contacts), the switches inside a contact were 1.2 % off at 1e-6
    and 0.2 % at 1e-8 while they were stepped over as MSL's noEvent does; located as events,
    0.07 % at 1e-6. Each makes the same mode changes and converges: over two decades of
    Tolerance at least 25-fold (the chaotic one not decade by decade: 34 % off at 1e-6, 23 % at
    1e-7, 0.4 % at 1e-8)."""

    model = st.Model.load(DATA / f"{case}.toml")
    r, tight = model.simulate(), model.simulate(Tolerance=1e-9)
    assert _changes(r) == _changes(tight)
    errors = [_distance(model, tight, model.simulate(Tolerance=tol)) for tol in (1e-6, 1e-7, 1e-8)]
    assert errors[0] > 25 * errors[2] and errors[1] > errors[2], errors
    if case == "damped_backlash":
        assert errors[0] > 5 * errors[1] > 25 * errors[2], errors
    else:
        assert _outside_tube(model, tight, r)  # beyond any tube at the default Tolerance


def test_an_oscillation_the_default_tolerance_barely_resolves_converges_with_the_tolerance() -> None:
    """Found by `make soak` (1 in about 2000 drivetrains): two inertias on a stiff spring
    (105 rad/s), driven by a sine, no friction. Tsit45 at the default Tolerance 1e-6 takes 74
    steps for 17 periods and is 0.19 % of the largest speed off, at the MSL tube's edge (76
    steps and 0.22 %, outside it, before the step-size controller's gain changed), and the
    error falls about tenfold per decade of Tolerance, as the method's order says."""

    model = st.Model.load(DATA / "coarse_oscillation.toml")
    r, tight = model.simulate(), model.simulate(Tolerance=1e-9)
    scale = max(float(np.abs(tight[f"J{k}.w"]).max()) for k in range(2))
    assert r.stats["events"] == 0
    errors = [_distance(model, tight, model.simulate(Tolerance=tol)) for tol in (1e-6, 1e-7, 1e-8)]
    assert errors[0] > 1e-3 * scale, (errors[0], scale)
    assert errors[0] > 5 * errors[1] > 25 * errors[2], errors


def test_a_stiff_oscillation_near_rest_grows_under_the_explicit_method_to_its_tolerance() -> None:
    """Found by `make soak` (three times in 10 000 drivetrains): two shafts on a spring started
    at 1e-9 rad/s. Below the absolute tolerance (1e-6 rad/s at the default Tolerance) the error
    test does not see the motion, so the explicit method steps beyond its stability bound and
    amplifies it until its error estimate reaches that tolerance: a known limit of Tsit45 under
    an absolute tolerance (architecture.md, "A stiff oscillation near rest"). What holds: the
    error stays within a few hundred times the absolute tolerance and shrinks with it, and the
    implicit methods keep the motion where it is."""

    text = (DATA / "speeds_below_tolerance.toml").read_text()
    stiff = st.Model.loads(text.replace("J = 2.0", "J = 0.5").replace("c = 181.0", "c = 20000.0"))
    tight = stiff.simulate(Tolerance=1e-12)
    errors = {tol: _distance(stiff, tight, stiff.simulate(Tolerance=tol)) for tol in (1e-6, 1e-8)}
    assert 1e-5 < errors[1e-6] <= 5e-4 and errors[1e-8] <= errors[1e-6] / 50, errors
    r = stiff.simulate()
    assert _outside_tube(stiff, tight, r)
    _assert_converges(stiff, r, stiff.simulate(Tolerance=1e-9))
    # the drivetrain as the soak found it: 9e-8 rad/s off, inside the tube's floor
    gentle = st.Model.loads(text)
    assert not _outside_tube(gentle, gentle.simulate(Tolerance=1e-9), gentle.simulate())
    for solver in ("esdirk34", "bdf"):
        assert _distance(stiff, tight, stiff.simulate(Solver=solver)) <= 5e-9, solver


def test_a_drivetrain_at_rest_to_round_off_stays_at_rest_at_every_tolerance() -> None:
    """Found by `make soak` (2 in 10 000 drivetrains): shafts started at 1e-103 rad/s, no drive,
    two clutches whose normal forces fall to zero at 0.75 s. A clutch used to start sliding
    backward at the initialization on the sign of that 1e-103 (the relation `w < 0` was
    compared literally there), and the stiff spring-damper between them then rang on
    round-off, amplified near rest by the explicit method (1e-5 rad/s at the default
    Tolerance), so the later breakaways followed the noise and differed from tolerance to
    tolerance. A relation now starts true only beyond the event band, as it would become true
    later (`switching/relation.rs`): both clutches start stuck, nothing rings, and every
    tolerance gives the same modes, with the shafts at rest to round-off."""

    model = st.Model.load(DATA / "noise_at_rest.toml")
    runs = {tol: model.simulate(Tolerance=tol) for tol in (1e-6, 1e-8, 1e-9)}
    assert {tuple(_changes(r)) for r in runs.values()} == {(("c1", 3, 0), ("c6", 3, 0))}
    for tol, r in runs.items():
        assert _largest_speed(model, r) <= 1e-90, (tol, _largest_speed(model, r))
        assert r.audit().ok(), str(r.audit())


def test_energy_that_drifts_with_the_integration_error_converges_with_the_tolerance() -> None:
    """Found by `make soak` (3 in its first 110 drivetrains): a 32 Hz spring beside a clutch that
    sticks and slips 102 times in 1 s; the energies drift by 1.4e-4 of their scale at the
    default Tolerance (3.0e-4 before the step-size controller's gain changed), more than
    tenfold less per decade of Tolerance, and every element's balance closes."""

    model = st.Model.load(DATA / "fast_spring_drift.toml")
    r = model.simulate()
    drifts = [_energy_drift(model.simulate(Tolerance=tol)) for tol in (1e-6, 1e-7, 1e-8)]
    assert drifts[0] >= 1e-4 and drifts[0] > 10 * drifts[1] > 100 * drifts[2], drifts
    _assert_energy_closes(model, r)
    assert r.audit().ok(), str(r.audit())


def test_a_near_tie_the_default_tolerance_does_not_resolve_converges_with_the_tolerance() -> None:
    """Found by `make soak` (1 in about 10 000 drivetrains): brake2 holds its shaft while its
    static limit falls; at the default Tolerance the torque it holds comes within 4e-5 of the
    limit and it stays locked, at 1e-7 and tighter it breaks away at 0.8709 s. The held torque's
    own error at the default Tolerance (2.4e-3 N·m at 0.870 s, from the spring and the lossy
    gear beside it) exceeds that margin (2.1e-3 N·m at 0.871 s): the default run decides the
    tie the other way, within its tolerance, as any tool would. It is outside the tube, and
    converges."""

    model = st.Model.load(DATA / "near_tie_breakaway.toml")
    r, tight = model.simulate(), model.simulate(Tolerance=1e-9)
    assert _changes(r) != _changes(tight) and _outside_tube(model, tight, r)
    held, limit = np.abs(r["brake2.tau"]), r["brake2.tau0_max"]
    window = (r.time > 0.86) & (r.time < 0.872)
    margin = float((limit - held)[window].min())
    before = (r.time > 0.86) & (r.time < 0.8708)  # the tight run breaks away at 0.8709 s
    error = float(np.abs(held - np.abs(np.interp(r.time, tight.time, tight["brake2.tau"])))[before].max())
    assert 0 < margin < min(error, 1e-4 * float(limit[window].min())), (margin, error)
    _assert_converges(model, r, tight)


def test_a_locked_brake_breaks_away_when_a_fast_drive_exceeds_its_limit_between_long_steps() -> None:
    """Found by `make soak` (1 in about 3000 drivetrains): a brake holds an inertia against a
    5 Hz drive torque while its pressing force falls (a 1 Hz sine). Locked, the states do not
    move, so the integrator's steps grew past the drive's period (54 steps for 1 s), and the
    drive exceeded the static limit at 0.530 s and fell back 55 ms later between two samples
    of the crossing scan: the brake held 0.33 N·m beyond its limit. Steps are now at most a
    quarter of the signals' shortest period, and the brake breaks away where the torque it
    holds first reaches its limit."""

    model = st.Model.load(DATA / "missed_breakaway.toml")
    r = model.simulate()
    assert not _beyond_static_limit(model, r)
    # where |drive| first reaches tau0_max on the output grid, interpolated linearly
    gap = np.abs(r["torque.y"]) - r["brake0.tau0_max"]
    k = int(np.argmax(gap > 0))
    reached = r.time[k - 1] - gap[k - 1] * (r.time[k] - r.time[k - 1]) / (gap[k] - gap[k - 1])
    first = next(e for e in r.events if e.component == "brake0" and e.time > 0)
    assert first.new_mode == -1 and first.time == pytest.approx(reached, abs=1e-5), (first, reached)


def _assert_no_start_against_its_motion(r: st.Result, name: str) -> None:
    """A start is never held while the element turns the other way beyond the relation band."""
    w = r[f"{name}.w"]
    assert w[r[f"{name}.startBackward"] == 1.0].max(initial=0.0) <= 2e-10
    assert w[r[f"{name}.startForward"] == 1.0].min(initial=0.0) >= -2e-10


def test_a_brake_whose_normal_force_touches_zero_re_engages_without_delivering_energy() -> None:
    """Found by `make soak` (1 in about 3000 drivetrains): brake4's pressing force (a 2 Hz sine
    from 0 to 1) touches zero at 0.375 s and 0.875 s. Each time the brake re-engages starting
    backward with almost no friction, its slip passes the relation band and turns back within a
    few milliseconds of a 31 ms scan interval while the samples at both ends show no sign
    change. It used to lock at three bands from zero (the start's end was located, the slip
    that crossed before it was not) and, the second time, to hold the start while the shaft
    turned forward, delivering 3.2e-5 J. Now the slip's hump is found from the cubic through
    the samples' values and rates, and a crossing located in an interval is checked for an
    indicator that crossed before it: the brake slides backward and stops inside the band, no
    start outlives its direction, and the audit closes."""

    model = st.Model.load(DATA / "touching_zero_press.toml")
    r = model.simulate()
    locked = r["brake4.locked"] == 1.0
    assert np.abs(r["brake4.w"][locked]).max() <= 2e-10
    assert r.audit().ok(), str(r.audit())
    _assert_no_start_against_its_motion(r, "brake4")
    slides = [e.time for e in r.events if e.component == "brake4" and e.new_mode == -1]
    assert slides and 0 < slides[0] - 0.375 < 1e-3, slides


def test_a_start_held_only_by_the_static_limit_ends_when_its_torque_comes_back_inside() -> None:
    """Found by `make soak` (1 in about 3000 drivetrains), after the fix above: brake12 starts
    backward at 0.6875 s (its pressing force, a 4 Hz sine, near zero) with its shaft at
    +1e-10 rad/s, so the start is held by `sa < -tau0_max` alone (turning forward, the
    hysteresis of `sa < -tau0` no longer holds it). Only the relations of the hysteresis were
    watched for the start's end: it went on while the shaft turned forward to 1.2e-3 rad/s,
    then locked there, and the brake delivered 1.7e-5 J. Every relation that holds a start is
    now watched: it ends 2.6 µs later and the brake locks inside the band."""

    model = st.Model.load(DATA / "touching_zero_press2.toml")
    r = model.simulate()
    locked = r["brake12.locked"] == 1.0
    assert np.abs(r["brake12.w"][locked]).max() <= 2e-10
    _assert_no_start_against_its_motion(r, "brake12")
    assert r.audit().ok(), str(r.audit())


def test_a_one_way_clutch_that_starts_forward_never_turns_backward_while_starting() -> None:
    """Found by `make soak` (2 in 10 000 drivetrains): c3, an engaged one-way clutch locked
    while holding backward torque, started forward at 0.3031 s, yet released its relative
    acceleration was -48.7 rad/s²: it turned backward to -0.46 rad/s with the start held, its
    friction pushing along the motion (12.6 W delivered). At that instant c5 stops sliding: with
    c5 locked c3's torque passes its limit, with c3 locked c5's does, and with both starting both
    turn back, so the mixed system updated as a whole cycles; its last fallback (the union of
    the cycling relations, meant for redundant locks) started both. Updated one element at a
    time the event settles with c3 starting and c5 holding."""

    model = st.Model.load(DATA / "one_way_start_backward.toml")
    r = model.simulate()
    starting = r["c3.startForward"] == 1.0
    assert r["c3.w_rel"][starting].min(initial=0.0) >= -2e-10
    assert r.audit().ok(), str(r.audit())


def test_a_start_through_a_normal_force_touching_zero_locks_within_the_integration_error() -> None:
    """Found by `make soak` (1 in 10 000 drivetrains): c4, locked at the band's edge
    (+1e-10 rad/s), starts backward at 0.87401 s as its static limit falls with its normal
    force, which touches zero at 0.875 s. For 2 ms its relative acceleration is a few 1e-4
    rad/s² while its shafts turn at 0.5-0.7 rad/s, so the integrator's error (Tolerance 1e-6 of
    those speeds) moves its relative speed more than the acceleration does: it drifts forward to
    3.2e-7 rad/s and the clutch locks there when its acceleration reaches zero. At Tolerance
    1e-7 and tighter it locks inside the band; the audit closes."""

    model = st.Model.load(DATA / "touching_zero_band.toml")
    r = model.simulate()
    assert r.audit().ok(), str(r.audit())
    slip = _locked_slips(model, r)["c4"]
    assert 1e-9 < slip <= 1e-6 * _largest_speed(model, r), slip
    for tol in (1e-7, 1e-9):
        assert _locked_slips(model, model.simulate(Tolerance=tol))["c4"] <= 1e-9, tol


def test_a_one_way_clutch_starting_with_almost_no_acceleration_withholds_only_the_integrators_error() -> None:
    """Found by `make soak`: c4, an engaged one-way clutch, starts forward at 0.73795 s with
    almost no acceleration; its relative speed drifts backward to -1.9e-6 rad/s while starting
    (the integrator's error on speeds of 27 rad/s), where MSL's lossPower is 0 (stuck:
    w_rel <= 0), so 5.6e-5 W of tau·w_rel is neither loss nor stored. The audit keeps that
    power apart (`withheld`) and bounds it by the torque times the integrator's error on the
    relative speed: it closes, the rest of c4's balance closes to round-off, and the withheld
    power shrinks with the tolerance (at 1e-7 it is within round-off)."""

    model = st.Model.load(DATA / "one_way_start_drift.toml")
    audits = {tol: model.simulate(Tolerance=tol).audit() for tol in (1e-6, 1e-7)}
    for audit in audits.values():
        assert audit.ok(), str(audit)
    c4 = {tol: next(e for e in a.elements if e.component == "c4") for tol, a in audits.items()}
    assert c4[1e-6].residual <= audits[1e-6].allowed(c4[1e-6])
    assert c4[1e-6].withheld > audits[1e-6].allowed(c4[1e-6])  # beyond round-off: the drift
    assert c4[1e-7].withheld <= audits[1e-7].allowed(c4[1e-7])
    assert c4[1e-7].slip_bound < c4[1e-6].slip_bound / 5


def test_a_cycle_of_four_at_a_breakaway_tie_starts_both_clutches() -> None:
    """Found by `make soak` (1 in 10 000 drivetrains): at 0.3998 s the one-way clutch c8
    reaches its static limit. With c8 starting, the locked c11's torque passes its own limit;
    with both starting, c8's falls back below its limit; with c8 locked again c11 turns back:
    the mixed system cycles through four sets. Its last fallback took the union of the last
    two only and kept c11 locked at -0.989 N·m against 0.794 (for 2.6e-10 s); the union of the
    whole cycle starts both, as the Coulomb law has it (each slips the way it accelerates)."""

    model = st.Model.load(DATA / "breakaway_tie_cycle.toml")
    r = model.simulate()
    assert not _beyond_static_limit(model, r)
    starts = [e for e in r.events if 0.3997 < e.time < 0.3999 and e.new_mode != 0]
    assert {e.component for e in starts} == {"c8", "c11"}, starts
    assert r.audit().ok(), str(r.audit())


def test_a_brake_starting_backward_that_a_lossy_gear_turns_forward_stops_starting_there():
    """Found by the properties (1 in about 500 drivetrains): brake6 starts backward while the
    lossy gear beside it drives its shaft forward. MSL's start, held by its hysteresis, would
    go on with the friction driving the motion and then lock at the slip gained (creeping).
    The start ends where the speed leaves the relation band; the brake then breaks away
    forward, and every locked element stays inside the band and its static limit.

    The corner is a near-tie that a change in the arithmetic moves: the ElastoBacklash's
    located switches took this drivetrain off it, and c5.d = 1.6657937541474963 (found by
    scanning it, 2.776 before) brought it back; the next bit of d did not. The small modes'
    inverse and Tsit45's dense output from its stages (issue 10, fourth round) moved it again:
    c5.d = 2.925695544488903, found by scanning; the gentler step-size controller to
    2.9256955444888972 (a few bits away); relations that start false at the initialization
    unless beyond the event band (c4 and c7 no longer start sliding on round-off) to 1.12,
    found by scanning 1 to 4 in steps of 0.01. When this test stops finding the corner, scan
    c5.d again rather than loosen what it asserts."""

    model = st.Model.loads((DATA / "start_turns_back.toml").read_text())
    r = model.simulate()
    ends = [e for e in r.events if e.component == "brake6" and "turned the other way" in e.cause]
    assert ends and (ends[0].old_mode, ends[0].new_mode) == (0, 1), r.events
    speed_there = r["brake6.w"][np.searchsorted(r.time, ends[0].time)]
    assert 0.0 < speed_there <= 2e-10, speed_there
    for name in ("brake3", "brake6", "c2", "c4"):
        locked = r[f"{name}.locked"] == 1.0
        speed = r[f"{name}.w" if name.startswith("brake") else f"{name}.w_rel"]
        assert np.abs(speed[locked]).max(initial=0.0) <= 2e-10, name
    assert not _beyond_static_limit(model, r)
    assert r.audit().ok(), str(r.audit())
