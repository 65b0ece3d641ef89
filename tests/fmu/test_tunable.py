"""Tunable parameters: ``Simulation.set_parameter`` mid-run, and the same through an FMU
(FMI 2.0 and 3.0, driven by FMPy) between two ``doStep`` calls.

A flywheel (J = 2, w = 100) behind a 2:1 gear (load J = 8) is braked with a constant normal force, mu =
0.4, cgeo = 0.1: the closed form gives the instant it stops after the force is raised. The
FMU changing ``brake.fn_max`` at a communication point agrees with the Simulation doing the
same at that time; a fixed parameter (the gear's ratio, a start value) is refused in step mode
with an error status and a message; a state saved after a change restores exactly; the model
descriptions declare the tunable ones and pass FMPy's validation.
"""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu
from test_fmu_state import Runner

import stiction as st
from stiction.errors import ModelError
from stiction.model.catalogue import catalogue

OUTPUTS = ["flywheel.w", "load.w"]


def braked() -> st.Model:
    """Flywheel → gear (2:1) → load, the brake on the load; the force a model input at 1."""
    m = st.Model("geared_brake")
    m.add("flywheel", st.Inertia(J=2.0, phi=0.0, w=100.0))
    m.add("gear", st.IdealGear(ratio=2.0))
    m.add("load", st.Inertia(J=8.0))
    m.add("brake", st.Brake(fn_max=2000.0, mu_pos=[[0.0, 0.4]], peak=1.0, cgeo=0.1))
    m.connect("flywheel.flange_b", "gear.flange_a")
    m.connect("gear.flange_b", "load.flange_a")
    m.connect("load.flange_b", "brake.flange_a")
    m.input("brake.f_normalized", start=1.0)
    m.experiment.update(StartTime=0.0, StopTime=4.0, Interval=0.01, Tolerance=1e-8)
    return m


# the inertia at the flywheel: 2 + 8/ratio² = 4; the brake torque there: mu·cgeo·fn_max/ratio
# = 0.02·fn_max, so 10 rad/s² at fn_max = 2000
def stop_time(t1: float, fn_max: float) -> float:
    """When the flywheel stops with fn_max = 2000 until ``t1``, then ``fn_max``."""
    w1 = 100.0 - 10.0 * t1
    return t1 + w1 / (0.02 * fn_max / 4.0)


def test_the_catalogue_says_which_parameters_are_tunable() -> None:
    cat = catalogue()
    assert cat["Brake"].parameter("fn_max").tunable
    assert cat["Brake"].parameter("mu_pos").tunable
    assert cat["SpringDamper"].parameter("c").tunable
    assert cat["Inertia"].parameter("J").tunable
    assert not cat["IdealGear"].parameter("ratio").tunable
    assert not cat["Step"].parameter("startTime").tunable
    assert not cat["Inertia"].parameter("w").tunable  # a start value
    assert not cat["Brake"].parameter("useHeatPort").tunable


def test_a_raised_brake_force_stops_the_flywheel_when_the_closed_form_says() -> None:
    sim = braked().simulation()
    sim.advance_to(1.5)
    assert sim["flywheel.w"] == pytest.approx(85.0, abs=1e-9)
    sim.set_parameter("brake.fn_max", 10000)  # an int is a number too
    sim.run()
    r = sim.result()
    stops = [e.time for e in r.events if e.component == "brake" and e.new == "stuck"]
    assert stops == [pytest.approx(stop_time(1.5, 10000.0), abs=1e-9)]
    # the normal force is recorded on both sides of the instant, each with its parameters
    time, fn = np.asarray(r["time"]), np.asarray(r["brake.fn"])
    k = int(np.flatnonzero(time == 1.5)[0])
    assert (fn[0], fn[k], fn[k + 1], fn[-1]) == (2000.0, 2000.0, 10000.0, 10000.0)


def test_fixed_parameters_and_bad_values_raise_and_the_run_goes_on() -> None:
    sim = braked().simulation()
    sim.advance_to(1.0)
    with pytest.raises(ModelError, match="'gear'.*'ratio'.*fixed"):
        sim.set_parameter("gear.ratio", 3.0)
    with pytest.raises(ModelError, match="'brake'.*'peak'"):
        sim.set_parameters({"brake.fn_max": 800.0, "brake.peak": 0.5})
    sim.run()
    assert sim["flywheel.w"] == pytest.approx(60.0, abs=1e-9)  # nothing changed


def simulation_values(times: list[float], change_at: float, fn_max: float) -> np.ndarray:
    """The outputs at each time of a Simulation that sets fn_max at ``change_at``."""
    sim = braked().simulation()
    rows, changed = [], False
    for t in times:
        if not changed and t > change_at:
            sim.advance_to(change_at)
            sim.set_parameter("brake.fn_max", fn_max)
            changed = True
        sim.advance_to(t)
        rows.append([sim[n] for n in OUTPUTS])
    return np.array(rows)


@pytest.fixture(params=[2, 3], ids=["fmi2", "fmi3"])
def version(request: pytest.FixtureRequest) -> int:
    return request.param


