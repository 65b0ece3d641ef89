"""A translational train cut into two FMUs at a flange with MSL's General adaptors
(``Translational.Components.GeneralForceToPositionAdaptor`` and
``GeneralPositionToForceAdaptor``), as ``test_fmu_cut`` does for the rotational ones.

The uncut model: a sine force drives a mass that a brake grips from 0.3 s on, and a
spring-damper ties the mass to ground. Cut at the brake's flange_b: the *mass FMU* (force
``cut.f`` in; ``cut.p``, ``cut.pder``, ``cut.pder2`` out) and the *spring FMU* (``cut.p``,
``cut.pder`` in with use_pder2 = false; ``cut.f`` out). A Gauss–Seidel master holds the force
over each communication step, so the mass's speed agrees with the uncut model to first order
in the step: the error halves with the step, and stays below K·h.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
from fmpy.validation import validate_fmu
from fmu_slave import Slave

import stiction as st

tr = st.translational
STOP = 1.0
STEPS = (1e-3, 5e-4, 2.5e-4)
K_BOUND = 65.0  # m/s²: max |mass.v − uncut| ≤ K_BOUND·h (62.6 measured at h = 1 ms: the same
# numbers as the rotational cut, whose equations these are)


def drive(m: st.Model) -> st.Model:
    """The mass side: a sine force on a mass, a brake gripping it from 0.3 s on."""
    m.add("sine", st.Sine(amplitude=40.0, f=2.0))
    m.add("src", tr.Force())
    m.add("mass", tr.Mass(m=0.1, s=0.0, v=0.0))
    m.add("brake", tr.Brake(mu_pos=[[0.0, 0.5]], fn_max=20.0))
    m.add("press", st.Step(height=1.0, startTime=0.3))
    m.connect("sine.y", "src.f")
    m.connect("src.flange", "mass.flange_a")
    m.connect("mass.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


def spring(m: st.Model, flange: str) -> st.Model:
    m.add("sd", tr.SpringDamper(c=400.0, d=2.0))
    m.add("ground", tr.Fixed())
    m.connect(flange, "sd.flange_a")
    m.connect("sd.flange_b", "ground.flange")
    return m


def mass_fmu(path: Path) -> Path:
    m = drive(st.Model("MassWithBrake"))
    m.add("cut", tr.GeneralForceToPositionAdaptor())
    m.connect("brake.flange_b", "cut.flange")
    m.input("cut.f", start=0.0)
    return m.to_fmu(path, outputs=["cut.p", "cut.pder", "cut.pder2", "mass.v"])


def spring_fmu(path: Path) -> Path:
    m = st.Model("TranslationalSpringDamper")
    m.add("cut", tr.GeneralPositionToForceAdaptor(use_pder2=False))
    spring(m, "cut.flange")
    m.input("cut.p", start=0.0)
    m.input("cut.pder", start=0.0)
    return m.to_fmu(path, outputs=["cut.f"])


def co_simulate(masses: Path, springs: Path, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The master: mass.v at every communication point."""
    a, b = Slave(masses, "mass", STOP), Slave(springs, "spring", STOP)
    n = round(STOP / h)
    times, speeds = np.zeros(n + 1), np.zeros(n + 1)
    try:
        for k in range(n + 1):
            t = k * h
            p, pder, v = a.get("cut.p", "cut.pder", "mass.v")
            times[k], speeds[k] = t, v
            if k == n:
                break
            b.set({"cut.p": p, "cut.pder": pder})
            (f,) = b.get("cut.f")
            a.set({"cut.f": f})
            a.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            b.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
    finally:
        a.close()
        b.close()
    return times, speeds


def test_a_cut_translational_train_agrees_with_the_whole_to_the_coupling_error(tmp_path: Path) -> None:
    masses = mass_fmu(tmp_path / "MassWithBrake.fmu")
    springs = spring_fmu(tmp_path / "TranslationalSpringDamper.fmu")
    for fmu in (masses, springs):
        assert validate_fmu(str(fmu)) == []
    ref = spring(drive(st.Model("Uncut")), "brake.flange_b").simulate(
        StopTime=STOP, Interval=1e-4, Tolerance=1e-10
    )
    assert any(e.component == "brake" for e in ref.events)
    errors = []
    for h in STEPS:
        t, v = co_simulate(masses, springs, h)
        errors.append(float(np.max(np.abs(v - np.interp(t, ref.time, ref["mass.v"])))))
    for h, e in zip(STEPS, errors):
        assert e <= K_BOUND * h, (h, e, errors)
    # first order: halving the step halves the error
    for coarse, fine in itertools.pairwise(errors):
        assert 1.5 < coarse / fine < 2.6, errors
