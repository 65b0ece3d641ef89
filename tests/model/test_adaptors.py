"""MSL's flange adaptors against closed forms.

AngleToTorqueAdaptor prescribes the motion of its flange from phi, w, a (a constraint whose
right-hand side is the input a, with the angle and speed set from phi and w) and reports the
torque that motion needs: with phi = sin t it is c·phi + d·w on a spring-damper and J·a on an
inertia, exactly. A brake on the prescribed shaft slides with the prescribed speed and turns at
its zeros. A new input value moves the flange at once (an input event). TorqueToAngleAdaptor is
a torque on its flange (MSL: flange.tau = tau) and reports the flange's phi, w, a: a parabola on
a free inertia. Bad input names the component and the parameter.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import stiction as st

C, D, J = 50.0, 2.0, 2.0
F = 1.0 / (2.0 * math.pi)  # Sine frequency of sin(t)


def prescribed(name: str = "prescribed", **adaptor: bool) -> st.Model:
    """phi = sin t, w = cos t, a = −sin t drive an AngleToTorqueAdaptor's flange."""
    m = st.Model(name)
    m.add("phi", st.Sine(amplitude=1.0, f=F))
    m.add("w", st.Sine(amplitude=1.0, f=F, phase=math.pi / 2))
    m.add("a", st.Sine(amplitude=-1.0, f=F))
    m.add("adaptor", st.AngleToTorqueAdaptor(**adaptor))
    m.add("ground", st.Fixed())
    m.connect("phi.y", "adaptor.phi")
    if adaptor.get("use_w", True) or adaptor.get("use_a", True):
        m.connect("w.y", "adaptor.w")
    if adaptor.get("use_a", True):
        m.connect("a.y", "adaptor.a")
    return m


def with_spring_damper(m: st.Model) -> st.Model:
    m.add("sd", st.SpringDamper(c=C, d=D))
    m.connect("adaptor.flange", "sd.flange_a")
    m.connect("sd.flange_b", "ground.flange")
    return m


def test_angle_to_torque_on_a_spring_damper_needs_c_phi_plus_d_w() -> None:
    """No inertia on the shaft: the adaptor's row holds it; tau = c·sin t + d·cos t exactly."""
    m = with_spring_damper(prescribed())
    m.check()
    r = m.simulate(StopTime=6.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.phi"], np.sin(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.w"], np.cos(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.a"], -np.sin(t), rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.tau"], C * np.sin(t) + D * np.cos(t), rtol=0, atol=1e-11)
    # MSL: tau = −flange.tau
    np.testing.assert_allclose(r["adaptor.flange.tau"], -r["adaptor.tau"], rtol=0, atol=1e-11)
    audit = r.audit()
    assert audit.ok(), audit.worst


def test_angle_to_torque_on_an_inertia_needs_j_a() -> None:
    """The acceleration row's right-hand side is the input a: tau = J·a + c·phi + d·w."""
    m = with_spring_damper(prescribed())
    m.add("J", st.Inertia(J=J))
    m.connect("adaptor.flange", "J.flange_a")
    r = m.simulate(StopTime=6.0, Interval=0.01, Tolerance=1e-10)
    t = r.time
    exact = -J * np.sin(t) + C * np.sin(t) + D * np.cos(t)
    np.testing.assert_allclose(r["adaptor.tau"], exact, rtol=0, atol=1e-10)
    np.testing.assert_allclose(r["J.w"], np.cos(t), rtol=0, atol=1e-13)
    audit = r.audit()
    assert audit.ok(), audit.worst
    # the adaptor is the only source: its work is the kinetic and spring energy plus the losses
    # (the work is an integral the integrator carries, so to its tolerance)
    energy = 0.5 * J * np.cos(t) ** 2 + 0.5 * C * np.sin(t) ** 2 - 0.5 * J
    dissipated = D * (t / 2 + np.sin(2 * t) / 4)
    np.testing.assert_allclose(r["system.sourceWork"], energy + dissipated, rtol=1e-9, atol=1e-9)


