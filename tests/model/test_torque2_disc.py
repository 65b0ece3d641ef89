"""Torque2 (a torque between two flanges) and Disc (a rigid angle offset without inertia), in
closed form.

Torque2 with a constant input tau between J1 (flange_a) and J2 (flange_b), both at rest:
``w2 = tau·t/J2``, ``w1 = −tau·t/J1`` (the reaction), the total angular momentum stays 0.
Disc(deltaPhi) between an inertia and a spring: flange_b is flange_a turned by deltaPhi, so
the spring sees that angle, and the inertia oscillates about −deltaPhi.
"""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st


def test_torque2_drives_flange_b_and_reacts_on_flange_a() -> None:
    m = st.Model("t2")
    m.add("tau", st.Constant(k=3.0))
    m.add("torque", st.Torque2())
    m.add("J1", st.Inertia(J=2.0, phi=0.0, w=0.0))
    m.add("J2", st.Inertia(J=0.5, phi=0.0, w=0.0))
    m.connect("tau.y", "torque.tau")
    m.connect("torque.flange_a", "J1.flange_b")
    m.connect("torque.flange_b", "J2.flange_a")
    r = m.simulate(StopTime=1.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["J2.w"], 3.0 * t / 0.5, atol=1e-9)
    np.testing.assert_allclose(r["J1.w"], -3.0 * t / 2.0, atol=1e-9)
    np.testing.assert_allclose(r["torque.flange_a.tau"], 3.0)
    np.testing.assert_allclose(r["torque.flange_b.tau"], -3.0)
    np.testing.assert_allclose(2.0 * r["J1.w"] + 0.5 * r["J2.w"], 0.0, atol=1e-9)
    # the work the pair does is the kinetic energy both gain
    np.testing.assert_allclose(
        r["system.sourceWork"], 0.5 * (2.0 * r["J1.w"] ** 2 + 0.5 * r["J2.w"] ** 2), rtol=1e-6, atol=1e-9
    )


DELTA = 0.3


def test_disc_turns_flange_b_by_delta_phi() -> None:
    """J — disc — spring — fixed: the spring is unstretched at J.phi = −deltaPhi."""
    m = st.Model("disc")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.add("disc", st.Disc(deltaPhi=DELTA))
    m.add("spring", st.Spring(c=4.0))
    m.add("fixed", st.Fixed())
    m.connect("J.flange_b", "disc.flange_a")
    m.connect("disc.flange_b", "spring.flange_a")
    m.connect("spring.flange_b", "fixed.flange")
    r = m.simulate(StopTime=2.0, Interval=0.01, Tolerance=1e-9)
    t = r.time
    # J·phi'' = −c·(phi + deltaPhi): phi = −deltaPhi + deltaPhi·cos(2t)
    np.testing.assert_allclose(r["J.phi"], -DELTA + DELTA * np.cos(2.0 * t), atol=1e-7)
    np.testing.assert_allclose(r["spring.phi_rel"], -(r["J.phi"] + DELTA), atol=1e-9)
    np.testing.assert_allclose(r["disc.phi"], r["J.phi"] + DELTA / 2, atol=1e-9)
    np.testing.assert_allclose(r["disc.flange_a.tau"], -r["disc.flange_b.tau"], atol=1e-9)


def test_disc_and_torque2_import_from_modelica() -> None:
    text = """
model DiscAndTorque2
  Modelica.Mechanics.Rotational.Components.Inertia J(J=1, phi(fixed=true, start=0), w(fixed=true, start=0));
  Modelica.Mechanics.Rotational.Components.Disc disc(deltaPhi=0.3);
  Modelica.Mechanics.Rotational.Components.Spring spring(c=4);
  Modelica.Mechanics.Rotational.Components.Fixed fixed;
  Modelica.Mechanics.Rotational.Sources.Torque2 torque;
  Modelica.Blocks.Sources.Constant zero(k=0);
equation
  connect(J.flange_b, disc.flange_a);
  connect(disc.flange_b, spring.flange_a);
  connect(spring.flange_b, fixed.flange);
  connect(torque.flange_a, fixed.flange);
  connect(torque.flange_b, J.flange_a);
  connect(zero.y, torque.tau);
  annotation (experiment(StopTime=2, Interval=0.01));
end DiscAndTorque2;
"""
    model = st.Model.from_modelica(text)
    assert st.Model.from_modelica(model.to_modelica()) == model
    r = model.simulate()
    assert r["J.phi"].min() == pytest.approx(-2 * DELTA, abs=1e-4)
