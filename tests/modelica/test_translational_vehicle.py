"""The translational vehicle and sources from Modelica and Python (issue 31): MSL's Vehicle and
EddyCurrentBrake examples in the 2e-3 tube (TOML twins; EddyCurrentBrake also from its .mo
file), MSL's class names read and written back, a coasting vehicle on a grade against a SciPy
integration of the same ODE, and the Vehicle example exported as an FMU that FMPy runs."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import fmpy
import numpy as np
import pytest
from paths import DATA, EXAMPLES
from scipy.integrate import solve_ivp

import stiction as st

DIR = EXAMPLES / "msl-translational"
REF = DATA / "msl-translational"
G_N = 9.80665


@cache
def _toml_run(name: str) -> st.Result:
    return st.Model.load(DIR / f"{name}.toml").simulate()


@pytest.mark.parametrize("name", ["Vehicle", "EddyCurrentBrake"])
def test_toml_twin_stays_in_the_msl_tube(name: str) -> None:
    signals = REF / f"{name}.signals.txt"
    report = st.compare(_toml_run(name), REF / f"{name}.csv", tolerance=2e-3, signals=signals)
    assert len(report) == len(signals.read_text().split()) - 1 and report.passed, str(report)


def test_eddy_current_brake_mo_file_is_its_toml_twin() -> None:
    r_mo = st.Model.from_modelica(DIR / "EddyCurrentBrake.mo").simulate()
    r_toml = _toml_run("EddyCurrentBrake")
    for signal in ["mass.s", "mass.v", "heatCapacitor.T", "eddyCurrentForce.lossPower", "eddyCurrentForce.f"]:
        assert np.array_equal(r_mo[signal], r_toml[signal]), signal
    report = st.compare(
        r_mo, REF / "EddyCurrentBrake.csv", tolerance=2e-3, signals=REF / "EddyCurrentBrake.signals.txt"
    )
    assert len(report) == 3 and report.passed, str(report)


def test_vehicle_trailer_is_pulled_with_the_force_its_resistances_take() -> None:
    """The MultiSensor between vehicle1 and the trailer reads the trailer's m·a + drag + roll
    (+ grade), and its power is that force times the common speed."""
    r = _toml_run("Vehicle")
    f = r["multiSensor.f"]
    alpha = np.arctan(np.where((r.time > 20) & (r.time < 25), 0.05, 0.0))
    resist = 100 * r["trailer.a"] + r["trailer.fDrag.f"] + r["trailer.fRoll.f"]
    inside = np.abs(r.time - np.round(r.time / 5) * 5) > 1e-6  # away from the table's jumps
    np.testing.assert_allclose(f[inside], (resist + 100 * G_N * np.sin(alpha))[inside], atol=1e-6)
    np.testing.assert_allclose(r["multiSensor.power"], f * r["trailer.v"], atol=1e-9)
    assert np.array_equal(r["vehicle1.v"], r["trailer.v"])
    assert f.max() > 50.0


def test_msl_vehicle_classes_are_read_and_written_back() -> None:
    text = """model Coast
  Modelica.Mechanics.Translational.Components.Vehicle car(m=800, J=1, R=0.3, A=2, Cd=0.3,
    CrConstant=0.01, inclinationConstant=0.02, s(fixed=true), v(start=25, fixed=true));
  Modelica.Mechanics.Translational.Sensors.MultiSensor sensor;
  Modelica.Mechanics.Translational.Components.RollingResistance tow(fWeight=500, CrConstant=0.02);
  Modelica.Mechanics.Translational.Sources.ForceStep push(stepForce=10, startTime=1);
equation
  connect(car.flangeT, sensor.flange_a);
  connect(sensor.flange_b, tow.flange);
  connect(push.flange, car.flangeT);
end Coast;
"""
    m = st.Model.from_modelica(text)
    types = {name: c.type for name, c in m.components.items()}
    assert types == {
        "car": "Translational.Vehicle",
        "sensor": "Translational.MultiSensor",
        "tow": "Translational.RollingResistance",
        "push": "Translational.ForceStep",
    }
    r = m.simulate(StopTime=2.0, Tolerance=1e-10)
    assert r["sensor.f"][-1] == pytest.approx(0.02 * 500, rel=1e-9)  # the towed roller's pull
    again = st.Model.from_modelica(m.to_modelica()).simulate(StopTime=2.0, Tolerance=1e-10)
    assert np.array_equal(again["car.v"], r["car.v"])


def test_a_coasting_vehicle_on_a_grade_follows_the_scipy_integration() -> None:
    """(m + J/R²)·v' = −(Cd·A·rho/2·v·|v| + Cr·m·g·cos(alpha)·sign(v) + m·g·sin(alpha)) from
    25 m/s uphill, until it stops (and MSL's linear regularization within vReg takes over)."""
    m, j, r_w, cd, a, rho, cr, incl = 900.0, 1.5, 0.31, 0.32, 2.1, 1.2, 0.013, 0.03
    model = st.Model.from_modelica(f"""model Coast
  Modelica.Mechanics.Translational.Components.Vehicle car(m={m}, J={j}, R={r_w}, A={a}, Cd={cd},
    CrConstant={cr}, inclinationConstant={incl}, s(fixed=true), v(start=25, fixed=true));
end Coast;
""")
    res = model.simulate(StopTime=80.0, Interval=0.05, Tolerance=1e-10)
    alpha = np.arctan(incl)

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        v = y[1]
        force = cd * a * rho / 2 * v * abs(v) + cr * m * G_N * np.cos(alpha) + m * G_N * np.sin(alpha)
        return [v, -force / (m + j / r_w**2)]

    stop = lambda _t, y: y[1] - 1e-3  # the end of the closed form (|v| = vReg)
    stop.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0, 80), [0.0, 25.0], rtol=1e-12, atol=1e-12, dense_output=True, events=stop)
    t_stop = sol.t_events[0][0]
    assert 20 < t_stop < 70
    before = res.time < t_stop - 1e-6
    np.testing.assert_allclose(res["car.v"][before], sol.sol(res.time[before])[1], atol=1e-7)
    np.testing.assert_allclose(res["car.s"][before], sol.sol(res.time[before])[0], atol=1e-6)
    # then it rolls back down: the grade beats the rolling resistance (0.03 > 0.013)
    assert res["car.v"][-1] < -1.0


