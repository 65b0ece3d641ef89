"""FMU export (FMI 2.0 Co-Simulation) checked with FMPy, an independent importer, and with a
small C host: agreement with ``Model.simulate``, inputs, independent instances, saved states,
errors from bad calls, and no growth in memory over many instantiate/reset cycles."""

from __future__ import annotations

import shutil
import subprocess
import sys
from ctypes import byref
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.validation import validate_fmu
from paths import FMI_HARNESS, REPO

import stiction as st

ROOT = REPO
COUPLED = ROOT / "examples" / "msl" / "CoupledClutches.toml"
FLYWHEEL = ROOT / "examples" / "braked_flywheel.toml"
CLUTCH_OUT = ["J1.w", "J2.w", "J3.w", "J4.w", "J1.phi", "clutch1.mode"]


def flywheel_with_input() -> st.Model:
    """The braked flywheel with its press ramp removed and the brake force a model input."""
    m = st.Model.load(FLYWHEEL)
    del m.components["press"]
    m.connections = [c for c in m.connections if "press.y" not in c]
    m.input("brake.f_normalized", start=0.0)
    return m


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def version(request: pytest.FixtureRequest) -> int:
    return request.param


@pytest.fixture(scope="module")
def clutches_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("fmu") / "CoupledClutches.fmu"
    return st.Model.load(COUPLED).to_fmu(path, outputs=CLUTCH_OUT)


@pytest.fixture(scope="module")
def flywheel_fmu(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return flywheel_with_input().to_fmu(tmp_path_factory.mktemp("fmu") / "Flywheel.fmu")


@pytest.fixture(scope="module")
def clutches_any(tmp_path_factory: pytest.TempPathFactory, version: int) -> Path:
    path = tmp_path_factory.mktemp("fmu") / "CoupledClutches.fmu"
    return st.Model.load(COUPLED).to_fmu(path, fmi_version=version, outputs=CLUTCH_OUT)


@pytest.fixture(scope="module")
def flywheel_any(tmp_path_factory: pytest.TempPathFactory, version: int) -> Path:
    path = tmp_path_factory.mktemp("fmu") / "Flywheel.fmu"
    return flywheel_with_input().to_fmu(path, fmi_version=version)


class Host:
    """One FMU2Slave with a logger that keeps the messages."""

    def __init__(self, fmu: Path, name: str = "instance") -> None:
        self.md = fmpy.read_model_description(fmu)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.messages: list[str] = []
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self._log)
        from fmpy.logging import addLoggerProxy

        addLoggerProxy(byref(self.callbacks))
        self.slave = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=fmpy.extract(fmu),
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.slave.instantiate(callbacks=self.callbacks)

    def _log(self, env: object, name: bytes, status: int, category: bytes, message: bytes) -> None:
        self.messages.append(message.decode())

    def start(self, stop: float, **params: float) -> None:
        self.slave.setupExperiment(startTime=0.0, stopTime=stop)
        self.slave.enterInitializationMode()
        for name, value in params.items():
            self.slave.setReal([self.vr[name]], [value])
        self.slave.exitInitializationMode()

    def get(self, name: str) -> float:
        return self.slave.getReal([self.vr[name]])[0]


def assert_close(a: np.ndarray, b: np.ndarray, name: str) -> None:
    scale = max(float(np.ptp(b)), 1e-12)
    assert np.max(np.abs(a - b)) <= 1e-6 * scale, name


def test_model_descriptions_pass_fmpy_validation(
    clutches_any: Path, flywheel_any: Path, version: int
) -> None:
    for fmu in (clutches_any, flywheel_any):
        assert validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(flywheel_any)
    assert md.fmiVersion == f"{version}.0"
    kinds = {v.name: (v.causality, v.variability) for v in md.modelVariables}
    assert kinds["brake.f_normalized"] == ("input", "continuous")
    assert kinds["flywheel.w"] == ("output", "continuous")
    assert kinds["brake.fn_max"] == ("parameter", "tunable")
    clutches = fmpy.read_model_description(clutches_any).modelVariables
    assert {v.name: v.variability for v in clutches}["step1.startTime"] == "fixed"
    fn_max = next(v for v in md.modelVariables if v.name == "brake.fn_max")
    assert (float(fn_max.start), fn_max.unit) == (2000.0, "N")


def test_coupled_clutches_in_fmpy_equals_simulate(clutches_any: Path) -> None:
    out = fmpy.simulate_fmu(str(clutches_any), stop_time=1.5, output_interval=0.01, output=CLUTCH_OUT)
    ref = st.Model.load(COUPLED).simulate()
    assert len(out) == 151
    for name in CLUTCH_OUT[:-1]:
        assert_close(out[name], np.interp(out["time"], ref.time, ref[name]), name)
    # every clutch1 mode the reference passes through at the grid points, the FMU reports too
    grid = np.searchsorted(ref.time, out["time"], side="right") - 1
    np.testing.assert_array_equal(out["clutch1.mode"], ref["clutch1.mode"][grid])


