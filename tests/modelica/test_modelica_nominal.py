"""Nominals of state variables: ``w_rel(nominal=…)``, ``phi(nominal=…)`` and MSL's ``phi_nominal``
import as the start value's ``nominal``, export back, and scale the integrator's error control
(absolute tolerance Tolerance·nominal on the states the variable is made of)."""

from __future__ import annotations

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

# An inertia on a spring-damper to ground (100 rad/s, damping ratio 0.001) released at
# w = 1e-4 rad/s: its angle stays within 1e-6 rad, its speed within 1e-4 rad/s.
OSCILLATOR = """
model SmallOscillation
  Modelica.Mechanics.Rotational.Components.Fixed ground;
  Modelica.Mechanics.Rotational.Components.SpringDamper spring(c=1e4, d=0.2{phi}
    phi_rel(fixed=true, start=0{phi_rel}), w_rel(fixed=true, start=1e-4{w_rel}));
  Modelica.Mechanics.Rotational.Components.Inertia J(J=1);
equation
  connect(ground.flange, spring.flange_a);
  connect(spring.flange_b, J.flange_a);
  annotation (experiment(StopTime=5, Interval=0.01));
end SmallOscillation;
"""


def _oscillator(phi: str = ",", phi_rel: str = "", w_rel: str = "") -> str:
    return OSCILLATOR.format(phi=phi, phi_rel=phi_rel, w_rel=w_rel)


def _speed_error(result: st.Result) -> float:
    """Largest error of ``J.w`` against the damped oscillation, relative to its start."""
    sigma, t = 0.1, result.time
    omega = np.sqrt(1e4 - sigma**2)
    exact = 1e-4 * np.exp(-sigma * t) * (np.cos(omega * t) - sigma / omega * np.sin(omega * t))
    return float(np.abs(result["J.w"] - exact).max() / 1e-4)


def test_nominals_resolve_a_small_oscillation_at_the_default_tolerance() -> None:
    plain = st.Model.from_modelica(_oscillator())
    scaled = st.Model.from_modelica(_oscillator(", phi_nominal=1e-6,", w_rel=", nominal=1e-4"))
    assert scaled.components["spring"].params["phi_rel"]["nominal"] == 1e-6
    assert scaled.components["spring"].params["w_rel"]["nominal"] == 1e-4
    assert _speed_error(plain.simulate()) > 1e-2  # an absolute 1e-6 does not resolve it
    assert _speed_error(scaled.simulate()) < 1e-3


def test_the_nominal_round_trips_through_to_modelica() -> None:
    model = st.Model.from_modelica(_oscillator(phi_rel=", nominal=1e-6", w_rel=", nominal=1e-4"))
    again = st.Model.from_modelica(model.to_modelica())
    assert again.components["spring"].params == model.components["spring"].params
    np.testing.assert_array_equal(again.simulate()["J.w"], model.simulate()["J.w"])


def test_phi_nominal_is_msl_s_nominal_of_phi_rel() -> None:
    """``nominal = if phi_nominal >= eps then phi_nominal else 1``; a modifier of ``phi_rel``'s
    own nominal overrides that binding."""
    params = lambda text: st.Model.from_modelica(text).components["spring"].params["phi_rel"]
    assert params(_oscillator(", phi_nominal=0,"))["nominal"] == 1.0
    assert params(_oscillator(", phi_nominal=1e-3,", phi_rel=", nominal=1e-5"))["nominal"] == 1e-5
    short = _oscillator(", phi_nominal=1e-3,").replace(
        "phi_rel(fixed=true, start=0)", "phi_rel(start=0, fixed=true)"
    )
    assert params(short) == {"start": 0.0, "fixed": True, "nominal": 1e-3}


@pytest.mark.parametrize("bad", ["0", "-1e-4"])
def test_a_nominal_that_is_not_positive_is_refused_at_its_place(bad: str) -> None:
    text = _oscillator(w_rel=f", nominal={bad}")
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text)
    ((line, col, message),) = info.value.errors
    at = text.index(f"nominal={bad}")
    assert (line, col) == (text.count("\n", 0, at) + 1, at - text.rfind("\n", 0, at))
    assert "spring.w_rel" in message and "nominal must be a positive number" in message


def test_a_negative_phi_nominal_is_refused() -> None:
    with pytest.raises(st.ModelError, match="spring.phi_nominal"):
        st.Model.from_modelica(_oscillator(", phi_nominal=-1,"))


@pytest.mark.parametrize("bad", [0.0, -1.0])
def test_the_python_api_refuses_a_nominal_that_is_not_positive(bad: float) -> None:
    model = st.Model.from_modelica(_oscillator())
    model.components["J"] = st.Inertia(J=1.0, w={"start": 0.0, "fixed": False, "nominal": bad})
    with pytest.raises(st.ModelError, match=r"J.*'w'.*'nominal' must be positive"):
        model.simulate()


def test_elastic_bearing_takes_msl_s_nominal_and_no_tolerance() -> None:
    mo = st.Model.from_modelica(MSL_EXAMPLES / "ElasticBearing.mo")
    toml = st.Model.load(MSL_EXAMPLES / "ElasticBearing.toml")
    assert mo.components["springDamper"].params["w_rel"]["nominal"] == 1e-4
    assert toml.components["springDamper"].params["w_rel"]["nominal"] == 1e-4
    assert "Tolerance" not in mo.experiment and "Tolerance" not in toml.experiment


def test_a_start_value_set_for_a_run_keeps_its_nominal() -> None:
    """``params=`` sets the value; the nominal the model gave the variable still scales the
    error control (without it, ElasticBearing's housing would leave the tube)."""
    model = st.Model.load(MSL_EXAMPLES / "ElasticBearing.toml")
    base, again = model.simulate(), model.simulate(params={"springDamper.w_rel": 0.0})
    assert again.stats["steps"] == base.stats["steps"]
    np.testing.assert_array_equal(again["springDamper.w_rel"], base["springDamper.w_rel"])
