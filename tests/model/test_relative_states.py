"""RelativeStates: no torque, and its phi_rel/w_rel start values set the pair's relative
motion. Two free inertias J1, J2 with J1 fixed at rest and RelativeStates(phi_rel = 0.2,
w_rel = 1.5, both fixed) between them: J2 starts at 0.2 with 1.5 rad/s and flies on
uniformly, J1 stays at rest (no torque passes)."""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st


def _pair(**rel: object) -> st.Model:
    m = st.Model("relative")
    m.add("J1", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.add("states", st.RelativeStates(**rel))
    m.add("J2", st.Inertia(J=2.0))
    m.connect("J1.flange_b", "states.flange_a")
    m.connect("states.flange_b", "J2.flange_a")
    return m


def test_relative_start_values_and_no_torque() -> None:
    fixed = {"phi_rel": {"start": 0.2, "fixed": True}, "w_rel": {"start": 1.5, "fixed": True}}
    r = _pair(**fixed).simulate(StopTime=1.0, Interval=0.1)
    t = r.time
    np.testing.assert_allclose(r["J2.phi"], 0.2 + 1.5 * t, atol=1e-12)
    np.testing.assert_allclose(r["J1.w"], 0.0, atol=0)
    np.testing.assert_allclose(r["states.phi_rel"], 0.2 + 1.5 * t, atol=1e-12)
    np.testing.assert_allclose(r["states.w_rel"], 1.5, atol=1e-12)
    np.testing.assert_allclose(r["states.a_rel"], 0.0, atol=1e-12)
    np.testing.assert_allclose(r["states.flange_a.tau"], 0.0, atol=0)


def test_over_determined_relative_start_is_refused() -> None:
    """J1 and J2 both fixed and phi_rel fixed too: one start value too many, named."""
    m = _pair(phi_rel={"start": 0.2, "fixed": True})
    m.components["J2"] = st.Inertia(J=2.0, phi=0.0, w=0.0)
    with pytest.raises(st.ModelError, match="phi_rel"):
        m.simulate(StopTime=0.1)
