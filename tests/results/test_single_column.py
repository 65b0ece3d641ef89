"""One variable read alone gives the full table's column bit for bit (issue 34): a variable of
the kinematics (the kinetic energy, an angle or speed between shafts) computed from each row's
kinematics only; a friction element's torque, loss, normal force or ``mu``, a law's torque or a
signal from the part of each row it reads, with the mode solve only in the rows that need it (a
clutch locked); and any other one as a column of the table."""

from __future__ import annotations

import numpy as np
import pytest
from paths import EXAMPLES, MSL_EXAMPLES

import stiction as st
from stiction.testing import ladder_toml

MODELS = [
    MSL_EXAMPLES / "CoupledClutches.toml",  # rotational, clutches locking
    MSL_EXAMPLES / "Friction.toml",  # bearing friction, brake, a speed source
    MSL_EXAMPLES / "SimpleGearShift.toml",  # a one-way clutch, gears
    MSL_EXAMPLES / "HeatLosses.toml",  # thermal: heat ports, temperatures
    MSL_EXAMPLES / "LossyGearDemo2.toml",  # a lossy gear: its variables need the solve
    EXAMPLES / "msl-translational" / "Brake.toml",  # translational
    EXAMPLES / "msl-translational" / "Friction.toml",  # translational stick-slip
]


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)


def _assert_columns_equal_table(model: st.Model) -> int:
    """Every variable read from a result that computes the variables of the kinematics alone,
    against the table of another run of the same model (runs are deterministic), bit for bit;
    returns how many were computed alone (the table is computed only after them)."""
    table = model.simulate()
    full = table.data
    r = model.simulate()
    alone = [k for k, name in enumerate(r.names) if r._source.is_direct(name)]
    for k in alone:
        np.testing.assert_array_equal(_bits(r[r.names[k]]), _bits(full[:, k]), err_msg=r.names[k])
    assert r._data is None, "no variable read alone computed the table"
    for k, name in enumerate(r.names):  # the others: the table's, computed now
        np.testing.assert_array_equal(_bits(r[name]), _bits(full[:, k]), err_msg=name)
    return len(alone)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_every_variable_alone_is_the_tables_column(path) -> None:
    model = st.Model.load(path)
    assert _assert_columns_equal_table(model) > 0


def test_the_ladders_kinetic_energy_is_computed_alone() -> None:
    """The ladder's kinetic energy reads only the kinematics: computed without the table,
    equal to its column bit for bit, and to ½·Σ J·w² of the inertias."""
    model = st.Model.loads(ladder_toml(12))
    r = model.simulate()
    assert r._source.is_direct("system.kineticEnergy")
    energy = r["system.kineticEnergy"]
    assert r._data is None, "the table was not computed"
    full = model.simulate()
    np.testing.assert_array_equal(
        _bits(energy), _bits(full.data[:, full.names.index("system.kineticEnergy")])
    )
    inertias = [n for n, c in model.components.items() if c.type == "Inertia"]
    by_hand = sum(0.5 * model.components[n].params["J"] * r[f"{n}.w"] ** 2 for n in inertias)
    np.testing.assert_allclose(energy, by_hand, rtol=1e-12, atol=1e-12)


def test_a_clutch_torque_is_computed_alone_through_its_locked_rows() -> None:
    """clutch1's torque is its sliding law while it slides, 0 while free and the lock row's
    multiplier while locked: read alone, without the table, it is the table's column bit for
    bit in all three, at the events' rows too (both sides of each event)."""
    model = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    r = model.simulate()
    assert r._source.is_direct("clutch1.tau")
    tau = r["clutch1.tau"]
    assert r._data is None, "the table was not computed"
    full = model.simulate()
    np.testing.assert_array_equal(_bits(tau), _bits(full["clutch1.tau"]))
    locked, free = full["clutch1.locked"] > 0, full["clutch1.free"] > 0
    assert locked.sum() > 100 and free.sum() > 100 and (~locked & ~free).sum() > 100
    t = full["time"]
    assert np.any(t[1:] == t[:-1]), "rows on both sides of events"
    assert np.all(tau[free] == 0.0) and np.any(tau[locked] != 0.0)