def test_parameters_set_by_the_importer_act_as_in_simulate(clutches_fmu: Path) -> None:
    params = {"clutch1.fn_max": 30.0, "J2.J": 2.5}
    out = fmpy.simulate_fmu(
        str(clutches_fmu), stop_time=1.5, output_interval=0.01, output=CLUTCH_OUT, start_values=params
    )
    ref = st.Model.load(COUPLED).simulate(params=params)
    plain = st.Model.load(COUPLED).simulate()
    for name in ("J1.w", "J3.w"):
        assert_close(out[name], np.interp(out["time"], ref.time, ref[name]), name)
    assert np.max(np.abs(out["J3.w"] - np.interp(out["time"], plain.time, plain["J3.w"]))) > 0.1


def test_braked_flywheel_driven_by_an_input_signal(flywheel_any: Path) -> None:
    signal = np.array(
        [(0.0, 0.0), (0.5, 0.0), (0.5, 0.6), (1.0, 0.6), (1.0, 1.0), (4.0, 1.0)],
        dtype=[("time", float), ("brake.f_normalized", float)],
    )
    out = fmpy.simulate_fmu(
        str(flywheel_any), stop_time=4.0, output_interval=0.01, input=signal, output=["flywheel.w", "disc.T"]
    )
    sim = flywheel_with_input().simulation(StopTime=4.0)
    ref = {"flywheel.w": [sim["flywheel.w"]], "disc.T": [sim["disc.T"]]}
    for t in out["time"][1:]:
        sim.set_input("brake.f_normalized", 1.0 if t > 1.0 + 1e-9 else 0.6 if t > 0.5 + 1e-9 else 0.0)
        sim.advance_to(float(t))
        for name, values in ref.items():
            values.append(sim[name])
    for name, values in ref.items():
        assert_close(out[name], np.array(values), name)
    assert out["flywheel.w"][-1] == pytest.approx(0.0, abs=1e-6)  # braked to rest, then stuck
    assert out["flywheel.w"][60] < 100.0 - 1.0  # braking from the input at 0.5 s on


def test_two_instances_are_independent(flywheel_fmu: Path) -> None:
    a, b = Host(flywheel_fmu, "a"), Host(flywheel_fmu, "b")
    a.start(2.0)
    b.start(2.0, **{"flywheel.J": 4.0})
    for s in (a, b):
        s.slave.setReal([s.vr["brake.f_normalized"]], [1.0])
    for k in range(10):
        a.slave.doStep(0.1 * k, 0.1)
        b.slave.doStep(0.1 * k, 0.1)
    # the same torque on twice the inertia: half the speed lost
    lost_a, lost_b = 100.0 - a.get("flywheel.w"), 100.0 - b.get("flywheel.w")
    assert lost_a > 10.0
    assert lost_b == pytest.approx(lost_a / 2, rel=0.02)
    for s in (a, b):
        s.slave.terminate()
        s.slave.freeInstance()


def test_bad_calls_return_an_error_with_a_message(flywheel_fmu: Path) -> None:
    h = Host(flywheel_fmu)
    with pytest.raises(FMICallException, match="status 3"):
        h.slave.doStep(0.0, 0.1)
    assert "fmi2DoStep: doStep is not allowed in state Instantiated" in h.messages[-1]
    with pytest.raises(FMICallException):
        h.slave.getReal([9999])
    assert "unknown value reference 9999" in h.messages[-1]
    with pytest.raises(FMICallException):
        h.slave.setReal([h.vr["flywheel.J"]], [-1.0])
    assert "flywheel" in h.messages[-1] and "J" in h.messages[-1]
    h.start(1.0)
    with pytest.raises(FMICallException):
        h.slave.doStep(0.0, -0.1)
    with pytest.raises(FMICallException):  # a start value: fixed once initialization is over
        h.slave.setReal([h.vr["flywheel.w"]], [10.0])
    assert "setting the start value of flywheel.w is not allowed in state Step" in h.messages[-1]
    h.slave.doStep(0.0, 0.5)  # still usable after refused calls
    assert h.get("flywheel.w") == pytest.approx(100.0)
    with pytest.raises(FMICallException):
        h.slave.doStep(0.5, 1.0)  # past the stop time set up
    assert "past StopTime = 1" in h.messages[-1]
    h.slave.terminate()
    assert h.get("flywheel.w") == pytest.approx(100.0)  # final values stay readable
    with pytest.raises(FMICallException):
        h.slave.doStep(0.5, 0.1)
    h.slave.reset()  # and reset after terminate starts anew
    h.start(1.0)
    h.slave.doStep(0.0, 1.0)
    h.slave.terminate()
    h.slave.freeInstance()


