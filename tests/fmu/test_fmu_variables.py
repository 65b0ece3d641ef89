"""Boolean parameters, Boolean start values and tables as FMU variables (FMI 2.0 and 3.0),
checked with FMPy: they carry their MSL names, pass FMPy's validation, set before the end of
initialization they change the run as the same edit of the model does in ``stiction
simulate`` (to 1e-9), and bad use (a wrong type, phase or shape, an unknown value reference)
is an error status with a logged message, never a crash."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu
from paths import REPO
from test_fmu_state import Runner

import stiction as st

ROOT = REPO
BRAKING = ROOT / "examples" / "msl" / "CompareBrakingTorque.toml"
ONE_WAY = ROOT / "examples" / "msl" / "OneWayClutch.toml"
FLYWHEEL = ROOT / "examples" / "braked_flywheel.toml"
SOURCES = ["linearSpeedDependentTorque", "quadraticSpeedDependentTorque", "inverseSpeedDependentTorque"]
MU = [[0.0, 0.5], [50.0, 0.3], [100.0, 0.2]]  # the flywheel brake's edited mu_pos


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def version(request: pytest.FixtureRequest) -> int:
    return request.param


def variables(fmu: Path) -> dict[str, object]:
    return {v.name: v for v in fmpy.read_model_description(fmu).modelVariables}


def run(r: Runner, stop: float, h: float, outputs: list[str]) -> np.ndarray:
    """The outputs after each step of h, from an initialized runner."""
    rows = []
    for k in range(round(stop / h)):
        r.slave.doStep(k * h, h)
        rows.append(r.get(outputs))
    return np.array(rows)


def expected(model: st.Model, stop: float, h: float, outputs: list[str]) -> np.ndarray:
    """``stiction simulate``'s values at the same points."""
    result = model.simulate(StopTime=stop)
    points = np.arange(1, round(stop / h) + 1) * h
    return np.column_stack([np.interp(points, result.time, result[n]) for n in outputs])


def test_booleans_and_tables_are_variables_with_their_msl_names(tmp_path: Path, version: int) -> None:
    for path in (BRAKING, ONE_WAY, FLYWHEEL):
        fmu = st.Model.load(path).to_fmu(tmp_path / f"{path.stem}{version}.fmu", fmi_version=version)
        assert validate_fmu(str(fmu)) == [], path.stem
    braking = variables(st.Model.load(BRAKING).to_fmu(tmp_path / "b.fmu", fmi_version=version))
    for source in SOURCES:
        v = braking[f"{source}.TorqueDirection"]
        assert (v.type, v.causality, v.variability, v.start) == ("Boolean", "parameter", "fixed", "false")
    one_way = variables(st.Model.load(ONE_WAY).to_fmu(tmp_path / "o.fmu", fmi_version=version))
    stuck = one_way["oneWayClutch.stuck"]
    assert (stuck.type, stuck.causality, stuck.initial, stuck.start) == ("Boolean", "local", "exact", "false")
    # useSupport and useHeatPort decide the compiled model's ports: they stay in the model
    assert not [n for n in one_way if n.endswith(("useSupport", "useHeatPort"))]
    fly = variables(st.Model.load(FLYWHEEL).to_fmu(tmp_path / "f.fmu", fmi_version=version))
    assert "brake.useHeatPort" not in fly
    if version == 3:
        mu = fly["brake.mu_pos"]
        assert (mu.type, [d.start for d in mu.dimensions]) == ("Float64", [3, 2])
    else:
        assert fly["brake.mu_pos[2,1]"].start == "50.0"
        assert fly["brake.mu_pos[3,2]"].start == "0.35"


def test_a_boolean_parameter_set_before_initialization_changes_the_run(tmp_path: Path, version: int) -> None:
    model = st.Model.load(BRAKING)
    outputs = [f"inertia{k}.w" for k in (2, 3, 4)]
    fmu = model.to_fmu(tmp_path / "braking.fmu", fmi_version=version, outputs=outputs)
    r = Runner(fmu, version)
    set_bool = r.slave.setBoolean
    set_bool([r.vr[f"{s}.TorqueDirection"] for s in SOURCES], [True] * 3)
    assert r.slave.getBoolean([r.vr[f"{SOURCES[0]}.TorqueDirection"]]) == [True]
    r.start(3.0)
    got = run(r, 3.0, 0.01, outputs)
    for s in SOURCES:
        model.set(f"{s}.TorqueDirection", True)
    np.testing.assert_allclose(got, expected(model, 3.0, 0.01, outputs), rtol=0, atol=1e-9)
    # the torque keeps its direction through w = 0: the speeds turn negative
    assert got[-1].min() < -1.0


