"""One variable read alone gives the full table's column bit for bit (issue 34): a variable of
the kinematics (the kinetic energy, an angle or speed between shafts) computed from each row's
kinematics only, and any other one computed alone (every row evaluated, only it kept)."""

from __future__ import annotations

import numpy as np
import pytest
from paths import EXAMPLES, MSL_EXAMPLES

import stiction as st
from stiction.testing import ladder_toml

MODELS = [
    MSL_EXAMPLES / "CoupledClutches.toml",  # rotational, clutches locking
    MSL_EXAMPLES / "HeatLosses.toml",  # thermal: heat ports, temperatures
    EXAMPLES / "msl-translational" / "Brake.toml",  # translational
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


def test_a_torque_is_not_kinematic() -> None:
    """A clutch's torque needs the row's mode solve: reading it computes the table (kept for
    the next algebraic column)."""
    r = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml").simulate()
    assert not r._source.is_direct("clutch1.tau")
    r["clutch1.tau"]
    assert r._data is not None