def test_an_fmu_takes_a_tunable_parameter_between_steps(tmp_path: Path, version: int) -> None:
    fmu = braked().to_fmu(tmp_path / "geared.fmu", fmi_version=version, outputs=OUTPUTS)
    assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(fmu)
    variability = {v.name: v.variability for v in md.modelVariables}
    assert variability["brake.fn_max"] == "tunable"
    assert variability["gear.ratio"] == "fixed"
    r = Runner(fmu, version)
    r.start(4.0)
    h, rows = 0.05, []
    for j in range(80):
        if j == 30:
            r.set("brake.fn_max", 10000.0)
        r.slave.doStep(j * h, h)
        rows.append(r.get(OUTPUTS))
    times = [(j + 1) * h for j in range(80)]
    # the Simulation setting it at the same point, 1.5 s: the same run
    expected = simulation_values(times, 30 * h, 10000.0)
    np.testing.assert_allclose(np.array(rows), expected, rtol=0, atol=1e-12)
    # at rest from the closed form's instant, 3.2 s
    stopped = [t for t, (w, _) in zip(times, rows, strict=True) if abs(w) < 1e-6]
    assert stopped[0] == pytest.approx(3.2, abs=h)
    assert rows[24][0] == pytest.approx(100.0 - 10.0 * 1.25, abs=1e-9)


def test_an_fmu_refuses_a_fixed_parameter_in_step_mode(tmp_path: Path, version: int) -> None:
    fmu = braked().to_fmu(tmp_path / "geared.fmu", fmi_version=version, outputs=OUTPUTS)
    r = Runner(fmu, version)
    r.start(4.0)
    r.slave.doStep(0.0, 0.5)
    with pytest.raises(FMICallException):
        r.set("gear.ratio", 3.0)
    assert "setting parameter gear.ratio is not allowed in state Step" in r.messages[-1]
    assert "fixed" in r.messages[-1]
    with pytest.raises(FMICallException):  # a value out of range: refused, named
        r.set("brake.peak", 0.5)
    assert "peak" in r.messages[-1]
    r.slave.doStep(0.5, 0.5)  # the run goes on unchanged
    assert r.get(["flywheel.w"]) == [pytest.approx(90.0, abs=1e-9)]


def test_a_state_saved_after_a_change_restores_exactly(tmp_path: Path, version: int) -> None:
    fmu = braked().to_fmu(tmp_path / "geared.fmu", fmi_version=version, outputs=OUTPUTS)
    first, second = Runner(fmu, version), Runner(fmu, version)
    first.start(4.0)
    h = 0.05
    first.run(0, 10, h, OUTPUTS, None)
    first.set("brake.fn_max", 6000.0)
    first.run(10, 20, h, OUTPUTS, None)
    state = first.save()
    data = first.serialize(state)
    later = first.run(20, 60, h, OUTPUTS, None)
    # restored in the instance that saved it, and from bytes in a new one
    first.restore(state)
    again = first.run(20, 60, h, OUTPUTS, None)
    second.restore(second.deserialize(data))
    fresh = second.run(20, 60, h, OUTPUTS, None)
    assert np.array_equal(later, again)
    assert np.array_equal(later, fresh)
    # and the restored instance holds the changed value
    assert second.get(["brake.fn_max"]) == [6000.0]


def test_an_fmu_takes_a_friction_table_between_steps_at_one_event(tmp_path: Path, version: int) -> None:
    """A whole table set in step mode (FMI 3.0 one array, FMI 2.0 all its elements in one
    call) is one change at the communication point, as ``Simulation.set_parameters``."""
    model = braked()
    fmu = model.to_fmu(tmp_path / "geared.fmu", fmi_version=version, outputs=OUTPUTS)
    md = fmpy.read_model_description(fmu)
    table = [[0.0, 0.3], [5.0, 0.25], [50.0, 0.2]]  # another shape than the model's 1×2
    r = Runner(fmu, version)
    r.start(4.0)
    r.slave.doStep(0.0, 1.0)
    if version == 3:
        assert {v.name: v.variability for v in md.modelVariables}["brake.mu_pos"] == "tunable"
        with pytest.raises(FMICallException):  # the shape is the FMU's
            r.slave.setFloat64([r.vr["brake.mu_pos"]], [x for row in table for x in row])
        assert "shape is fixed" in r.messages[-1]
        r.slave.setFloat64([r.vr["brake.mu_pos"]], [0.0, 0.2])
    else:
        assert {v.name: v.variability for v in md.modelVariables}["brake.mu_pos[1,2]"] == "tunable"
        r.slave.setReal([r.vr["brake.mu_pos[1,1]"], r.vr["brake.mu_pos[1,2]"]], [0.0, 0.2])
    r.slave.doStep(1.0, 1.0)
    sim = model.simulation()
    sim.advance_to(1.0)
    sim.set_parameters({"brake.mu_pos": [[0.0, 0.2]]})
    sim.advance_to(2.0)
    assert r.get(OUTPUTS) == [sim[n] for n in OUTPUTS]
    # half the friction from 1 s: 90 rad/s, then 5 rad/s² for 1 s
    assert sim["flywheel.w"] == pytest.approx(85.0, abs=1e-9)
