"""Property-based tests over mixed rotational–translational drivetrains (issue 31): a chain of
inertias (the couplings, brakes, bearing friction and drive of test_properties.py) that ends in
a wheel — MSL's ``IdealRollingWheel`` or stiction's ``SlipWheel``, rolling or skidding at the
start — driving a vehicle mass (``Translational.Mass``), sometimes with a translational
``Brake`` or ``SupportFriction`` on it, a trailer on a spring-damper, rolling resistance and a
speed-dependent drag. The invariants are those of the rotational drivetrains, in both domains:
the energy audit closes (the system's and every element's: ½·J·w², ½·m·v², the work of forces
and torques, the friction losses), a run is bit-identical when repeated, every stuck element
(clutch, brake, tyre contact) holds no more than its static friction and keeps its relative
speed inside the relation band, and a tight tolerance lies in the tube of the default one.

CI runs a third of test_properties.py's budget here (the full one and the tube under ``slow``);
``make soak`` (``STICTION_SOAK``) runs them all at its count."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs
from test_properties import (
    BUDGET,
    COUPLINGS,
    FEWER,
    _add_outside_torques,
    _assert_energy_closes,
    _coupling,
    _force,
    _run,
)

import stiction as st
from stiction.results.comparison import compare

tr = st.translational
G = 9.81
# the friction elements, their force or torque, static limit and relative speed while locked
FRICTION = {
    "Clutch": ("tau", "tau0_max", "w_rel"),
    "Brake": ("tau", "tau0_max", "w"),
    "BearingFriction": ("tau", "tau0_max", "w"),
    "Translational.Brake": ("f", "f0_max", "v"),
    "Translational.SupportFriction": ("f", "f0_max", "v"),
    "SlipWheel": ("f", "f0_max", "v_slip"),
}


@hs.composite
def mixed_drivetrains(draw: Any) -> st.Model:
    """Inertias J0..J(n-1) in a chain (mostly) ending in a wheel on the car's mass."""
    n = draw(hs.integers(1, 5))
    m = st.Model("mixed")
    speeds = [draw(hs.floats(-30.0, 30.0))]
    m.add("J0", st.Inertia(J=draw(hs.floats(0.05, 2.0)), phi=0.0, w=speeds[0]))
    for i in range(1, n):
        parent = draw(hs.integers(max(0, i - 2), i - 1))
        kind = draw(hs.sampled_from(COUPLINGS))
        coupling = _coupling(draw, kind)
        geared = kind in ("IdealGear", "LossyGear")
        if kind == "OneWayClutch":
            w = speeds[parent] + draw(hs.floats(0.0, 10.0))
        elif geared:
            w = speeds[parent] / coupling.params["ratio"]
        else:
            w = draw(hs.floats(-30.0, 30.0))
        speeds.append(w)
        free = {"start": w, "fixed": False}
        phi = {"start": 0.0, "fixed": not geared}
        m.add(f"J{i}", st.Inertia(J=draw(hs.floats(0.05, 2.0)), phi=phi, w=free if geared else w))
        m.add(f"c{i}", coupling)
        m.connect(f"J{parent}.flange_b", f"c{i}.flange_a")
        m.connect(f"c{i}.flange_b", f"J{i}.flange_a")
        if kind in ("Clutch", "OneWayClutch"):
            block, params = _force(draw)
            m.add(f"f{i}", getattr(st, block)(**params))
            m.connect(f"f{i}.y", f"c{i}.f_normalized")
    mass = draw(hs.floats(20.0, 500.0))
    _add_wheel_and_car(draw, m, speeds[n - 1], f"J{n - 1}.flange_b", mass)
    _add_road_loads(draw, m, mass)
    _add_outside_torques(draw, m, n)
    m.experiment.update(StopTime=1.0, Interval=1e-3)
    return m


