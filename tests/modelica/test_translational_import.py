"""The translational domain read from Modelica: MSL's Translational classes map to stiction's
``Translational.*`` types, the domain of a port is in the catalogue, and a connect between a
rotational and a translational flange is refused at its place with both ports named."""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st
from stiction.model.catalogue import catalogue

HEAD = "within Modelica.Mechanics.Rotational.Examples;\nmodel M\n"
BODY = """  Rotational.Components.Inertia J(J=0.5, w(start=0, fixed=true));
  Rotational.Sources.ConstantTorque torque(tau_constant=2);
  Rotational.Components.IdealRollingWheel wheel(radius=0.2);
  Modelica.Mechanics.Translational.Components.Mass car(m=10, s(start=1, fixed=true));
equation
  connect(torque.flange, J.flange_a);
  connect(J.flange_b, wheel.flangeR);
"""


def test_a_wheel_rolling_a_mass_from_modelica_accelerates_at_the_closed_form() -> None:
    m = st.Model.from_modelica(HEAD + BODY + "  connect(wheel.flangeT, car.flange_a);\nend M;")
    assert m.components["car"].type == "Translational.Mass"
    r = m.simulate(StopTime=1.0, Tolerance=1e-10)
    a = 2 * 0.2 / (0.5 + 10 * 0.2**2)
    assert np.allclose(r["car.a"], a, rtol=1e-9, atol=0)
    # the mass starts where it is told; MSL's row phi·radius = s holds from the start, so the
    # inertia's free start angle follows it
    assert r["car.s"][-1] == pytest.approx(1 + a / 2, rel=1e-9)
    assert r["J.phi"][0] == pytest.approx(1 / 0.2, rel=1e-12)


def test_a_rotational_flange_connected_to_a_translational_one_is_refused_with_both_named() -> None:
    text = HEAD + BODY + "  connect(J.flange_b, car.flange_a);\nend M;"
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text)
    message = str(info.value)
    for words in ["10:3", "'J.flange_b'", "translational flange 'car.flange_a'", "IdealRollingWheel"]:
        assert words in message, message


def test_the_catalogue_gives_each_flange_its_domain() -> None:
    ports = {p.name: p.kind for p in catalogue()["IdealRollingWheel"].ports}
    assert ports == {
        "flangeR": "flange",
        "flangeT": "translational flange",
        "supportR": "flange",
        "supportT": "translational flange",
    }
    units = {v.name: v.unit for v in catalogue()["Translational.Mass"].variables}
    assert units["a"] == "m/s2" and units["flange_a.f"] == "N" and units["s"] == "m"
    assert {v.name: v.unit for v in catalogue()["Inertia"].variables}["a"] == "rad/s2"


def test_a_mass_length_from_modelica_places_its_flanges_and_round_trips() -> None:
    """MSL's PartialRigid: flange_a.s = s - L/2, flange_b.s = s + L/2, held by a Fixed at s0."""
    text = """model Held
  Modelica.Mechanics.Translational.Components.Fixed fixed(s0=0.5);
  Modelica.Mechanics.Translational.Components.Mass body(m=2, L=1.5);
  Modelica.Mechanics.Translational.Sources.ConstantForce push(f_constant=3);
  Modelica.Mechanics.Translational.Components.Mass free(m=1, L=3, v(start=2, fixed=true));
  Modelica.Mechanics.Translational.Sources.LinearSpeedDependentForce drag(
    f_nominal=-1, v_nominal=1, ForceDirection=false);
equation
  connect(fixed.flange, body.flange_a);
  connect(push.flange, body.flange_b);
  connect(drag.flange, free.flange_a);
end Held;
"""
    m = st.Model.from_modelica(text)
    r = m.simulate(StopTime=1.0, Tolerance=1e-10)
    assert r["body.s"][-1] == 1.25 and r["body.flange_b.s"][-1] == 2.0
    # the push on flange_b is held at flange_a: body.flange_a.f = -3, the ground takes +3
    assert r["body.flange_a.f"][-1] == pytest.approx(-3.0) and r["fixed.flange.f"][-1] == pytest.approx(3.0)
    assert r["free.v"][-1] == pytest.approx(2 * np.exp(-1.0), rel=1e-8)  # m·v' = -v
    assert r["free.flange_a.s"][-1] == pytest.approx(r["free.s"][-1] - 1.5, abs=1e-12)
    again = st.Model.from_modelica(m.to_modelica()).simulate(StopTime=1.0, Tolerance=1e-10)
    assert np.array_equal(again["free.s"], r["free.s"])
