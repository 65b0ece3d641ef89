"""MSL's prescribed-motion sources (``Sources.Speed``, ``Position``, ``Accelerate``, ``Move``)
from Python: imported from Modelica written in MSL's style (``Speed speed(exact=true)``,
``connect(sine.y, move.u[1])``), round-tripped through ``to_modelica``, swept over ``f_crit``
(the filter's closed form) and exported as an FMU that FMPy runs as ``simulate`` does. The
closed forms of each source are the core's tests (crates/stiction-core/tests/motion.rs)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import stiction as st

SPEED_DRIVE = """
model SpeedDrive "A speed source follows a ramp exactly"
  import Modelica.Units.SI;
  parameter SI.Inertia J = 2;
  Modelica.Blocks.Sources.Ramp ramp(height=10, duration=2, startTime=0.5);
  Modelica.Mechanics.Rotational.Sources.Speed speed(exact=true);
  Modelica.Mechanics.Rotational.Components.Inertia inertia(J=J);
equation
  connect(ramp.y, speed.w_ref);
  connect(speed.flange, inertia.flange_a);
  annotation(experiment(StopTime=3, Interval=0.01));
end SpeedDrive;
"""

MOVE_DRIVE = """
model MoveDrive
  Modelica.Blocks.Sources.Sine p(f=0.15915494309189535);
  Modelica.Blocks.Sources.Sine v(f=0.15915494309189535, phase=1.5707963267948966);
  Modelica.Blocks.Sources.Sine a(amplitude=-1, f=0.15915494309189535);
  Modelica.Mechanics.Rotational.Sources.Move move;
  Modelica.Mechanics.Rotational.Components.Inertia inertia(J=2);
equation
  connect(p.y, move.u[1]);
  connect(v.y, move.u[2]);
  connect(a.y, move.u[3]);
  connect(move.flange, inertia.flange_a);
  annotation(experiment(StopTime=3, Interval=0.01));
end MoveDrive;
"""

FILTERED = """
model FilteredSpeed
  Modelica.Blocks.Sources.Step step(height=3, startTime=0.1);
  Modelica.Mechanics.Rotational.Sources.Speed speed(f_crit=2);
  Modelica.Mechanics.Rotational.Components.Inertia inertia(J=2);
equation
  connect(step.y, speed.w_ref);
  connect(speed.flange, inertia.flange_a);
  annotation(experiment(StopTime=1, Interval=0.001, Tolerance=1e-8));
end FilteredSpeed;
"""


def test_an_exact_speed_source_imports_and_takes_j_times_the_ramps_slope() -> None:
    m = st.Model.from_modelica(SPEED_DRIVE)
    assert m.components["speed"].type == "Speed"
    r = m.simulate()
    rising = (r.time > 0.6) & (r.time < 2.4)
    np.testing.assert_allclose(r["inertia.flange_a.tau"][rising], 2.0 * 5.0, rtol=1e-10)
    np.testing.assert_allclose(r["speed.w"], 1.0 * np.clip((r.time - 0.5) / 2, 0, 1) * 10, atol=1e-12)
    again = st.Model.from_modelica(m.to_modelica()).simulate()
    np.testing.assert_array_equal(again["inertia.w"], r["inertia.w"])


def test_move_reads_its_array_input_elements_and_writes_them_back() -> None:
    m = st.Model.from_modelica(MOVE_DRIVE)
    text = m.to_modelica()
    assert "connect(p.y, move.u[1]);" in text
    r = st.Model.from_modelica(text).simulate()
    np.testing.assert_allclose(r["inertia.phi"], np.sin(r.time), atol=1e-12)
    np.testing.assert_allclose(r["inertia.flange_a.tau"], -2.0 * np.sin(r.time), atol=1e-10)


def test_exact_on_a_model_input_is_refused_by_name_and_the_filter_is_not() -> None:
    # an input from outside (an FMU host's) has no known derivative: exact = true cannot follow it
    m = st.Model.from_modelica(SPEED_DRIVE)
    del m.components["ramp"]
    m.connections = [c for c in m.connections if "ramp.y" not in c]
    m.input("speed.w_ref", start=1.0)
    with pytest.raises(st.StictionError, match=r"'speed'.*'w_ref'.*model input 'speed.w_ref'"):
        m.simulate()
    m.set("speed.exact", False)
    np.testing.assert_allclose(m.simulate()["inertia.w"], 1.0, atol=1e-12)


def test_a_sweep_of_f_crit_moves_the_filters_rise_time_as_its_closed_form() -> None:
    # w = 3·(1 − exp(−2π f_crit (t − 0.1))) reaches 2.85 (95 %) at 0.1 + ln 20 / (2π f_crit)
    m = st.Model.from_modelica(FILTERED)
    f_crits = [1.0, 2.0, 5.0]
    result = st.sweep(m, {"speed.f_crit": f_crits}, ["time_of(inertia.w > 2.85)"], progress=False, workers=1)
    assert list(result.table["status"]) == ["ok"] * 3
    for f, t95 in zip(f_crits, result.table["time_of(inertia.w > 2.85)"], strict=True):
        assert t95 == pytest.approx(0.1 + math.log(20) / (2 * math.pi * f), abs=2e-3)


def test_an_fmu_with_a_speed_source_runs_in_fmpy_as_simulate(tmp_path: Path) -> None:
    fmpy = pytest.importorskip("fmpy")
    m = st.Model.from_modelica(FILTERED)
    fmu = m.to_fmu(tmp_path / "speed.fmu", outputs=["inertia.w"])
    out = fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.01)
    ref = m.simulate()
    # the reference on the FMU's grid (its own grid is ten times finer)
    want = np.interp(out["time"], ref.time, ref["inertia.w"])
    assert np.max(np.abs(out["inertia.w"] - want)) < 2e-4