def test_a_restored_state_continues_as_the_original(clutches_fmu: Path) -> None:
    h = Host(clutches_fmu)
    h.start(1.5)
    t, dt = 0.0, 0.05
    while t < 0.6 - 1e-9:
        h.slave.doStep(t, dt)
        t += dt
    saved, t_saved = h.slave.getFMUstate(), t
    first = []
    while t < 1.5 - 1e-9:
        h.slave.doStep(t, dt)
        t += dt
        first.append([h.get(n) for n in CLUTCH_OUT])
    h.slave.setFMUstate(saved)
    again, t = [], t_saved
    while t < 1.5 - 1e-9:
        h.slave.doStep(t, dt)
        t += dt
        again.append([h.get(n) for n in CLUTCH_OUT])
    h.slave.freeFMUstate(saved)
    # the restored run is the one that went on: equal to the bit
    np.testing.assert_array_equal(np.array(again), np.array(first))
    h.slave.terminate()
    h.slave.freeInstance()


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_a_c_host_runs_the_fmu_without_python(flywheel_fmu: Path, tmp_path: Path) -> None:
    exe = tmp_path / "harness"
    subprocess.run(["cc", "-O2", "-o", exe, FMI_HARNESS, "-ldl"], check=True)
    md = fmpy.read_model_description(flywheel_fmu)
    unzipped = Path(fmpy.extract(flywheel_fmu))
    library = next((unzipped / "binaries").rglob("*.so"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    args = [exe, unzipped, library, md.guid, vr["flywheel.w"], 3.0, 0.001, 300, vr["brake.f_normalized"], 1.0]
    run = subprocess.run([str(a) for a in args], check=False, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    report = dict(line.split() for line in run.stdout.splitlines())
    sim = flywheel_with_input().simulation(StopTime=3.0)
    sim.set_input("brake.f_normalized", 1.0)
    sim.advance_to(3.0)
    assert float(report["value"]) == pytest.approx(sim["flywheel.w"], abs=1e-9)
    # the state saved halfway, restored here and from its bytes in a new instance, continues
    # as the run that went on: bit for bit
    assert report["restored_new"] == report["restored_same"] == report["value"]
    # 300 reset/initialize and 300 instantiate/free cycles: memory does not keep growing
    assert int(report["rss_after_kb"]) - int(report["rss_before_kb"]) < 2000


def test_fmi3_errors_states_and_steps(tmp_path: Path) -> None:
    from fmpy.fmi3 import FMU3Slave

    fmu = st.Model.load(COUPLED).to_fmu(tmp_path / "CC3.fmu", fmi_version=3, outputs=CLUTCH_OUT)
    md = fmpy.read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU3Slave(
        guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.coSimulation.modelIdentifier
    )
    slave.instantiate()
    with pytest.raises(FMICallException, match="status 3"):
        slave.doStep(0.0, 0.1)
    with pytest.raises(FMICallException):
        slave.getFloat64([12345])
    slave.enterInitializationMode(startTime=0.0, stopTime=1.5)
    slave.exitInitializationMode()
    slave.doStep(0.0, 0.5)
    saved = slave.getFMUState()
    slave.doStep(0.5, 0.5)
    first = slave.getFloat64([vr["J4.w"], vr["time"]])
    slave.setFMUState(saved)
    assert slave.getFloat64([vr["time"]]) == [0.5]
    slave.doStep(0.5, 0.5)
    again = slave.getFloat64([vr["J4.w"], vr["time"]])
    assert again == first  # the restored run is the one that went on
    ref = st.Model.load(COUPLED).simulate()
    assert first[0] == pytest.approx(float(np.interp(1.0, ref.time, ref["J4.w"])), abs=1e-5)
    slave.freeFMUState(saved)
    slave.terminate()
    slave.freeInstance()


def _stiction(*args: str | Path) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, "-m", "stiction", *map(str, args)]
    return subprocess.run(command, check=False, capture_output=True, text=True)


def test_the_command_exports_a_modelica_model(tmp_path: Path) -> None:
    fmu = tmp_path / "CC.fmu"
    run = _stiction(
        "fmu", ROOT / "examples/msl/CoupledClutches.mo", "-o", fmu, "--fmi", "3", "--outputs", "J1.w"
    )
    assert run.returncode == 0, run.stderr
    md = fmpy.read_model_description(fmu)
    assert [v.name for v in md.modelVariables if v.causality == "output"] == ["J1.w"]
    bad = _stiction("fmu", COUPLED, "-o", fmu, "--outputs", "J9.w")
    assert bad.returncode != 0 and "output 'J9.w': not a variable of the model" in bad.stderr


def test_a_model_with_a_data_file_carries_it(tmp_path: Path) -> None:
    model = st.Model.load(ROOT / "examples" / "brake_force_profile.toml")
    fmu = model.to_fmu(tmp_path / "Profile.fmu", outputs=["vehicle.w"])
    out = fmpy.simulate_fmu(str(fmu), stop_time=6.0, output_interval=0.01)
    ref = model.simulate()
    assert_close(out["vehicle.w"], np.interp(out["time"], ref.time, ref["vehicle.w"]), "vehicle.w")