def _add_wheel_and_car(draw: Any, m: st.Model, w: float, hub: str, mass: float) -> None:
    """The wheel on the last inertia and the car: an ideal wheel fixes the car's speed (its
    start is free), a slip wheel's contact starts rolling or skidding."""
    radius = draw(hs.floats(0.1, 0.5))
    if draw(hs.booleans()):
        m.add("wheel", st.IdealRollingWheel(radius=radius))
        car = tr.Mass(m=mass, s={"start": 0.0, "fixed": False}, v={"start": radius * w, "fixed": False})
    else:
        mu = draw(hs.floats(0.2, 1.0))
        m.add(
            "wheel",
            st.SlipWheel(
                radius=radius,
                mu_pos=[[0.0, mu], [10.0, draw(hs.floats(0.5, 1.0)) * mu]],
                extrapolation="HoldLastPoint",
                peak=draw(hs.floats(1.0, 1.3)),
                fNConstant=mass * G,
            ),
        )
        skidding = draw(hs.booleans())  # else rolling: the contact starts stuck
        slip = draw(hs.floats(-5.0, 5.0).filter(lambda x: abs(x) > 1e-3)) if skidding else 0.0
        car = tr.Mass(m=mass, s=0.0, v=radius * w + slip)
    m.add("car", car)
    m.connect(hub, "wheel.flangeR")
    m.connect("wheel.flangeT", "car.flange_a")


def _add_road_loads(draw: Any, m: st.Model, mass: float) -> None:
    """Any of: a translational brake or support friction on the car, a trailer on a
    spring-damper, rolling resistance, a drag growing with the speed."""
    if draw(hs.booleans()):
        m.add(
            "tbrake",
            tr.Brake(
                fn_max=draw(hs.floats(10.0, 3000.0)), mu_pos=[[0.0, 0.5]], peak=draw(hs.floats(1.0, 1.5))
            ),
        )
        block, params = _force(draw)
        m.add("tpress", getattr(st, block)(**params))
        m.connect("tpress.y", "tbrake.f_normalized")
        m.connect("car.flange_b", "tbrake.flange_a")
    if draw(hs.booleans()):
        f0 = draw(hs.floats(1.0, 200.0))
        m.add(
            "support", tr.SupportFriction(f_pos=[[0.0, f0], [10.0, 1.5 * f0]], peak=draw(hs.floats(1.0, 1.5)))
        )
        m.connect("car.flange_b", "support.flange_a")
    if draw(hs.booleans()):
        m.add("hitch", tr.SpringDamper(c=draw(hs.floats(1e2, 1e5)), d=draw(hs.floats(1.0, 500.0))))
        trailer_v = {"start": 0.0, "fixed": False}  # starts beside the car, at its speed
        m.add("trailer", tr.Mass(m=draw(hs.floats(10.0, 300.0)), s=0.0, v=trailer_v))
        m.connect("car.flange_b", "hitch.flange_a")
        m.connect("hitch.flange_b", "trailer.flange_a")
        m.add("tie", tr.RelSpeedSensor())  # (its output unread: a sensor on the joint)
        m.connect("car.flange_b", "tie.flange_a")
        m.connect("trailer.flange_a", "tie.flange_b")
    if draw(hs.booleans()):
        m.add("rolling", tr.RollingResistance(fWeight=mass * G, CrConstant=draw(hs.floats(0.005, 0.05))))
        m.connect("car.flange_b", "rolling.flange")
    if draw(hs.booleans()):
        drag = tr.QuadraticSpeedDependentForce(
            f_nominal=-draw(hs.floats(1.0, 100.0)), v_nominal=20.0, ForceDirection=False
        )
        m.add("drag", drag)
        m.connect("car.flange_b", "drag.flange")


def _speeds(model: st.Model) -> list[str]:
    """Every inertia's w and every mass's v."""
    kinds = {"Inertia": "w", "Translational.Mass": "v"}
    return [f"{n}.{kinds[c.type]}" for n, c in model.components.items() if c.type in kinds]


