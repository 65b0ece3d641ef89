"""Start values of states as FMU variables (FMI 2.0 and 3.0), checked with FMPy: the state's
variable carries its start with ``initial="exact"`` (fixed) or ``"approx"`` (a guess); a start
value set before initialization gives the run ``stiction simulate`` gives with that start value,
and one set after initialization is refused."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu
from paths import REPO
from test_fmu_state import fmi2_callbacks

import stiction as st

ROOT = REPO
COUPLED = ROOT / "examples" / "msl" / "CoupledClutches.toml"
OUT = ["J1.w", "J2.w", "J4.w", "J1.phi"]


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def clutches(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    model = st.Model.load(COUPLED).set("J3.w", {"start": 0.0, "fixed": False})
    path = tmp_path_factory.mktemp("fmu") / "CC.fmu"
    return model.to_fmu(path, fmi_version=request.param, outputs=OUT)


def test_start_values_are_declared_the_fmi_way(clutches: Path) -> None:
    assert validate_fmu(str(clutches)) == []
    md = fmpy.read_model_description(clutches)
    v = {x.name: x for x in md.modelVariables}
    assert (v["J1.w"].causality, v["J1.w"].initial, float(v["J1.w"].start)) == ("output", "exact", 10.0)
    assert (v["J2.phi"].causality, v["J2.phi"].initial, float(v["J2.phi"].start)) == ("local", "exact", 0.0)
    assert (v["J3.w"].causality, v["J3.w"].initial) == ("local", "approx")  # a guess
    assert v["J1.w"].unit == "rad/s"
    initial_unknowns = {u.variable.name for u in md.initialUnknowns}
    assert "J1.w" not in initial_unknowns  # its start value is exact: known before initialization


def test_a_start_value_set_before_initialization_changes_the_run(clutches: Path) -> None:
    out = fmpy.simulate_fmu(str(clutches), stop_time=1.5, output_interval=0.01, start_values={"J1.w": 14.0})
    ref = st.Model.load(COUPLED).set("J1.w", 14.0).simulate()
    default = st.Model.load(COUPLED).simulate()
    assert out["J1.w"][0] == 14.0
    for name in OUT:
        expected = np.interp(out["time"], ref.time, ref[name])
        scale = float(np.ptp(expected))
        assert np.max(np.abs(out[name] - expected)) <= 1e-6 * scale, name
    # and it is another run than the default one
    assert abs(out["J4.w"][-1] - float(np.interp(1.5, default.time, default["J4.w"]))) > 0.1


def test_a_start_value_is_fixed_after_initialization(tmp_path: Path) -> None:
    fmu = st.Model.load(COUPLED).to_fmu(tmp_path / "CC2.fmu", outputs=OUT)
    md = fmpy.read_model_description(fmu)
    vr = {x.name: x.valueReference for x in md.modelVariables}
    slave = FMU2Slave(
        guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.coSimulation.modelIdentifier
    )
    messages: list[str] = []
    slave.instantiate(callbacks=fmi2_callbacks(messages))
    slave.setReal([vr["J2.phi"]], [0.5])  # before initialization: taken
    slave.setupExperiment(startTime=0.0, stopTime=1.5)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    assert slave.getReal([vr["J2.phi"]]) == [0.5]
    with pytest.raises(FMICallException):
        slave.setReal([vr["J1.w"]], [3.0])
    assert "setting the start value of J1.w is not allowed in state Step" in messages[-1]
    slave.doStep(0.0, 0.1)  # still usable
    slave.terminate()
    slave.freeInstance()
