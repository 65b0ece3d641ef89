"""A drivetrain cut into two FMUs at a flange, as MSL's ``Rotational.Examples.GenerationOfFMUs``.

The uncut model: a sine torque drives an inertia that a brake grips from 0.3 s on, and a
spring-damper ties the inertia to ground. Cut at the inertia's flange_b:
- the *inertia FMU* (torque in, phi/w/a out): the drive, the inertia and the brake, with a
  TorqueToAngleAdaptor on the cut flange whose ``tau`` is an FMU input;
- the *spring FMU* (phi/w in, torque out): an AngleToTorqueAdaptor (use_a = false) on the
  spring-damper, ``phi`` and ``w`` FMU inputs and ``tau`` an output.
A fixed-step master written with FMPy's FMU2Slave API exchanges the values at every
communication point (Gauss–Seidel: the spring FMU gets the inertia's phi and w at t, the
inertia FMU the spring's torque at t, both step). The torque is held constant over each step,
so the coupling error is first order in the step h: the inertia's speed agrees with the uncut
model simulated in stiction to within K·h (K = 65 rad/s² here, about 16× the speed's range per
second of step: 1.6 % of the range at h = 1 ms), and halving h halves the error.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
from fmpy.validation import validate_fmu
from fmu_slave import Slave

import stiction as st

STOP = 1.0
STEPS = (1e-3, 5e-4, 2.5e-4)
K_BOUND = 65.0  # rad/s²: max |J.w − uncut| ≤ K_BOUND·h


def drive(m: st.Model) -> st.Model:
    """The inertia side: a sine torque on J, a brake gripping it from 0.3 s on."""
    m.add("sine", st.Sine(amplitude=40.0, f=2.0))
    m.add("src", st.Torque())
    m.add("J", st.Inertia(J=0.1, phi=0.0, w=0.0))
    m.add("brake", st.Brake(mu_pos=[[0.0, 0.5]], fn_max=20.0, cgeo=1.0))
    m.add("press", st.Step(height=1.0, startTime=0.3))
    m.connect("sine.y", "src.tau")
    m.connect("src.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


def spring(m: st.Model, flange: str) -> st.Model:
    """The spring side: a spring-damper from `flange` to ground."""
    m.add("sd", st.SpringDamper(c=400.0, d=2.0))
    m.add("ground", st.Fixed())
    m.connect(flange, "sd.flange_a")
    m.connect("sd.flange_b", "ground.flange")
    return m


def uncut() -> st.Model:
    return spring(drive(st.Model("Uncut")), "brake.flange_b")


def inertia_fmu(path: Path) -> Path:
    m = drive(st.Model("InertiaWithBrake"))
    m.add("cut", st.TorqueToAngleAdaptor())
    m.connect("brake.flange_b", "cut.flange")
    m.input("cut.tau", start=0.0)
    return m.to_fmu(path, outputs=["cut.phi", "cut.w", "cut.a", "J.w"])


def spring_fmu(path: Path) -> Path:
    m = st.Model("SpringDamper")
    m.add("cut", st.AngleToTorqueAdaptor(use_a=False))
    spring(m, "cut.flange")
    m.input("cut.phi", start=0.0)
    m.input("cut.w", start=0.0)
    return m.to_fmu(path, outputs=["cut.tau"])


def co_simulate(inertia: Path, springs: Path, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The master: J.w at every communication point."""
    a, b = Slave(inertia, "inertia", STOP), Slave(springs, "spring", STOP)
    n = round(STOP / h)
    times, speeds = np.zeros(n + 1), np.zeros(n + 1)
    try:
        for k in range(n + 1):
            t = k * h
            phi, w, jw = a.get("cut.phi", "cut.w", "J.w")
            times[k], speeds[k] = t, jw
            if k == n:
                break
            b.set({"cut.phi": phi, "cut.w": w})
            (tau,) = b.get("cut.tau")
            a.set({"cut.tau": tau})
            a.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            b.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
    finally:
        a.close()
        b.close()
    return times, speeds


def test_a_cut_drivetrain_agrees_with_the_whole_to_the_coupling_error(tmp_path: Path) -> None:
    inertia = inertia_fmu(tmp_path / "InertiaWithBrake.fmu")
    springs = spring_fmu(tmp_path / "SpringDamper.fmu")
    for fmu in (inertia, springs):
        assert validate_fmu(str(fmu)) == []
    ref = uncut().simulate(StopTime=STOP, Interval=1e-4, Tolerance=1e-10)
    assert any(e.component == "brake" for e in ref.events)  # the brake switches in the run
    errors = []
    for h in STEPS:
        t, w = co_simulate(inertia, springs, h)
        errors.append(float(np.max(np.abs(w - np.interp(t, ref.time, ref["J.w"])))))
    print("coupling error max|J.w - uncut| per step:", dict(zip(STEPS, errors, strict=True)))
    # first order: each halving of h halves the error
    for coarse, fine in itertools.pairwise(errors):
        assert 1.8 < coarse / fine < 2.2
    # the bound: error ≤ K·h with K = 65 rad/s² for this drivetrain (measured 62.6, 61.4, 60.8:
    # the torque held over a step lags the spring's by about h/2·dτ/dt, and the spring's
    # 63 rad/s natural frequency carries that into the speed)
    assert all(e <= K_BOUND * h for e, h in zip(errors, STEPS, strict=True))