def _beyond_static_limit(model: st.Model, r: st.Result) -> list[str]:
    """The friction elements (both domains, the tyre contact among them) that hold more than
    their static friction while locked, past round-off of the energy scale."""
    audit = ("system.kineticEnergy", "system.potentialEnergy", "system.dissipatedEnergy", "system.sourceWork")
    scale = max(1.0, *(float(np.abs(r[n]).max()) for n in audit))
    found = []
    for name, comp in model.components.items():
        if comp.type not in FRICTION or comp.type == "BearingFriction":
            continue
        force, limit, _ = FRICTION[comp.type]
        locked = r[f"{name}.locked"] == 1.0
        excess = np.abs(r[f"{name}.{force}"][locked]) - r[f"{name}.{limit}"][locked]
        if excess.size and excess.max() > 1e-6 * scale:
            found.append(name)
    return found


def _locked_slips(model: st.Model, r: st.Result) -> dict[str, float]:
    slips = {}
    for name, comp in model.components.items():
        if comp.type in FRICTION:
            locked = r[f"{name}.locked"] == 1.0
            slips[name] = float(np.abs(r[f"{name}.{FRICTION[comp.type][2]}"][locked]).max(initial=0.0))
    return slips


def _largest_speed(model: st.Model, r: st.Result) -> float:
    return max(float(np.abs(r[s]).max()) for s in _speeds(model))


def _assert_invariants(model: st.Model) -> None:
    r = _run(model)
    if r is None:
        return
    _assert_energy_closes(model, r)
    audit = r.audit()  # element by element, both domains: no passive element delivers energy
    assert audit.ok(), str(audit)
    np.testing.assert_array_equal(r.data, model.simulate().data)
    assert not _beyond_static_limit(model, r)
    beyond = {name: slip for name, slip in _locked_slips(model, r).items() if slip > 1e-9}
    if beyond:  # within the integrator's reach, and inside the band at a tighter tolerance
        assert max(beyond.values()) <= 1e-6 * _largest_speed(model, r), f"locked slips {beyond}"
        tighter = _locked_slips(model, model.simulate(Tolerance=1e-7))
        assert all(tighter[name] <= 1e-9 for name in beyond), f"locked slips {beyond}, at 1e-7 {tighter}"
    if "wheel" in model.components and model.components["wheel"].type == "IdealRollingWheel":
        radius = model.components["wheel"].params["radius"]
        hub = model.connections[[b for _, b in model.connections].index("wheel.flangeR")][0].split(".")[0]
        np.testing.assert_allclose(r["car.v"], radius * r[f"{hub}.w"], rtol=1e-9, atol=1e-9)


MIXED = settings(FEWER)  # a third of the rotational budget in CI


@MIXED
@given(mixed_drivetrains())
def test_mixed_drivetrains_keep_their_invariants(model: st.Model) -> None:
    _assert_invariants(model)


@pytest.mark.slow
@BUDGET
@given(mixed_drivetrains())
def test_mixed_drivetrains_keep_their_invariants_at_the_full_budget(model: st.Model) -> None:
    _assert_invariants(model)


@pytest.mark.slow
@FEWER
@given(mixed_drivetrains())
def test_a_tight_tolerance_lies_in_the_tube_of_the_default_one_in_both_domains(model: st.Model) -> None:
    """As for the rotational drivetrains (test_properties.py): the run at Tolerance 1e-9 in
    the 2e-3 tube around the default run's speeds, inertias' and masses' alike (the floor
    2e-3 of the largest speed, at least 1e-5), or the default run converging to it."""
    if any(c.type == "ElastoBacklash" for c in model.components.values()):
        return  # chaotic bouncing: see test_properties.py
    r = _run(model)
    if r is None:
        return
    tight = model.simulate(Tolerance=1e-9)
    scale = _largest_speed(model, tight)
    if scale < 1e-4:
        return
    report = compare(tight, r, tolerance=2e-3, signals=_speeds(model), floor=max(2e-3 * scale, 1e-5))
    if not report.failed:
        return
    closer = model.simulate(Tolerance=1e-8)
    changes = lambda x: [(e.component, e.old_mode, e.new_mode) for e in x.events]

    def distance(x: st.Result) -> float:
        return max(
            float(np.abs(x[s] - np.interp(x.time, tight.time, tight[s])).max()) for s in _speeds(model)
        )

    assert changes(closer) == changes(tight)
    assert distance(closer) <= distance(r) / 10