def test_a_variable_that_needs_the_solve_in_most_rows_is_the_tables() -> None:
    """clutch2 is locked in half the rows: its torque (and any acceleration) is read as a
    column of the table, computed once and kept for the next one."""
    r = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml").simulate()
    assert not r._source.is_direct("clutch2.tau")
    assert not r._source.is_direct("J1.a")
    r["clutch2.tau"]
    assert r._data is not None


def test_columns_alone_across_parameter_changes() -> None:
    """A run whose clutch parameters change twice (each stretch of rows evaluated with its own
    system): every variable read alone is the table's column bit for bit."""

    def run() -> st.Result:
        sim = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml").simulation()
        sim.run(StopTime=0.5)
        sim.set_parameter("clutch1.fn_max", 30.0)
        sim.run(StopTime=1.0)
        sim.set_parameter("clutch1.fn_max", 10.0)
        sim.run(StopTime=1.5)
        return sim.result()

    full = run().data
    r = run()
    alone = [k for k, name in enumerate(r.names) if r._source.is_direct(name)]
    assert "clutch1.tau" in [r.names[k] for k in alone]
    for k in alone:
        np.testing.assert_array_equal(_bits(r[r.names[k]]), _bits(full[:, k]), err_msg=r.names[k])
    assert r._data is None, "no variable read alone computed the table"


def _driven_clutch_line() -> st.Model:
    """A speed source drives J1; a clutch couples it to a shaft without inertia that a spring
    and damper join to J2: the clutch's speed is the solve's while it is open (massless), the
    source's motion is prescribed (`kinematics`, not the states alone)."""
    m = st.Model("driven_clutch_line")
    m.add("wave", st.Sine(amplitude=5.0, f=2.0, offset=8.0))
    m.add("speed", st.Speed(exact=False, f_crit=50.0))
    m.add("J1", st.Inertia(J=1.0))
    m.add("press", st.Ramp(height=1.0, duration=0.3, startTime=0.2))
    m.add("clutch", st.Clutch(fn_max=20.0))
    m.add("sd", st.SpringDamper(c=200.0, d=5.0))
    m.add("J2", st.Inertia(J=2.0, phi=0.0, w=0.0))
    m.connect("wave.y", "speed.w_ref")
    m.connect("speed.flange", "J1.flange_a")
    m.connect("J1.flange_b", "clutch.flange_a")
    m.connect("press.y", "clutch.f_normalized")
    m.connect("clutch.flange_b", "sd.flange_a")
    m.connect("sd.flange_b", "J2.flange_a")
    m.experiment.update(StopTime=1.5, Interval=1e-3)
    return m


def test_columns_alone_with_a_prescribed_speed_and_a_massless_shaft() -> None:
    """Every variable read alone is the table's column bit for bit where the rows need the
    prescribed motion's kinematics and a shaft's speed is the solve's. The ramp (a signal) is
    computed alone; the spring-damper's torque and the clutch's read the massless shaft's
    speed, which only the solve gives: columns of the table."""
    model = _driven_clutch_line()
    assert _assert_columns_equal_table(model) > 0
    r = model.simulate()
    assert r._source.is_direct("press.y")
    assert not r._source.is_direct("sd.tau") and not r._source.is_direct("clutch.tau")


def test_every_variable_alone_of_a_ladder_is_the_tables_column() -> None:
    """The ladder of clutches engaging one after another, spring-dampers and brakes: its wide
    table (672 variables) makes a clutch's torque alone worth it even where the clutch holds
    most rows (clutch5: 92 %)."""
    model = st.Model.loads(ladder_toml(24))
    assert _assert_columns_equal_table(model) > 0
    r = model.simulate()
    held = r["clutch5.locked"] > 0
    assert held.mean() > 0.8 and r._source.is_direct("clutch5.tau")
