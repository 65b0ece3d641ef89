"""Quantities with units where a number is typed (issue 29): ``"20 kN"``, ``"1500 rpm"``,
``"20 degC"`` for Real parameters and start values, converted once to the catalogue's unit
when the component is built (Python, a model file, ``Model.set``, a run's overrides); a
quantity of the wrong kind names the component, the parameter, what it is and what was
wanted. MSL's display units show in the summaries and on plot axes."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import stiction as st
from stiction.model.quantities import in_display_unit, to_si

RPM = 2 * math.pi / 60


def test_python_components_take_quantities_in_si() -> None:
    j = st.Inertia(J="2 kg*m^2", w="1500 rpm")
    assert j.params == {"J": 2.0, "w": pytest.approx(1500 * RPM)}
    assert st.Brake(fn_max="20 kN").params == {"fn_max": 20000.0}
    assert st.HeatCapacitor(C=1.0, T="20 degC").params["T"] == pytest.approx(293.15)  # an offset unit
    assert st.Spring(c="500 N*m/deg").params["c"] == pytest.approx(500 * 180 / math.pi)
    assert st.Step(startTime="250 ms").params == {"startTime": 0.25}
    guess = st.Inertia(J=1.0, w={"start": "60 rpm", "fixed": False})
    assert guess.params["w"] == {"start": pytest.approx(2 * math.pi), "fixed": False}
    assert st.Inertia(J="3").params == {"J": 3.0}  # a bare number is a number, as everywhere


def test_a_parameter_in_degc_takes_degc() -> None:
    """Celsius.FixedTemperature declares degC: 20 degC stays 20, 300 K becomes 26.85."""
    assert st.Component("Celsius.FixedTemperature", {"T": "20 degC"}).params == {"T": 20.0}
    assert st.Component("Celsius.FixedTemperature", {"T": "300 K"}).params["T"] == pytest.approx(26.85)


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (
            lambda: st.Brake(fn_max="20 km/h"),
            r"^Brake: parameter 'fn_max': '20 km/h' is a speed, not a force \[N\]$",
        ),
        (lambda: st.Inertia(J=1.0, w="2 Hz"), r"'2 Hz' is a frequency, not an angular velocity \[rad/s\]"),
        (lambda: st.Spring(c="500 N*m"), r"is a torque or an energy, not a rotational stiffness \[N.m/rad\]"),
        (lambda: st.Inertia(J="2 kg"), r"'2 kg' is a mass, not a moment of inertia \[kg.m2\]"),
        (lambda: st.Brake(fn_max="20 kNN"), r"'20 kNN': 'kNN' is not a unit pint knows"),
        (lambda: st.Brake(fn_max="0.9*F0"), r"'0.9\*F0' is not a number with a unit .*expr"),
        (lambda: st.Inertia(J="-2 kg*m^2"), r"parameter 'J': must be >= 0, got -2$"),  # then the range
    ],
)
def test_a_quantity_of_the_wrong_kind_is_refused(make, message: str) -> None:
    with pytest.raises(st.ModelError, match=message):
        make()


def test_a_model_file_takes_quantities_and_names_the_component() -> None:
    text = """name = "m"
[components]
J = { type = "Inertia", J = "2 kg*m^2", w = "1500 rpm" }
disc = { type = "HeatCapacitor", C = "2.3 kJ/K", T = { start = "20 degC", fixed = true } }
"""
    m = st.Model.loads(text)
    assert m["J"].params == {"J": 2.0, "w": pytest.approx(1500 * RPM)}
    assert m["disc"].params == {"C": 2300.0, "T": {"start": pytest.approx(293.15), "fixed": True}}
    assert "w = 157.07963267948966" in m.to_toml()  # saved in SI
    bad = 'name = "m"\n[components]\nbrake = { type = "Brake", fn_max = "20 km/h" }\n'
    with pytest.raises(
        st.ModelError,
        match=r"component 'brake' \(Brake\): parameter 'fn_max': '20 km/h' is a speed, not a force",
    ):
        st.Model.loads(bad)


def test_set_converts_and_names_the_component() -> None:
    m = st.Model("m").add("brake", st.Brake(fn_max=100.0))
    m.set("brake.fn_max", "20 kN")
    assert m["brake"].params["fn_max"] == 20000.0
    with pytest.raises(
        st.ModelError, match=r"^component 'brake' \(Brake\): parameter 'fn_max': '1 m' is a length"
    ):
        m.set("brake.fn_max", "1 m")
    assert m["brake"].params["fn_max"] == 20000.0  # unchanged


def _flywheel() -> st.Model:
    m = st.Model("flywheel")
    m.add("J", st.Inertia(J=2.0, w=10.0))
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=[[0, 0.5]]))
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment.update(StopTime=1.0, Interval=0.01)
    return m


def test_run_overrides_and_top_level_parameters_take_quantities() -> None:
    m = _flywheel()
    r = m.simulate(params={"J.w": "60 rpm", "StopTime": "500 ms"})
    assert r["J.w"][0] == pytest.approx(2 * math.pi) and r.time[-1] == pytest.approx(0.5)
    m.parameters["w0"] = "60 rpm"  # no declared unit: SI base units (rad/s)
    m.set("J.w", st.expr("w0"))
    assert m.simulate()["J.w"][0] == pytest.approx(2 * math.pi)
    sim = m.simulation()
    sim.advance_to(0.1)
    sim.set_parameter("brake.fn_max", "0.2 kN")
    sim.run()
    assert sim.result()["brake.fn"][-1] == pytest.approx(200.0)  # fn_max * f_normalized


def test_describe_shows_msl_display_units() -> None:
    text = str(st.describe("HeatCapacitor"))
    assert "T : start value [K] (displayUnit degC), start (a guess unless given) 293.15 (20 degC)" in text
    assert "- T [K] (displayUnit degC)" in text
    assert "phi_rel0 : Real [rad] (displayUnit deg)" in str(st.describe("Spring"))
    assert "(displayUnit" not in str(st.describe("Brake")).split("Variables")[0]  # N, rad/s: none
    assert in_display_unit(np.array([273.15, 293.15]), "K")[1] == "degC"
    np.testing.assert_allclose(in_display_unit(np.array([273.15, 293.15]), "K")[0], [0.0, 20.0])


def test_plots_show_temperatures_in_degc() -> None:
    m = st.Model("heat").add("disc", st.HeatCapacitor(C=10.0, T="20 degC"))
    fig = m.simulate(StopTime=0.1).plot("disc.T")
    axis = fig.axes[0]
    assert axis.get_ylabel() == "disc.T [degC]"
    np.testing.assert_allclose(axis.lines[0].get_ydata(), 20.0)


def test_to_si_reads_modelica_units() -> None:
    assert to_si("1 t*m^2", "kg.m2", "x") == 1000.0
    assert to_si("1 kN*m*s/rad", "N.m.s/rad", "x") == 1000.0
    assert to_si("50 %", "1", "x") == 0.5 and to_si("50 %", "%", "x") == 50.0
    assert to_si("1 kW/K", "W/K", "x") == 1000.0


def test_importing_stiction_does_not_load_pint() -> None:
    code = "import sys, stiction as st; st.Inertia(J=1.0, w=2.0); print('pint' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_top_level_quantity_is_exported_as_its_si_number() -> None:
    m = _flywheel()
    m.parameters["w0"] = "60 rpm"
    m.set("J.w", st.expr("w0"))
    assert "parameter Real w0 = 6.283185307179586;" in m.to_modelica()
    assert st.Model.from_modelica(m.to_modelica()).simulate()["J.w"][0] == pytest.approx(2 * math.pi)
