"""EddyCurrentTorque: MSL's EddyCurrentBrake in the 2e-3 tube, its energy balance, and Kloss'
equation in closed form.

With ``tau = 2·tau_nominal·w_n/(1 + w_n²)``, ``w_n = w/W`` (``W = w_nominal·(1 + alphaRef·(T −
TRef))``) braking an inertia J, ``J·W·(ln w + w²/(2W²))`` falls at ``2·tau_nominal(t)``:
``F(w(t)) − F(w0) = −2·∫tau_nominal dt``.
"""

from __future__ import annotations

import numpy as np
import pytest
from paths import MSL_DATA, MSL_EXAMPLES

import stiction as st

ALPHA20_COPPER = 3.92e-3
RUN = {"StopTime": 1.0, "Interval": 0.001, "Tolerance": 1e-8}


def test_eddy_current_brake_stays_inside_the_msl_tube() -> None:
    r = st.Model.load(MSL_EXAMPLES / "EddyCurrentBrake.toml").simulate()
    signals = MSL_DATA / "EddyCurrentBrake.signals.txt"
    report = st.compare(r, MSL_DATA / "EddyCurrentBrake.csv", tolerance=2e-3, signals=signals)
    assert len(report) == 3
    assert report.passed, str(report)


def test_eddy_current_brake_heat_is_the_kinetic_loss() -> None:
    """Adiabatic capacitor: C·(T − T0) = ½·J·(w0² − w²) at every row, and = ∫lossPower."""
    r = st.Model.load(MSL_EXAMPLES / "EddyCurrentBrake.toml").simulate()
    heat = 1.0 * (r["heatCapacitor.T"] - 293.15)
    kinetic_loss = 0.5 * 1.0 * (20.0**2 - r["inertia.w"] ** 2)
    np.testing.assert_allclose(heat, kinetic_loss, atol=1e-6 * 200.0)
    assert heat[-1] > 199.0  # nearly all of the 200 J
    integral = np.trapezoid(r["eddyCurrentTorque.lossPower"], r.time)
    assert integral == pytest.approx(heat[-1], rel=1e-3)


def _brake(**eddy: object) -> st.Model:
    m = st.Model("brake")
    m.add("eddy", st.EddyCurrentTorque(w_nominal=10.0, **eddy))
    m.add("inertia", st.Inertia(J=2.0, phi=0.0, w=30.0))
    m.connect("eddy.flange", "inertia.flange_a")
    return m


def _kloss_integral(w: np.ndarray, j: float, w_eff: float) -> np.ndarray:
    return j * w_eff * (np.log(w) + w**2 / (2 * w_eff**2))


@pytest.mark.parametrize("temperature", [293.15, 353.15])
def test_kloss_closed_form_at_a_fixed_temperature(temperature: float) -> None:
    """No heat port: the device temperature T shifts W by (1 + alphaRef·(T − TRef))."""
    t_ref = 313.15
    r = _brake(tau_nominal=50.0, alpha20=ALPHA20_COPPER, TRef=t_ref, T=temperature).simulate(**RUN)
    alpha_ref = ALPHA20_COPPER / (1 + ALPHA20_COPPER * (t_ref - 293.15))
    w_eff = 10.0 * (1 + alpha_ref * (temperature - t_ref))
    f = _kloss_integral(r["inertia.w"], 2.0, w_eff)
    np.testing.assert_allclose(f - f[0], -2 * 50.0 * r.time, atol=1e-5 * abs(f[0]))
    # the loss is the torque times the speed, and the torque brakes
    tau = r["eddy.tau"]
    np.testing.assert_allclose(r["eddy.lossPower"], tau * r["eddy.w"], rtol=1e-12)
    assert np.all(tau > 0.0)


