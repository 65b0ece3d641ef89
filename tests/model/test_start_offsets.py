"""A grounded flange's angle is no speed: a fixed relative speed next to a Fixed at phi0 ≠ 0
starts at its start value (it once started at start + phi0: the angle offset of the relation
leaked into the speed's start equation)."""

from __future__ import annotations

import pytest

import stiction as st

MODEL = """
name = "offset"
connect = [["fixed.flange", "sd.flange_a"], ["sd.flange_b", "J.flange_a"]]
[experiment]
StopTime = 0.01
[components]
fixed = {{ type = "Fixed", phi0 = {phi0} }}
sd = {{ type = "SpringDamper", c = 1.0, d = 1.0, w_rel = {{ start = 2.0, fixed = true }}, phi_rel = {{ start = 0.25, fixed = true }} }}
J = {{ type = "Inertia", J = 1.0 }}
"""


@pytest.mark.parametrize("phi0", [0.0, 0.5])
def test_relative_start_values_next_to_a_grounded_flange(phi0: float) -> None:
    r = st.Model.loads(MODEL.format(phi0=phi0)).simulate()
    assert r["sd.w_rel"][0] == pytest.approx(2.0, abs=1e-12)
    assert r["J.w"][0] == pytest.approx(2.0, abs=1e-12)
    assert r["sd.phi_rel"][0] == pytest.approx(0.25, abs=1e-12)
    assert r["J.phi"][0] == pytest.approx(phi0 + 0.25, abs=1e-12)
