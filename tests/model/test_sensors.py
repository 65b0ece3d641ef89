"""Rotational.Sensors through the Python package: MSL's ElasticBearing (a MultiSensor between
the gear housing and its spring-damper) in the 2e-3 tube, a brake driven by a measured speed
in a TOML model, a sweep, an FMU run by FMPy, the Modelica class names and the catalogue."""

from __future__ import annotations

import math
from pathlib import Path

import fmpy
import numpy as np
import pytest
from paths import MSL_DATA, MSL_EXAMPLES

import stiction as st
from stiction.model.catalogue import catalogue
from stiction.modelica.names import TYPE_OF
from stiction.results.io.csv import read_csv
from stiction.sweeps import grid, sweep

SENSORS = {
    "AngleSensor": ["phi"],
    "SpeedSensor": ["w"],
    "AccSensor": ["a"],
    "RelAngleSensor": ["phi_rel"],
    "RelSpeedSensor": ["w_rel"],
    "RelAccSensor": ["a_rel"],
    "TorqueSensor": ["tau"],
    "PowerSensor": ["power"],
    "MultiSensor": ["power", "w", "tau"],
}

# J·w' = −mu·cgeo·fn_max·k·w while it slides: w = w0·exp(−rate·t)
BRAKE = """
name = "speed_brake"
connect = [
  ["J.flange_b", "brake.flange_a"],
  ["J.flange_a", "speed.flange"],
  ["speed.w", "gain.u"],
  ["gain.y", "brake.f_normalized"],
]
[experiment]
StopTime = 2.0
Interval = 0.01
Tolerance = 1e-8
[components]
J = { type = "Inertia", J = 2.0, w = 10.0 }
speed = { type = "SpeedSensor" }
gain = { type = "Gain", k = 0.05 }
brake = { type = "Brake", fn_max = 20.0, mu_pos = [[0.0, 0.4]] }
"""


def rate(fn_max: float, k: float = 0.05) -> float:
    return 0.4 * fn_max * k / 2.0


def test_elastic_bearing_stays_inside_the_msl_tube() -> None:
    """ElasticBearing, with its MultiSensor, on MSL's six compared signals; the sensor's
    torque is the spring-damper's (it is the only thing between them), its power tau·w."""
    result = st.Model.load(MSL_EXAMPLES / "ElasticBearing.toml").simulate()
    reference = MSL_DATA / "ElasticBearing.csv"
    signals = MSL_DATA / "ElasticBearing.signals.txt"
    report = st.compare(result, reference, tolerance=2e-3, signals=signals)
    assert len(report) == 6 and report.passed, str(report)
    # negative control: 1 % of the range off on one signal leaves the tube
    ref_names, ref_data = read_csv(reference)
    bad = result.data.copy()
    name = "springDamper.w_rel"
    bad[:, result.names.index(name)] += 0.01 * np.ptp(ref_data[:, ref_names.index(name)])
    assert st.compare((result.names, bad), reference, signals=signals).failed == [name]
    tau, w = result["multiSensor.tau"], result["multiSensor.w"]
    np.testing.assert_allclose(tau, -result["springDamper.tau"], rtol=0, atol=1e-9 * np.abs(tau).max())
    np.testing.assert_array_equal(w, result["housing.w"])
    np.testing.assert_allclose(result["multiSensor.power"], tau * w, rtol=1e-12, atol=1e-15)
    assert np.abs(tau).max() > 100.0  # the bearing carries the reaction of the gear


def test_a_brake_driven_by_a_measured_speed_decays_exponentially() -> None:
    result = st.Model.loads(BRAKE).simulate()
    exact = 10.0 * np.exp(-rate(20.0) * result.time)
    np.testing.assert_allclose(result["J.w"], exact, rtol=0, atol=1e-5)
    np.testing.assert_array_equal(result["speed.w"], result["J.w"])
    assert result.metric("max(gain.y)") == pytest.approx(0.5)


def test_a_sweep_over_a_sensor_driven_brake_equals_single_runs() -> None:
    model = st.Model.loads(BRAKE)
    variants = grid({"brake.fn_max": [10.0, 20.0, 40.0]})
    result = sweep(model, variants, ["final(J.w)", "max(speed.w)"], progress=False)
    assert (result.table["status"] == "ok").all()
    for k, fn_max in enumerate([10.0, 20.0, 40.0]):
        expected = 10.0 * math.exp(-rate(fn_max) * 2.0)
        assert result.table.loc[k, "final(J.w)"] == pytest.approx(expected, abs=1e-5)
        single = model.simulate(params={"brake.fn_max": fn_max})
        assert result.table.loc[k, "final(J.w)"] == single.metric("final(J.w)")


def test_an_fmu_with_a_sensor_runs_in_fmpy(tmp_path: Path) -> None:
    model = st.Model.loads(BRAKE)
    fmu = model.to_fmu(tmp_path / "SpeedBrake.fmu", outputs=["J.w", "speed.w", "gain.y"])
    out = fmpy.simulate_fmu(str(fmu), stop_time=2.0, output_interval=0.01, output=["J.w", "speed.w"])
    exact = 10.0 * np.exp(-rate(20.0) * out["time"])
    np.testing.assert_allclose(out["J.w"], exact, rtol=0, atol=1e-4)
    np.testing.assert_array_equal(out["speed.w"], out["J.w"])


def test_every_sensor_is_in_the_catalogue_with_its_msl_class_and_outputs() -> None:
    types = catalogue()
    for name, outputs in SENSORS.items():
        msl = f"Modelica.Mechanics.Rotational.Sensors.{name}"
        assert TYPE_OF[msl] == name
        assert types[name].msl_class == msl
        variables = [v.name for v in types[name].variables]
        assert all(o in variables for o in outputs), (name, variables)


def test_a_cut_torque_into_a_brake_is_refused_naming_both() -> None:
    text = (
        BRAKE.replace('["J.flange_a", "speed.flange"],', '["J.flange_a", "speed.flange_b"],')
        .replace('["speed.w", "gain.u"]', '["speed.tau", "gain.u"]')
        .replace('{ type = "SpeedSensor" }', '{ type = "TorqueSensor" }')
    )
    with pytest.raises(st.StictionError, match=r"(?s)brake.*speed\.tau.*algebraic loop"):
        st.Model.loads(text).simulate()