def test_a_brake_on_the_prescribed_shaft_slides_with_its_speed() -> None:
    """Speed cos t: the brake slides forward, turns at t = π/2 and 3π/2 (exact friction events
    at the prescribed speed's zeros), and the adaptor supplies J·a plus its sliding torque."""
    m = prescribed("braked")
    m.add("J", st.Inertia(J=J))
    m.add("brake", st.Brake(mu_pos=[[0.0, 0.5]], fn_max=100.0, cgeo=1.0))
    m.add("force", st.Constant(k=1.0))
    m.connect("adaptor.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("force.y", "brake.f_normalized")
    r = m.simulate(StopTime=5.0, Interval=0.01)
    turns = [(e.time, e.new_mode) for e in r.events if e.component == "brake" and e.time > 0.0]
    assert [new for _, new in turns] == [-1, 1]  # backward, forward: straight through, no stick
    for (time, _), zero in zip(turns, (math.pi / 2, 3 * math.pi / 2), strict=True):
        assert abs(time - zero) < 1e-9
    t = r.time
    away = np.abs(np.cos(t)) > 1e-6
    sliding = 50.0 * np.sign(np.cos(t))  # mu·cgeo·fn_max
    exact = -J * np.sin(t) + sliding
    np.testing.assert_allclose(r["adaptor.tau"][away], exact[away], rtol=0, atol=1e-9)
    audit = r.audit()
    assert audit.ok(), audit.worst


def test_without_w_and_a_the_flange_follows_the_angle_at_rest() -> None:
    """use_w = use_a = false (MSL's Move_phi): w and a are 0, tau = c·phi."""
    m = with_spring_damper(prescribed("angle_only", use_w=False, use_a=False))
    r = m.simulate(StopTime=2.0, Interval=0.01)
    np.testing.assert_allclose(r["adaptor.w"], 0.0, rtol=0, atol=0)
    np.testing.assert_allclose(r["adaptor.tau"], C * np.sin(r.time), rtol=0, atol=1e-11)


def test_a_new_input_moves_the_flange_at_once() -> None:
    """phi and w as model inputs (use_a = false): setting them is an input event after which the
    flange's angle and speed are the new values — the state is reset, not integrated there."""
    m = st.Model("inputs")
    m.add("adaptor", st.AngleToTorqueAdaptor(use_a=False))
    m.add("J", st.Inertia(J=J))
    m.add("ground", st.Fixed())
    with_spring_damper(m)
    m.connect("adaptor.flange", "J.flange_a")
    m.input("adaptor.phi", start=0.0)
    m.input("adaptor.w", start=0.0)
    sim = m.simulation(StopTime=1.0)
    sim.advance_to(0.5)
    assert sim.get("J.phi") == 0.0
    sim.set_input("adaptor.phi", 0.3)
    sim.set_input("adaptor.w", 2.0)
    assert sim.get("J.phi") == pytest.approx(0.3, abs=1e-15)
    assert sim.get("J.w") == pytest.approx(2.0, abs=1e-15)
    assert sim.get("adaptor.tau") == pytest.approx(C * 0.3 + D * 2.0, abs=1e-12)
    sim.advance_to(0.75)  # a = 0: the speed holds and the angle stays the input's
    assert sim.get("J.w") == pytest.approx(2.0, abs=1e-12)
    assert sim.get("J.phi") == pytest.approx(0.3, abs=1e-12)


def test_shafts_ideal_gears_tie_to_the_prescribed_one_move_with_it_at_once() -> None:
    """Behind ideal gears (ratios 2 and -0.5) the angles and speeds are the prescribed ones
    through the ratios (MSL: phi_a = ratio·phi_b, algebraic), also right after an input event;
    the gears' rows no longer hold only in the accelerations."""
    m = st.Model("geared")
    m.add("adaptor", st.AngleToTorqueAdaptor(use_a=False))
    m.add("gear", st.IdealGear(ratio=2.0))
    m.add("J", st.Inertia(J=J))
    m.add("gear2", st.IdealGear(ratio=-0.5))
    m.add("J2", st.Inertia(J=0.5))
    for a, b in [("adaptor.flange", "gear.flange_a"), ("gear.flange_b", "J.flange_a")]:
        m.connect(a, b)
    for a, b in [("J.flange_b", "gear2.flange_a"), ("gear2.flange_b", "J2.flange_a")]:
        m.connect(a, b)
    m.input("adaptor.phi", start=0.0)
    m.input("adaptor.w", start=0.0)
    sim = m.simulation(StopTime=1.0)
    sim.advance_to(0.5)
    sim.set_input("adaptor.phi", 0.3)
    sim.set_input("adaptor.w", 2.0)
    for t in (0.5, 0.75):  # at the event and after it (a = 0: the speeds hold)
        sim.advance_to(t)
        assert (sim.get("J.phi"), sim.get("J.w")) == pytest.approx((0.15, 1.0), abs=1e-12)
        assert (sim.get("J2.phi"), sim.get("J2.w")) == pytest.approx((-0.3, -2.0), abs=1e-12)
    assert sim.get("adaptor.tau") == pytest.approx(0.0, abs=1e-12)  # nothing to accelerate


def test_torque_to_angle_on_an_inertia_is_a_parabola() -> None:
    """MSL flange.tau = tau: a constant tau = 3 decelerates J = 2 at 1.5 rad/s²."""
    m = st.Model("parabola")
    m.add("tau", st.Constant(k=3.0))
    m.add("adaptor", st.TorqueToAngleAdaptor())
    m.add("J", st.Inertia(J=J, phi=0.0, w=0.0))
    m.connect("tau.y", "adaptor.tau")
    m.connect("adaptor.flange", "J.flange_b")
    r = m.simulate(StopTime=2.0, Interval=0.01)
    t = r.time
    np.testing.assert_allclose(r["adaptor.a"], -1.5, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r["adaptor.w"], -1.5 * t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.phi"], -0.75 * t**2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["adaptor.flange.tau"], 3.0, rtol=0, atol=0)
    audit = r.audit()
    assert audit.ok(), audit.worst


def test_torque_to_angle_without_w_and_a_reports_only_phi() -> None:
    m = st.Model("phi_only")
    m.add("tau", st.Constant(k=3.0))
    m.add("adaptor", st.TorqueToAngleAdaptor(use_w=False, use_a=False))
    m.add("J", st.Inertia(J=J, phi=0.0, w=0.0))
    m.connect("tau.y", "adaptor.tau")
    m.connect("adaptor.flange", "J.flange_b")
    r = m.simulate(StopTime=1.0, Interval=0.1)
    assert "adaptor.phi" in r.names and "adaptor.w" not in r.names and "adaptor.a" not in r.names


@pytest.mark.parametrize(
    ("use_w", "use_a", "missing", "parameter"), [(True, False, "w", "use_w"), (False, True, "a", "use_a")]
)
def test_an_enabled_input_left_open_names_component_and_parameter(
    use_w: bool, use_a: bool, missing: str, parameter: str
) -> None:
    m = st.Model("open")
    m.add("adaptor", st.AngleToTorqueAdaptor(use_w=use_w, use_a=use_a))
    m.add("ground", st.Fixed())
    with_spring_damper(m)
    m.add("phi", st.Sine(f=F))
    m.add("w", st.Sine(f=F, phase=math.pi / 2))
    m.connect("phi.y", "adaptor.phi")
    if missing != "w":
        m.connect("w.y", "adaptor.w")
    with pytest.raises(st.ModelError) as e:
        m.simulate(StopTime=1.0)
    message = str(e.value)
    assert "adaptor" in message and parameter in message and f"'{missing}'" in message


def test_a_disabled_input_cannot_be_connected() -> None:
    m = prescribed("disabled", use_a=False)
    with pytest.raises(st.ModelError, match="adaptor"):
        m.connect("a.y", "adaptor.a")
        m.simulate(StopTime=1.0)


def test_a_grounded_flange_cannot_be_prescribed() -> None:
    m = prescribed("grounded")
    m.connect("adaptor.flange", "ground.flange")
    with pytest.raises(st.ModelError, match="adaptor"):
        m.simulate(StopTime=1.0)


def test_a_brake_on_a_prescribed_shaft_follows_jumps_of_the_speed_input() -> None:
    """As in an FMU (use_a = false, phi and w set between steps): held while the speed is 0,
    the brake slides with the speed it is given and reverses when the speed jumps through zero
    (straight through: a stuck element cannot hold a shaft the prescribed motion moves)."""
    m = st.Model("jumps")
    m.add("adaptor", st.AngleToTorqueAdaptor(use_a=False))
    m.add("J", st.Inertia(J=J))
    m.add("brake", st.Brake(mu_pos=[[0.0, 0.5]], fn_max=100.0, cgeo=1.0))
    m.add("force", st.Constant(k=1.0))
    m.connect("adaptor.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("force.y", "brake.f_normalized")
    m.input("adaptor.phi", start=0.0)
    m.input("adaptor.w", start=0.0)
    sim = m.simulation(StopTime=1.0)
    assert (sim.get("brake.mode"), sim.get("adaptor.tau")) == (0.0, 0.0)  # held, needing nothing
    for k, (w, mode, tau) in enumerate([(1.0, 1.0, 50.0), (-1.0, -1.0, -50.0), (2.0, 1.0, 50.0)]):
        sim.advance_to(0.2 * (k + 1))
        sim.set_input("adaptor.w", w)
        sim.advance_to(0.2 * (k + 1) + 0.1)
        assert sim.get("J.w") == w
        assert sim.get("brake.mode") == mode
        assert sim.get("adaptor.tau") == pytest.approx(tau, abs=1e-9)


def test_the_adaptors_go_through_modelica_under_their_msl_names() -> None:
    m = with_spring_damper(prescribed("roundtrip", use_a=False))
    text = m.to_modelica()
    assert "Modelica.Mechanics.Rotational.Components.AngleToTorqueAdaptor adaptor(use_a=false);" in text
    again = st.Model.from_modelica(text)
    assert again.components["adaptor"].type == "AngleToTorqueAdaptor"
    tau = again.simulate(StopTime=2.0, Interval=0.01)["adaptor.tau"]
    np.testing.assert_array_equal(tau, m.simulate(StopTime=2.0, Interval=0.01)["adaptor.tau"])


def test_a_fixed_start_on_the_prescribed_flange_is_over_determined() -> None:
    """MSL: flange.phi = phi already fixes the start; a fixed J.w on the same shaft is one too many."""
    m = with_spring_damper(prescribed("over"))
    m.add("J", st.Inertia(J=J, w=5.0))
    m.connect("adaptor.flange", "J.flange_a")
    with pytest.raises(st.ModelError, match=r"over-determined.*J\.w|J\.w.*over-determined|adaptor\.w"):
        m.simulate(StopTime=1.0)
