"""GeneralTorqueToAngleAdaptor and GeneralAngleToTorqueAdaptor (MSL's generic adaptor names:
p, pder, pder2, f) against the same closed forms as the plain adaptors: a prescribed sin t on a
spring-damper needs f = c·sin t + d·cos t, and a constant f = 3 on an inertia J = 2 gives a
parabola (MSL: flange.tau = f). The translational pair (GeneralPositionToForceAdaptor,
GeneralForceToPositionAdaptor) the same on a mass and a translational spring-damper."""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

C, D, J = 50.0, 2.0, 2.0
F = 1.0 / (2.0 * math.pi)


def test_general_angle_to_torque_on_a_spring_damper() -> None:
    m = st.Model("general_att")
    m.add("phi", st.Sine(amplitude=1.0, f=F))
    m.add("w", st.Sine(amplitude=1.0, f=F, phase=math.pi / 2))
    m.add("a", st.Sine(amplitude=-1.0, f=F))
    m.add("adaptor", st.GeneralAngleToTorqueAdaptor())
    m.add("sd", st.SpringDamper(c=C, d=D))
    m.add("ground", st.Fixed())
    m.connect("phi.y", "adaptor.p")
    m.connect("w.y", "adaptor.pder")
    m.connect("a.y", "adaptor.pder2")
    m.connect("adaptor.flange", "sd.flange_a")
    m.connect("sd.flange_b", "ground.flange")
    r = m.simulate(StopTime=6.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.p"], np.sin(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.pder"], np.cos(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.f"], C * np.sin(t) + D * np.cos(t), rtol=0, atol=1e-11)
    np.testing.assert_allclose(r["adaptor.flange.tau"], -r["adaptor.f"], rtol=0, atol=1e-11)


def test_general_torque_to_angle_on_an_inertia_is_a_parabola() -> None:
    m = st.Model("general_tta")
    m.add("tau", st.Constant(k=3.0))
    m.add("adaptor", st.GeneralTorqueToAngleAdaptor())
    m.add("J", st.Inertia(J=J, phi=0.0, w=0.0))
    m.connect("tau.y", "adaptor.f")
    m.connect("adaptor.flange", "J.flange_b")
    r = m.simulate(StopTime=2.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.pder2"], -1.5, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.pder"], -1.5 * t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.p"], -0.75 * t**2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.flange.tau"], 3.0, rtol=0, atol=0)


def test_use_pder2_needs_use_pder() -> None:
    """MSL: pder2 exists only with pder; without pder the flange follows p alone."""
    m = st.Model("p_only")
    m.add("phi", st.Constant(k=0.5))
    m.add("adaptor", st.GeneralAngleToTorqueAdaptor(use_pder=False, use_pder2=True))
    m.add("J", st.Inertia(J=1.0))
    m.connect("phi.y", "adaptor.p")
    m.connect("adaptor.flange", "J.flange_a")
    r = m.simulate(StopTime=1.0, Interval=0.1)
    assert "adaptor.pder" not in r.names and "adaptor.pder2" not in r.names
    np.testing.assert_allclose(r["J.phi"], 0.5, atol=1e-12)
    with pytest.raises(st.ModelError, match="pder2"):
        m.connect("phi.y", "adaptor.pder2")
        m.simulate(StopTime=1.0)


# Translational's GeneralPositionToForceAdaptor and GeneralForceToPositionAdaptor: the same
# adaptors on a translational flange (MSL: s, v, a, f as p, pder, pder2, f).
tr = st.translational


