"""The re-drive hooks of a ``Simulation`` (the virtual dynamometer's): ``advance_until`` stops at
the exact crossing of a level (or at the stick event that lands on it), ``reinit`` sets an
inertia's speed as an event whose energy counts as work supplied."""

from __future__ import annotations

import pytest

import stiction as st

J, C, MU, CGEO, FN_MAX = 2.0, 500.0, 0.4, 0.2, 1e5


def braked_inertia() -> st.Model:
    m = st.Model("redrive")
    m.add("J1", st.Inertia(J=J, w=10.0))
    m.add("brake", st.Brake(fn_max=FN_MAX, cgeo=CGEO, mu_pos=[[0.0, MU]], peak=1.0, useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=C, T=300.0))
    m.connect("brake.heatPort", "disc.port")
    m.connect("J1.flange_b", "brake.flange_a")
    m.input("brake.f_normalized", 0.0)
    m.experiment["Tolerance"] = 1e-11
    return m


def test_advance_until_and_reinit_on_a_plain_simulation() -> None:
    sim = braked_inertia().simulation(StopTime=100.0)
    sim.advance_to(1.0)
    fn = 1000.0
    sim.set_input("brake.f_normalized", fn / FN_MAX)
    assert sim.advance_until("J1.w", 4.0, 50.0)
    assert sim.time == pytest.approx(1.0 + J * 6.0 / (MU * CGEO * fn), rel=1e-12)
    assert sim.get("J1.w") == pytest.approx(4.0, rel=1e-12)
    assert not sim.advance_until("J1.w", -1.0, 60.0)  # it sticks at 0 and stays there
    assert sim.time == 60.0 and abs(sim.get("J1.w")) < 1e-9
    sim.set_input("brake.f_normalized", 0.0)
    sim.reinit("J1.w", 7.0)
    assert sim.get("J1.w") == 7.0
    phi = sim.get("J1.phi")
    sim.advance_to(61.0)
    # released: it turns freely at the speed it was given
    assert sim.get("J1.w") == pytest.approx(7.0, rel=1e-12)
    assert sim.get("J1.phi") - phi == pytest.approx(7.0, rel=1e-10)
    # the energy the reinit gave counts as work supplied: the balance closes
    kinetic, lost, work = (
        sim.get(f"system.{n}") for n in ("kineticEnergy", "dissipatedEnergy", "sourceWork")
    )
    assert work == pytest.approx(J * 7.0**2 / 2, rel=1e-9)
    assert kinetic + lost - work == pytest.approx(J * 10.0**2 / 2, rel=1e-9)
    with pytest.raises(st.UsageError, match="cannot be saved"):
        sim.state()
    with pytest.raises(st.UsageError, match="not an inertia"):
        sim.reinit("brake.w", 1.0)


def test_advance_until_a_temperature_and_refusals() -> None:
    sim = braked_inertia().simulation(StopTime=100.0)
    sim.set_input("brake.f_normalized", 1000.0 / FN_MAX)
    # the disc heats by J·(w0² − w²)/(2·C): 0.1 K above its start where w² = w0² − 2·C·0.1/J
    assert sim.advance_until("disc.T", 300.1)
    assert sim.get("J1.w") == pytest.approx((100.0 - 2 * C * 0.1 / J) ** 0.5, rel=1e-10)
    assert sim.get("disc.T") == pytest.approx(300.1, rel=1e-15)
    assert sim.advance_until("disc.T", sim.get("disc.T"))  # already there: at once
    with pytest.raises(st.UsageError, match="unknown variable"):
        sim.advance_until("disc.Tx", 1.0)
    with pytest.raises(st.UsageError, match="expected an inertia's speed"):
        sim.reinit("J1.phi", 1.0)
