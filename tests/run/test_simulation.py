"""The resumable Simulation from Python, model inputs, the exception hierarchy, format versions."""

from __future__ import annotations

import threading
from pathlib import Path

import numpy as np
import pytest
from paths import REPO

import stiction as st

ROOT = REPO
COUPLED = ROOT / "examples" / "msl" / "CoupledClutches.toml"
FLYWHEEL = ROOT / "examples" / "braked_flywheel.toml"


def flywheel_with_input() -> st.Model:
    """The braked flywheel with its press ramp removed and the brake force a model input."""
    m = st.Model.load(FLYWHEEL)
    del m.components["press"]
    m.connections = [c for c in m.connections if "press.y" not in c]
    m.input("brake.f_normalized", start=0.0)
    return m


def test_pieces_give_the_result_of_one_call_bit_for_bit() -> None:
    model = st.Model.load(COUPLED)
    whole = model.simulate()
    sim = model.simulation()
    for t in np.arange(0.0137, 1.5, 0.0137):
        sim.advance_to(float(t))
        assert sim.time == pytest.approx(float(t), abs=0.0)
    sim.run()
    assert sim.finished
    pieces = sim.result()
    assert pieces.names == whole.names
    for name in ("time", "J1.w", "J4.phi", "clutch2.mode", "clutch1.tau"):
        np.testing.assert_array_equal(pieces[name], whole[name])
    assert [e.time for e in pieces.events] == [e.time for e in whole.events]


def test_an_input_acts_from_the_instant_it_is_set() -> None:
    model = flywheel_with_input()
    sim = model.simulation(StopTime=3.0)
    assert sim.inputs == {"brake.f_normalized": 0.0}
    sim.advance_to(0.5)
    assert sim["flywheel.w"] == pytest.approx(100.0, abs=1e-9)
    sim.set_input("brake.f_normalized", 1.0)
    assert sim.values()["brake.f_normalized"] == 1.0
    sim.run()
    r = sim.result()
    engaged = [e for e in r.events if e.component == "brake" and e.time == 0.5]
    assert engaged, r.events
    # the flywheel then decelerates at the brake's sliding torque: mu(w)·cgeo·fn_max / J
    w = r["flywheel.w"]
    t = r.time
    k = int(np.searchsorted(t, 0.6))
    slope = (w[k + 1] - w[k - 1]) / (t[k + 1] - t[k - 1])
    mu = float(np.interp(w[k], [0.0, 50.0, 100.0], [0.42, 0.38, 0.35]))
    assert slope == pytest.approx(-mu * 0.1 * 2000.0 / 2.0, rel=1e-4)


def test_inputs_survive_the_model_file(tmp_path: Path) -> None:
    model = flywheel_with_input()
    model.inputs["brake.f_normalized"] = 0.25
    path = tmp_path / "m.toml"
    model.save(path)
    text = path.read_text()
    assert text.startswith("format = 1\n")
    assert "inputs" in text
    again = st.Model.load(path)
    assert again == model
    assert again.simulation().inputs == {"brake.f_normalized": 0.25}


def test_a_newer_model_file_format_is_refused_by_name() -> None:
    text = "format = 2\n" + COUPLED.read_text()
    with pytest.raises(st.ModelError, match="format 2 is newer"):
        st.Model.loads(text)


def test_saved_state_and_reset() -> None:
    sim = st.Model.load(COUPLED).simulation()
    sim.advance_to(0.6)
    state = sim.state()
    assert state.time == 0.6
    before = sim.values()
    sim.advance_to(1.0)
    sim.set_state(state)
    assert sim.time == 0.6
    assert sim.values() == before
    sim.reset()
    assert sim.time == 0.0


def test_cancel_from_another_thread_raises_simulation_cancelled() -> None:
    sim = st.Model.load(COUPLED).simulation()
    handle = sim.cancel_handle()
    thread = threading.Thread(target=handle.cancel)
    thread.start()
    thread.join()
    with pytest.raises(st.SimulationCancelled) as info:
        sim.run()
    assert isinstance(info.value, st.SimulationError)


def test_misuse_raises_usage_error_naming_the_problem() -> None:
    sim = st.Model.load(COUPLED).simulation()
    sim.advance_to(0.5)
    with pytest.raises(st.UsageError, match="not before the current time"):
        sim.advance_to(0.1)
    with pytest.raises(st.UsageError, match="not an input of the model"):
        sim.set_input("clutch1.f_normalized", 1.0)
    with pytest.raises(st.UsageError, match="unknown variable"):
        sim.get("J9.w")
    sim.result()
    with pytest.raises(st.UsageError, match="closed"):
        sim.advance_to(1.0)


def test_the_exception_hierarchy_is_public_and_catchable_by_name() -> None:
    kinds = [
        st.ModelError,
        st.UsageError,
        st.SimulationError,
        st.SingularSystemError,
        st.EventIterationError,
        st.ChatteringError,
        st.StepLimitError,
        st.NonFiniteStateError,
        st.IntegratorError,
        st.SimulationCancelled,
    ]
    for kind in kinds:
        assert issubclass(kind, st.StictionError)
        assert kind.__module__ == "stiction"
        assert kind.__name__ in st.__all__
    assert issubclass(st.ModelError, ValueError)
    assert issubclass(st.SingularSystemError, RuntimeError)


def test_a_singular_mode_is_a_singular_system_error() -> None:
    # two shafts without inertia joined by a clutch: nothing determines their accelerations
    # (each held by a spring only; a flange connected to nothing is refused before, by name)
    m = st.Model("massless")
    m.add("clutch", st.Clutch(fn_max=10.0))
    m.add("force", st.Constant(k=1.0))
    m.add("spring", st.Spring(c=1.0))
    m.add("spring2", st.Spring(c=1.0))
    m.add("fixed", st.Fixed())
    m.connect("force.y", "clutch.f_normalized")
    m.connect("fixed.flange", "spring.flange_a")
    m.connect("spring.flange_b", "clutch.flange_a")
    m.connect("clutch.flange_b", "spring2.flange_a")
    m.connect("spring2.flange_b", "fixed.flange")
    with pytest.raises(st.SingularSystemError, match="singular system"):
        m.simulate(StopTime=0.1)