def test_general_position_to_force_on_a_spring_damper() -> None:
    """A prescribed s = sin t on a spring-damper needs f = c·sin t + d·cos t (MSL: y =
    flange.f, the force the flange takes: the adaptor's flange.f is −f)."""
    m = st.Model("general_ptf")
    m.add("s", st.Sine(amplitude=1.0, f=F))
    m.add("v", st.Sine(amplitude=1.0, f=F, phase=math.pi / 2))
    m.add("a", st.Sine(amplitude=-1.0, f=F))
    m.add("adaptor", tr.GeneralPositionToForceAdaptor())
    m.add("sd", tr.SpringDamper(c=C, d=D))
    m.add("ground", tr.Fixed())
    m.connect("s.y", "adaptor.p")
    m.connect("v.y", "adaptor.pder")
    m.connect("a.y", "adaptor.pder2")
    m.connect("adaptor.flange", "sd.flange_a")
    m.connect("sd.flange_b", "ground.flange")
    r = m.simulate(StopTime=6.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.p"], np.sin(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.pder"], np.cos(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.f"], C * np.sin(t) + D * np.cos(t), rtol=0, atol=1e-11)
    np.testing.assert_allclose(r["adaptor.flange.f"], -r["adaptor.f"], rtol=0, atol=1e-11)
    np.testing.assert_allclose(r["sd.s_rel"], -np.sin(t), rtol=0, atol=1e-13)


def test_general_force_to_position_on_a_mass_is_a_parabola() -> None:
    """f = 3 N is the flange's cut force (MSL: u = flange.f), so it pushes the mass m = 2 at
    −1.5 m/s²."""
    m = st.Model("general_ftp")
    m.add("f", st.Constant(k=3.0))
    m.add("adaptor", tr.GeneralForceToPositionAdaptor())
    m.add("mass", tr.Mass(m=J, s=0.0, v=0.0))
    m.connect("f.y", "adaptor.f")
    m.connect("adaptor.flange", "mass.flange_b")
    r = m.simulate(StopTime=2.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.pder2"], -1.5, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.pder"], -1.5 * t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.p"], -0.75 * t**2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.flange.f"], 3.0, rtol=0, atol=0)
    np.testing.assert_allclose(r["mass.v"], -1.5 * t, rtol=0, atol=1e-12)


def test_translational_adaptors_have_a_translational_flange() -> None:
    """Joined to a rotational flange, the adaptor is refused by name; without pder the
    position alone moves the flange."""
    m = st.Model("wrong_domain")
    m.add("s", st.Constant(k=0.5))
    m.add("adaptor", tr.GeneralPositionToForceAdaptor(use_pder=False))
    m.add("J", st.Inertia(J=1.0))
    m.connect("s.y", "adaptor.p")
    with pytest.raises(st.ModelError, match="translational flange 'adaptor.flange'"):
        m.connect("adaptor.flange", "J.flange_a")
    ok = st.Model("position_only")
    ok.add("s", st.Constant(k=0.5))
    ok.add("adaptor", tr.GeneralPositionToForceAdaptor(use_pder=False))
    ok.add("mass", tr.Mass(m=1.0))
    ok.connect("s.y", "adaptor.p")
    ok.connect("adaptor.flange", "mass.flange_a")
    r = ok.simulate(StopTime=1.0, Interval=0.1)
    assert "adaptor.pder" not in r.names
    np.testing.assert_allclose(r["mass.s"], 0.5, atol=1e-12)


def test_translational_adaptors_round_trip_through_modelica() -> None:
    m = st.Model("adaptors_mo")
    m.add("f", st.Constant(k=3.0))
    m.add("adaptor", tr.GeneralForceToPositionAdaptor(use_pder2=False))
    m.add("mass", tr.Mass(m=J, s=0.0, v=0.0))
    m.connect("f.y", "adaptor.f")
    m.connect("adaptor.flange", "mass.flange_b")
    text = m.to_modelica()
    assert "Modelica.Mechanics.Translational.Components.GeneralForceToPositionAdaptor" in text
    back = st.Model.from_modelica(text)
    assert back.components["adaptor"].type == "Translational.GeneralForceToPositionAdaptor"
    a, b = m.simulate(StopTime=1.0), back.simulate(StopTime=1.0)
    np.testing.assert_array_equal(a["adaptor.p"], b["adaptor.p"])
    assert "adaptor.pder2" not in b.names
