"""A saved state is bytes, the core's one format (issue 28): ``SimulationState`` pickles as
them, a run restored from a pickle goes on bit for bit, and an FMU serializes the same bytes
(FMPy, an independent FMI host, reads them from the FMU)."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st


@pytest.fixture(scope="module")
def model() -> st.Model:
    return st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")


def test_a_pickled_state_goes_on_bit_for_bit(model: st.Model) -> None:
    sim = model.simulation()
    sim.advance_to(0.7)
    state = pickle.loads(pickle.dumps(sim.state()))
    assert isinstance(state, st.SimulationState) and state.time == pytest.approx(0.7)
    sim.run()
    straight = sim.result()
    again = model.simulation()
    again.set_state(state)
    again.run()
    restored = again.result()
    after = restored.time > 0.7  # the restored run records from the saved instant on
    assert after.sum() > 1000
    same = np.searchsorted(straight.time, restored.time[after][0])
    for name in ("J1.w", "J3.phi", "clutch2.mode"):
        assert np.array_equal(restored[name][after], straight[name][same : same + after.sum()]), name


def test_the_bytes_round_trip_and_bad_bytes_are_refused(model: st.Model) -> None:
    sim = model.simulation()
    sim.advance_to(0.3)
    data = sim.state().to_bytes()
    assert st.SimulationState.from_bytes(data).to_bytes() == data
    with pytest.raises(st.UsageError):
        st.SimulationState.from_bytes(data[:-3])


def test_an_fmu_serializes_the_same_bytes(model: st.Model, tmp_path: Path) -> None:
    fmpy = pytest.importorskip("fmpy")
    from fmpy.fmi2 import FMU2Slave

    path = model.to_fmu(tmp_path / "cc.fmu", outputs=["J1.w"])
    described = fmpy.read_model_description(str(path))
    unzipped = fmpy.extract(str(path))
    fmu = FMU2Slave(
        guid=described.guid,
        unzipDirectory=unzipped,
        modelIdentifier=described.coSimulation.modelIdentifier,
        instanceName="cc",
    )
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0, stopTime=1.5)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    t = 0.0
    while t < 0.3 - 1e-12:
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=0.1)
        t += 0.1
    serialized = bytes(fmu.serializeFMUState(fmu.getFMUState()))
    fmu.terminate()
    fmu.freeInstance()

    sim = model.simulation(StopTime=1.5)
    for stop in (0.1, 0.2, 0.30000000000000004):  # the host's communication points, as it sums them
        sim.advance_to(stop)
    ours = sim.state().to_bytes()
    body = ours[12:-8]  # between the core's magic and version and its checksum
    assert len(body) > 100 and body in serialized
