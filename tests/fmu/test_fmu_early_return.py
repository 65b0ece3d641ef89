"""FMI 3.0 early return, checked with FMPy's FMI 3.0 API: a host that allows it gets each
``doStep`` back at the first friction event inside it, with ``lastSuccessfulTime`` there; those
times are the state events of ``stiction simulate``, and the run ends where one that never
returns early ends. A host that does not allow it never gets a step back early. A state saved
right after such an event and restored in a new instance continues bit for bit."""

from __future__ import annotations

from pathlib import Path

import fmpy
import pytest
from fmpy.fmi3 import FMU3Slave
from paths import REPO

import stiction as st

ROOT = REPO
COUPLED = ROOT / "examples" / "msl" / "CoupledClutches.toml"
OUT = ["J1.w", "J2.w", "J3.w", "J4.w"]


def run(fmu: Path, early: bool, h: float = 0.1, stop: float = 1.5) -> tuple[list[float], list[float]]:
    """Steps to ``stop`` on a grid of ``h``; the times of early returns and the final outputs."""
    md = fmpy.read_model_description(fmu)
    vr = [v.valueReference for v in md.modelVariables if v.name in OUT]
    slave = FMU3Slave(
        guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.coSimulation.modelIdentifier
    )
    slave.instantiate(earlyReturnAllowed=early)
    slave.enterInitializationMode(startTime=0.0, stopTime=stop)
    slave.exitInitializationMode()
    returns, t, k = [], 0.0, 1
    while k <= round(stop / h):
        _, _, returned_early, last = slave.doStep(t, k * h - t)
        if returned_early:
            assert t < last < k * h
            returns.append(last)
        else:
            assert last == pytest.approx(k * h, abs=1e-12)
            k += 1
        t = last
    final = slave.getFloat64(vr)
    slave.terminate()
    slave.freeInstance()
    return returns, final


def test_do_step_returns_early_at_each_friction_event(tmp_path: Path) -> None:
    fmu = st.Model.load(COUPLED).to_fmu(tmp_path / "CC.fmu", fmi_version=3, outputs=OUT)
    returns, final = run(fmu, early=True)
    never, final_whole = run(fmu, early=False)
    assert never == []
    ref = st.Model.load(COUPLED).simulate()
    state_events = sorted({e.time for e in ref.events if "time event" not in e.cause and 0.0 < e.time < 1.5})
    assert len(state_events) >= 3
    off_grid = [t for t in state_events if abs(t / 0.1 - round(t / 0.1)) > 1e-9]
    # every mode change off the grid is a return, at its time to the bit (the run is stiction's)
    assert set(off_grid) <= set(returns)
    # and every return is at one: a sticking element first sets its start flag (a friction
    # event without a new mode) a hair before it slides, and returns there too
    assert all(min(abs(t - e) for e in off_grid) < 1e-9 for t in returns)
    # stopping at the events changes nothing: the integrator restarts there either way
    assert final == final_whole


def test_a_state_saved_at_an_early_return_continues_exactly(tmp_path: Path) -> None:
    fmu = st.Model.load(COUPLED).to_fmu(tmp_path / "CC.fmu", fmi_version=3, outputs=OUT)
    _, final_whole = run(fmu, early=False)
    md = fmpy.read_model_description(fmu)
    vr = [v.valueReference for v in md.modelVariables if v.name in OUT]
    args = {"guid": md.guid, "unzipDirectory": fmpy.extract(fmu)}
    args["modelIdentifier"] = md.coSimulation.modelIdentifier
    first, second = FMU3Slave(**args), FMU3Slave(**args)
    first.instantiate(earlyReturnAllowed=True)
    first.enterInitializationMode(startTime=0.0, stopTime=1.5)
    first.exitInitializationMode()
    t, returned_early = 0.0, False
    while not returned_early:  # to the first friction event off the 0.1 s grid
        _, _, returned_early, t_next = first.doStep(t, round(t * 10 + 1) / 10 - t)
        t = t_next
    data = first.serializeFMUState(first.getFMUState())
    second.instantiate()  # no early return here, not initialized: the state carries its setup
    second.setFMUState(second.deserializeFMUState(data))
    k = round(t * 10 + 0.5)
    second.doStep(t, k / 10 - t)
    while k < 15:
        second.doStep(k / 10, 0.1)
        k += 1
    assert second.getFloat64(vr) == final_whole
    for slave in (first, second):
        slave.terminate()
        slave.freeInstance()
