"""Modelica import: every MSL example written as a .mo file imports, simulates and equals its
TOML twin bit for bit; where MSL has a reference it stays in the MSL tube; derived variables
(SimpleGearShift's gearRatio, LossyGearDemo1's PowerLoss) are computed from the run."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from paths import MSL_DATA, REPO

import stiction as st

EXAMPLES = REPO / "examples" / "msl"
MSL_DIR = MSL_DATA
TWINS = sorted(p.stem for p in EXAMPLES.glob("*.toml"))
NAMES = TWINS  # .mo and .toml twins
MO_NAMES = sorted(p.stem for p in EXAMPLES.glob("*.mo"))
# Modelica.Mechanics.Rotational.Examples of MSL 4.x but GenerationOfFMUs (whose classes have
# equations of their own: refused, docs/modelica.md)
MSL_ROTATIONAL_EXAMPLES = [
    *("Backlash", "CompareBrakingTorque", "CoupledClutches", "EddyCurrentBrake", "ElasticBearing"),
    *("First", "FirstGrounded", "Friction", "HeatLosses", "LossyGearDemo1", "LossyGearDemo2"),
    *("LossyGearDemo3", "OneWayClutch", "OneWayClutchDisengaged", "RollingWheel", "SimpleGearShift"),
]


@cache
def _runs(name: str) -> tuple[st.Model, st.Result, st.Model, st.Result]:
    mo = st.Model.from_modelica(EXAMPLES / f"{name}.mo")
    toml = st.Model.load(EXAMPLES / f"{name}.toml")
    return mo, mo.simulate(), toml, toml.simulate()


def test_every_toml_example_has_a_modelica_twin() -> None:
    assert set(TWINS) <= {p.stem for p in EXAMPLES.glob("*.mo")}
    assert MO_NAMES == TWINS == MSL_ROTATIONAL_EXAMPLES


@pytest.mark.parametrize("name", NAMES)
def test_modelica_twin_is_the_same_model(name: str) -> None:
    mo, _, toml, _ = _runs(name)
    assert list(mo.components) == list(toml.components)
    for comp, c in toml.components.items():
        assert mo.components[comp].type == c.type
    as_sets = lambda m: {frozenset(pair) for pair in m.connections}
    assert as_sets(mo) == as_sets(toml)
    expected = {k: v for k, v in toml.experiment.items() if not (k == "StartTime" and v == 0.0)}
    assert mo.experiment == expected


@pytest.mark.parametrize("name", NAMES)
def test_modelica_twin_gives_the_identical_result(name: str) -> None:
    _, r_mo, _, r_toml = _runs(name)
    assert r_mo.names[: len(r_toml.names)] == r_toml.names
    for signal in r_toml.names:
        assert np.array_equal(r_mo[signal], r_toml[signal]), signal


REFERENCED = [n for n in MO_NAMES if (MSL_DIR / f"{n}.csv").is_file()]


@cache
def _mo_run(name: str) -> st.Result:
    return st.Model.from_modelica(EXAMPLES / f"{name}.mo").simulate()


@pytest.mark.parametrize("name", REFERENCED)
def test_modelica_twin_stays_in_the_msl_tube(name: str) -> None:
    """The MSL signal list where MSL has one, else every column of the reference (as MSL and
    the TOML twins' tests do)."""
    r_mo = _mo_run(name)
    listed = MSL_DIR / f"{name}.signals.txt"
    report = st.compare(
        r_mo, MSL_DIR / f"{name}.csv", tolerance=2e-3, signals=listed if listed.is_file() else None
    )
    # every signal MSL lists (RollingWheel's two) is compared, or at least three columns
    wanted = len(listed.read_text().split()) - 1 if listed.is_file() else 3  # minus time
    assert len(report) >= wanted and report.passed, str(report)


def test_every_reference_is_used() -> None:
    assert REFERENCED == [n for n in MO_NAMES if n not in ("CompareBrakingTorque", "HeatLosses")]
    assert {"FirstGrounded", "LossyGearDemo3"} <= set(REFERENCED)


def test_derived_variables_of_simple_gear_shift() -> None:
    mo, r, _, _ = _runs("SimpleGearShift")
    assert mo.variables["gearRatio"] == "wLoad / max(wEngine, 1e-06)"
    assert np.array_equal(r["wEngine"], r["engine.w"])
    expected = r["load.w"] / np.maximum(r["engine.w"], 1e-6)
    assert np.array_equal(r["gearRatio"], expected)
    assert r["gearRatio"][-1] == pytest.approx(1.0, abs=0.05)  # clutch locked: direct drive


def test_power_loss_with_der_equals_the_gear_loss_power() -> None:
    """MSL: PowerLoss (from der() of the flange angles) and gear.lossPower coincide."""
    _, r, _, _ = _runs("LossyGearDemo1")
    assert np.abs(r["gear.lossPower"]).max() > 0.1
    np.testing.assert_allclose(r["PowerLoss"], r["gear.lossPower"], rtol=0, atol=1e-12)


def test_top_level_parameters_are_kept_and_a_sweep_recomputes_dependents(tmp_path: Path) -> None:
    """T2 stays a parameter (TOML [parameters]); step1.startTime refers to it; changing T2
    moves clutch2's engagement, and the TOML form is the same model."""
    mo, r, _, _ = _runs("CoupledClutches")
    assert mo.parameters == {"f": 0.2, "T2": 0.4, "T3": 0.9}
    assert mo.components["step1"].params["startTime"] == {"expr": "T2"}
    assert mo.parameter_values()["step1.startTime"] == 0.4
    assert r.parameters["T2"] == 0.4  # written to data_1 of a .mat result
    mo.save(tmp_path / "cc.toml")
    again = st.Model.load(tmp_path / "cc.toml")
    assert again == mo
    again.parameters["T2"] = 0.6
    later = again.simulate()
    engaged = lambda res: res.time[np.argmax(res["clutch2.mode"] != 2)]
    assert engaged(r) == pytest.approx(0.4) and engaged(later) == pytest.approx(0.6)
    first = st.Model.from_modelica(EXAMPLES / "First.mo")
    assert first.parameter_values()["inertia1.J"] == 0.1  # Jmotor
    assert first.parameter_values()["damper.d"] == 10.0  # damping


SPIN = """
model Spin
  parameter Real w0 = 3;
  Modelica.Mechanics.Rotational.Components.Inertia J(J=2, phi(fixed=true, start=0), w(fixed=true, start=2*w0));
  Modelica.Mechanics.Rotational.Components.Damper d(d=1);
  Modelica.Mechanics.Rotational.Components.Fixed f;
equation
  connect(J.flange_b, d.flange_a);
  connect(d.flange_b, f.flange);
  annotation(experiment(StopTime=1, Interval=0.01));
end Spin;
"""


def test_a_start_value_written_with_a_parameter_follows_it(tmp_path: Path) -> None:
    """`w(start=2*w0)` stays an expression: editing w0, overriding it for one run, sweeping it
    and a Modelica round trip all start J at 2·w0; J decays as 2·w0·exp(-d·t/J)."""
    m = st.Model.from_modelica(SPIN)
    assert m.components["J"].params["w"] == {"expr": "2 * w0"}  # a fixed start, short form
    decay = np.exp(-0.5)  # d·t/J at t = 1
    assert m.simulate()["J.w"][-1] == pytest.approx(6.0 * decay, rel=1e-5)
    once = m.simulate(params={"w0": 1.0})
    assert once["J.w"][0] == 2.0 and m.simulate()["J.w"][0] == 6.0  # the model is unchanged
    table = st.sweep(m, {"w0": [1.0, 5.0]}, ["final(J.w)"], workers=1, progress=False).table
    assert table["final(J.w)"].tolist() == [
        once.metric("final(J.w)"),
        m.simulate(params={"w0": 5.0}).metric("final(J.w)"),
    ]
    back = st.Model.from_modelica(m.to_modelica())
    back.parameters["w0"] = 4.0
    assert back.simulate()["J.w"][0] == 8.0


def test_parameter_expressions_and_their_errors() -> None:
    m = st.Model("p")
    m.parameters.update({"T": 0.5, "T2": "2*T"})
    m.add("s", st.Step(startTime=st.expr("T2 + 0.1")))
    assert m.parameter_values()["s.startTime"] == pytest.approx(1.1)
    m.parameters["T"] = "T2"
    with pytest.raises(st.ModelError, match="cyclic definition T -> T2 -> T|cyclic definition T2 -> T -> T2"):
        m.engine_toml()
    m.parameters["T"] = 0.5
    m.components["s"].params["startTime"] = st.expr("Tx")
    with pytest.raises(st.ModelError, match="component 's': parameter 'startTime': no parameter 'Tx'"):
        m.engine_toml()


def test_result_of_the_simulation_api_has_derived_variables() -> None:
    mo, r, _, _ = _runs("SimpleGearShift")
    sim = mo.simulation()
    sim.run()
    assert np.array_equal(sim.result()["gearRatio"], r["gearRatio"])


def test_derived_variables_and_parameters_in_the_model_file(tmp_path: Path) -> None:
    m = st.Model.load(EXAMPLES / "CoupledClutches.toml")
    m.variable("slip12", "J1.w - J2.w")
    m.parameters["k"] = 2.0
    m.variable("scaled", "k * J1.w")
    m.save(tmp_path / "m.toml")
    text = (tmp_path / "m.toml").read_text()
    assert '[variables]\nslip12 = "J1.w - J2.w"' in text and "[parameters]\nk = 2.0" in text
    back = st.Model.load(tmp_path / "m.toml")
    assert back == m
    r = back.simulate()
    assert np.array_equal(r["slip12"], r["J1.w"] - r["J2.w"])
    assert np.array_equal(r["scaled"], 2.0 * r["J1.w"])
    with pytest.raises(st.ModelError, match="'variables' must be a table of expressions"):
        st.Model.loads('name = "x"\n[variables]\nx = 1\n')
    with pytest.raises(st.ModelError, match="syntax error"):
        m.variable("bad", "J1.w +* 2")