def test_a_table_set_before_initialization_changes_the_run(tmp_path: Path, version: int) -> None:
    model = st.Model.load(FLYWHEEL)
    outputs = ["flywheel.w", "disc.T"]
    fmu = model.to_fmu(tmp_path / "fly.fmu", fmi_version=version, outputs=outputs)
    r = Runner(fmu, version)
    if version == 3:
        r.slave.setFloat64([r.vr["brake.mu_pos"]], [x for row in MU for x in row])
        assert r.slave.getFloat64([r.vr["brake.mu_pos"]], nValues=6) == [x for row in MU for x in row]
    else:
        names = [f"brake.mu_pos[{i + 1},{j + 1}]" for i in range(3) for j in range(2)]
        r.slave.setReal([r.vr[n] for n in names], [x for row in MU for x in row])
    r.start(2.0)
    got = run(r, 2.0, 0.01, outputs)
    model.set("brake.mu_pos", MU)
    np.testing.assert_allclose(got, expected(model, 2.0, 0.01, outputs), rtol=0, atol=1e-9)
    default = expected(st.Model.load(FLYWHEEL), 2.0, 0.01, outputs)
    assert np.abs(got[:, 0] - default[:, 0]).max() > 1.0  # the edit shows


def test_bad_use_of_booleans_and_tables_is_an_error_not_a_crash(tmp_path: Path, version: int) -> None:
    fmu = st.Model.load(FLYWHEEL).to_fmu(tmp_path / "fly.fmu", fmi_version=version)
    braking = st.Model.load(BRAKING).to_fmu(tmp_path / "b.fmu", fmi_version=version)
    r = Runner(fmu, version)
    flag = Runner(braking, version)
    direction = flag.vr[f"{SOURCES[0]}.TorqueDirection"]
    bad = [
        (lambda: flag.slave.setBoolean([99999], [True]), flag, "unknown value reference"),
        (lambda: flag.slave.getBoolean([flag.vr["inertia1.w"]]), flag, "is not a Boolean"),
        (
            lambda: flag.slave.getReal([direction]) if version == 2 else flag.slave.getFloat64([direction]),
            flag,
            "is not a Real",
        ),
    ]
    if version == 3:
        mu = r.vr["brake.mu_pos"]
        bad.append((lambda: r.slave.setFloat64([mu], [0.0, 0.4, 50.0, 0.3]), r, "shape is fixed"))
        bad.append((lambda: r.slave.setFloat64([mu], [0, 0.4, 0, 0.3, 0, 0.2]), r, "strictly increasing"))
    for call, runner, message in bad:
        with pytest.raises(FMICallException):
            call()
        assert message in runner.messages[-1], runner.messages[-1]
    flag.start(1.0)
    with pytest.raises(FMICallException):  # a parameter: fixed once initialization is over
        flag.slave.setBoolean([direction], [True])
    assert "not allowed" in flag.messages[-1]
    flag.slave.doStep(0.0, 0.1)  # the instance is unharmed
    assert flag.slave.getBoolean([direction]) == [False]


def test_a_boolean_start_value_set_before_initialization_is_the_models(tmp_path: Path, version: int) -> None:
    model = st.Model.load(ONE_WAY)
    outputs = ["inertiaIn.w", "inertiaOut.w"]
    fmu = model.to_fmu(tmp_path / "owc.fmu", fmi_version=version, outputs=outputs)
    r = Runner(fmu, version)
    stuck = r.vr["oneWayClutch.startForward"]
    r.slave.setBoolean([stuck], [True])
    r.start(1.0)
    got = run(r, 1.0, 0.01, outputs)
    assert r.slave.getBoolean([stuck]) in ([True], [False])  # the state's value as the run has it
    model.set("oneWayClutch.startForward", {"start": True, "fixed": True})
    np.testing.assert_allclose(got, expected(model, 1.0, 0.01, outputs), rtol=0, atol=1e-9)