@pytest.mark.parametrize(
    ("bad", "parameter"), [("A=-1", "A"), ("CrConstant=-0.1", "CrConstant"), ("m=0", "m")]
)
def test_impossible_vehicle_data_is_refused_by_name(bad: str, parameter: str) -> None:
    base = {"m": "m=800", "A": "A=2", "CrConstant": "CrConstant=0.01"}
    base[parameter] = bad
    text = f"model Bad\n  Modelica.Mechanics.Translational.Components.Vehicle car(J=1, R=0.3, {', '.join(base.values())});\nend Bad;\n"
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text).simulate(StopTime=1.0)
    assert "car" in str(info.value) and f"'{parameter}'" in str(info.value), str(info.value)


def test_vehicle_example_runs_as_an_fmu_in_fmpy(tmp_path: Path) -> None:
    m = st.Model.load(DIR / "Vehicle.toml")
    fmu = m.to_fmu(tmp_path / "Vehicle.fmu", outputs=["vehicle.v", "trailer.s"])
    out = fmpy.simulate_fmu(str(fmu), stop_time=60.0, output_interval=0.05, output=["vehicle.v", "trailer.s"])
    ref = m.simulate()
    for name in ["vehicle.v", "trailer.s"]:
        expected = np.interp(out["time"], ref.time, ref[name])
        assert np.max(np.abs(out[name] - expected)) < 2e-3 * np.ptp(ref[name]), name


def test_the_genuine_vehicle_file_reads_its_two_column_table_as_one_time_table() -> None:
    """MSL's Vehicle example drives torque and inclination from one two-column CombiTimeTable
    (y[1], y[2]): it imports as one TimeTable whose y[1] feeds the gain and whose y[2] is the
    road's inclination for all three vehicles."""
    m = st.Model.from_modelica(DIR / "Vehicle.mo")
    table = m.components["timeTableTorqueInclination"]
    assert table.type == "TimeTable" and len(table.params["table"][0]) == 3
    pairs = {frozenset(p) for p in m.connections}
    assert frozenset(("timeTableTorqueInclination.y[1]", "gain.u")) in pairs
    for car in ("vehicle", "vehicle1", "trailer"):
        assert frozenset(("timeTableTorqueInclination.y[2]", f"{car}.inclination")) in pairs


def test_a_sweep_of_coasting_vehicles_matches_the_closed_form_per_variant() -> None:
    """Flat road, no drag: (m + J/R²)·v' = −Cr·m·g, so v(T) = v0 − Cr·m·g·T/(m + J/R²)."""
    m = st.Model.from_modelica("""model Coast
  Modelica.Mechanics.Translational.Components.Vehicle car(m=1000, J=2, R=0.3, A=0, Cd=0.3,
    CrConstant=0.01, s(fixed=true), v(start=20, fixed=true));
end Coast;
""")
    variants = st.grid({"car.m": [500.0, 1500.0], "car.CrConstant": [0.01, 0.03]})
    m.experiment.update(StopTime=5.0, Tolerance=1e-10)
    result = st.sweep(m, variants, ["final(car.v)"], progress=False, workers=2)
    assert list(result.table["status"]) == ["ok"] * 4
    for _, row in result.table.iterrows():
        mass, cr = row["car.m"], row["car.CrConstant"]
        expected = 20.0 - cr * mass * G_N * 5.0 / (mass + 2.0 / 0.3**2)
        assert row["final(car.v)"] == pytest.approx(expected, rel=1e-9)


def test_the_catalogue_gives_each_variable_the_unit_of_its_domain() -> None:
    """A mixed component's flange variables are in the flange's domain, its own in its type's."""
    from stiction.model.catalogue import catalogue

    units = {v.name: v.unit for v in catalogue()["Translational.Vehicle"].variables}
    assert units["a"] == "m/s2" and units["fDrag.f"] == "N" and units["flangeT.f"] == "N"
    assert units["flangeR.tau"] == "N.m" and units["flangeR.phi"] == "rad"
    wheel = {v.name: v.unit for v in catalogue()["IdealRollingWheel"].variables}
    assert wheel["flangeT.f"] == "N" and wheel["flangeR.tau"] == "N.m"
    speed = {v.name: v.unit for v in catalogue()["Translational.Speed"].variables}
    assert speed["v_ref"] == "m/s" and speed["a"] == "m/s2"