def test_kloss_closed_form_with_a_ramped_excitation() -> None:
    """useTau_nominalInput: tau_input ramps 0 → 100 N.m over [0.1, 0.2] s (MSL 4.1's example)."""
    m = _brake(useTau_nominalInput=True)
    m.add("ramp", st.Ramp(height=100.0, duration=0.1, startTime=0.1))
    m.connect("ramp.y", "eddy.tau_input")
    r = m.simulate(**RUN)
    t = r.time
    excitation = 100.0 * np.clip((t - 0.1) / 0.1, 0.0, 1.0)
    integral = np.concatenate(([0.0], np.cumsum(np.diff(t) * 0.5 * (excitation[1:] + excitation[:-1]))))
    f = _kloss_integral(r["inertia.w"], 2.0, 10.0)
    np.testing.assert_allclose(f - f[0], -2 * integral, atol=1e-4 * abs(f[0]))
    assert r["inertia.w"][t < 0.1].min() == pytest.approx(30.0)


def test_temperature_on_a_conductor_alone_is_refused_by_name() -> None:
    m = _brake(tau_nominal=10.0, useHeatPort=True)
    m.add("conductor", st.ThermalConductor(G=1.0))
    m.add("ambient", st.FixedTemperature(T=293.15))
    m.connect("eddy.heatPort", "conductor.port_a")
    m.connect("conductor.port_b", "ambient.port")
    with pytest.raises(st.ModelError, match=r"eddy.*heatPort.*HeatCapacitor"):
        m.simulate()


@pytest.mark.parametrize(
    ("params", "name"),
    [
        ({"w_nominal": 0.0}, "w_nominal"),
        ({"w_nominal": 1.0, "TRef": -1.0}, "TRef"),
        ({"w_nominal": 1.0, "alpha20": -1.0, "TRef": 400.0}, "alpha20"),
        ({"w_nominal": 1.0, "T": 0.0}, "T"),
    ],
)
def test_bad_parameters_are_refused_by_name(params: dict, name: str) -> None:
    text = f"""
name = "bad"
connect = [["eddy.flange", "J.flange_a"]]
[components]
eddy = {{ type = "EddyCurrentTorque", {", ".join(f"{k} = {v}" for k, v in params.items())} }}
J = {{ type = "Inertia", J = 1.0 }}
"""
    with pytest.raises(st.ModelError, match=rf"eddy.*'?\b{name}\b"):
        st.Model.loads(text).simulate()


EDDY_MO = """
model EddyCurrentBrake
  Modelica.Mechanics.Rotational.Sources.EddyCurrentTorque eddyCurrentTorque(
    useTau_nominalInput=true, tau_nominal=100, w_nominal=10, useSupport=false,
    alpha20(displayUnit="1/K") = 3.92e-3, TRef=293.15, useHeatPort=true);
  Modelica.Mechanics.Rotational.Components.Inertia inertia(phi(fixed=true, start=0), J=1,
    w(fixed=true, start=20));
  Modelica.Thermal.HeatTransfer.Components.HeatCapacitor heatCapacitor(C=1, T(fixed=true));
  Modelica.Blocks.Sources.Ramp ramp(height=100, duration=0.1, offset=0, startTime=0.1);
equation
  connect(eddyCurrentTorque.flange, inertia.flange_a);
  connect(eddyCurrentTorque.heatPort, heatCapacitor.port);
  connect(ramp.y, eddyCurrentTorque.tau_input);
  annotation (experiment(StopTime=1.0, Interval=0.001));
end EddyCurrentBrake;
"""


def test_msl_4_1_example_imports_and_heats_by_the_kinetic_loss() -> None:
    """MSL 4.1's EddyCurrentBrake (ramped excitation into tau_input) from Modelica: it round-trips,
    and the capacitor gains what the inertia loses (alpha20Copper written as its value)."""
    model = st.Model.from_modelica(EDDY_MO)
    assert st.Model.from_modelica(model.to_modelica()) == model
    r = model.simulate()
    heat = r["heatCapacitor.T"] - 293.15
    np.testing.assert_allclose(heat, 0.5 * (400.0 - r["inertia.w"] ** 2), atol=2e-4)
    assert np.all(r["eddyCurrentTorque.lossPower"][r.time < 0.1] == 0.0)
