"""InitializeFlange and Gearbox from Python and Modelica: imported in MSL's style (qualified
class names, ``stateSelect`` and nested start modifiers), round-tripped through
``to_modelica``, swept and exported as an FMU to the same results as ``Model.simulate``.

The closed forms (a flange started by signals against fixed start values, a stiff Gearbox
against its LossyGear, a lossless one against IdealGear + ElastoBacklash, the energy audit) are
in ``crates/stiction-core/tests/gearbox.rs``; here the same facts through the Python layers.
"""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest

import stiction as st

DRIVE = """
model GearboxDrive
  import Modelica.Mechanics.Rotational.Components;
  Components.Inertia motorInertia(J=0.5);
  Components.Gearbox gearbox(ratio=3, lossTable=[0, 0.9, 0.8, 0.4, 0.3; 10, 0.85, 0.75, 0.6, 0.4],
    c=5000, d=10, b=0.02, phi_rel(stateSelect=StateSelect.prefer));
  Components.Inertia load(J=4);
  Components.InitializeFlange initializeFlange(use_a_start=false, stateSelect=StateSelect.default);
  Modelica.Mechanics.Rotational.Sources.Torque torque;
  Modelica.Blocks.Sources.Sine sine(amplitude=30, f=0.5, offset=5);
  Modelica.Blocks.Sources.Constant phiStart(k=0.2);
  Modelica.Blocks.Sources.Constant wStart(k=1.5);
equation
  connect(sine.y, torque.tau);
  connect(torque.flange, motorInertia.flange_a);
  connect(motorInertia.flange_b, gearbox.flange_a);
  connect(gearbox.flange_b, load.flange_a);
  connect(initializeFlange.flange, motorInertia.flange_a);
  connect(phiStart.y, initializeFlange.phi_start);
  connect(wStart.y, initializeFlange.w_start);
  annotation (experiment(StopTime=4, Interval=0.01, Tolerance=1e-8));
end GearboxDrive;
"""


def drive() -> st.Model:
    return st.Model.from_modelica(DRIVE)


def test_imports_runs_and_round_trips() -> None:
    model = drive()
    assert st.Model.from_modelica(model.to_modelica()) == model
    r = model.simulate()
    # the motor starts where the signals say; the gear's own constraint starts the load with it
    assert r["motorInertia.phi"][0] == pytest.approx(0.2, abs=1e-15)
    assert r["motorInertia.w"][0] == pytest.approx(1.5, abs=1e-15)
    assert r["load.w"][0] == pytest.approx(0.5, abs=1e-12)
    np.testing.assert_array_equal(r["initializeFlange.flange.tau"], 0.0)
    # MSL's variables: phi_rel over the elasticity, its parts' variables under their names
    np.testing.assert_allclose(
        r["gearbox.phi_rel"], r["load.phi"] - r["gearbox.lossyGear.flange_b.phi"], atol=1e-12
    )
    np.testing.assert_allclose(
        r["gearbox.lossPower"],
        r["gearbox.lossyGear.lossPower"] + r["gearbox.elastoBacklash.lossPower"],
        atol=1e-12,
    )
    assert r["gearbox.lossPower"].max() > 1.0


def test_refusals_name_the_component_and_parameter() -> None:
    with pytest.raises(st.ModelError, match=r"initializeFlange.*use_a_start"):
        st.Model.from_modelica(DRIVE.replace("use_a_start=false, ", "")).simulate()
    fixed = DRIVE.replace("motorInertia(J=0.5)", "motorInertia(J=0.5, w(fixed=true, start=0))")
    with pytest.raises(st.ModelError, match=r"over-determined.*initializeFlange\.w_flange|motorInertia\.w"):
        st.Model.from_modelica(fixed).simulate()
    with pytest.raises(st.ModelError, match=r"gearbox.*\bb\b"):
        st.Model.from_modelica(DRIVE.replace("b=0.02", "b=-0.02")).simulate()


def test_gearbox_parameters_sweep() -> None:
    model = drive()
    result = st.sweep(model, st.grid({"gearbox.d": [0.0, 50.0]}), ["max(gearbox.w_rel)"], progress=False)
    assert list(result.table["status"]) == ["ok", "ok"]
    for _, row in result.table.iterrows():
        single = model.simulate(params={"gearbox.d": row["gearbox.d"]})
        assert row["max(gearbox.w_rel)"] == single.metric("max(gearbox.w_rel)")
    undamped, damped = result.table["max(gearbox.w_rel)"]
    assert undamped > damped


def test_fmu_matches_simulate(tmp_path: Path) -> None:
    model = drive()
    outputs = ["load.w", "gearbox.phi_rel", "motorInertia.phi"]
    fmu = model.to_fmu(tmp_path / "GearboxDrive.fmu", outputs=outputs)
    res = fmpy.simulate_fmu(str(fmu), stop_time=2.0, output_interval=0.001, output=outputs)
    r = model.simulate(StopTime=2.0, Interval=0.001)  # the FMU's grid: no interpolation error
    for name in outputs:
        ref = np.interp(res["time"], r.time, r[name])
        assert np.abs(res[name] - ref).max() < 1e-3 * np.ptp(r[name]), name


def test_support_and_heat_port_close_momentum_and_heat() -> None:
    """With useSupport and useHeatPort: the housing takes the reaction (total angular momentum is
    the motor's impulse) and the heat capacitor warms by the integrated lossPower over C."""
    m = st.Model("g")
    m.add("sine", st.Sine(amplitude=30.0, f=0.5, offset=5.0))
    m.add("motor", st.Torque())
    m.add("J1", st.Inertia(J=0.5, phi=0.0, w=0.0))
    table = [[0, 0.9, 0.8, 0.5, 0.3]]
    m.add(
        "gear",
        st.Gearbox(ratio=2.0, lossTable=table, c=5000.0, d=10.0, b=0.02, useHeatPort=True, useSupport=True),
    )
    m.add("J2", st.Inertia(J=4.0))
    m.add("house", st.Inertia(J=10.0))
    m.add("cap", st.HeatCapacitor(C=100.0, T=293.15))
    for a, b in [
        ("sine.y", "motor.tau"),
        ("motor.flange", "J1.flange_a"),
        ("J1.flange_b", "gear.flange_a"),
        ("gear.flange_b", "J2.flange_a"),
        ("gear.support", "house.flange_a"),
        ("gear.heatPort", "cap.port"),
    ]:
        m.connect(a, b)
    r = m.simulate(StopTime=2.0, Interval=0.001, Tolerance=1e-9)
    momentum = 0.5 * r["J1.w"] + 4.0 * r["J2.w"] + 10.0 * r["house.w"]
    impulse = np.concatenate([[0.0], np.cumsum(np.diff(r.time) * 0.5 * (r["sine.y"][1:] + r["sine.y"][:-1]))])
    np.testing.assert_allclose(momentum, impulse, atol=1e-4)
    heat = np.trapezoid(r["gear.lossPower"], r.time)
    assert heat > 10.0
    assert r["cap.T"][-1] - 293.15 == pytest.approx(heat / 100.0, rel=1e-4)
    np.testing.assert_allclose(r["gear.heatPort.Q_flow"], -r["gear.lossPower"])
