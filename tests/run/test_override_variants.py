"""Experiment overrides (issue 34): ``Model.simulate(StopTime=…)`` gives the run of the model
with that value set, bit for bit, whether the override equals the model's experiment or not,
and whether its variant was built for this call or kept from an earlier one."""

from __future__ import annotations

import numpy as np
from paths import MSL_EXAMPLES

import stiction as st
from stiction.run.compiled import VARIANTS_KEPT


def _same(a: st.Result, b: st.Result) -> None:
    assert a.names == b.names
    np.testing.assert_array_equal(a.data.view(np.int64), b.data.view(np.int64))
    assert [e.time for e in a.events] == [e.time for e in b.events]


def test_overrides_equal_a_model_with_the_values_set() -> None:
    model = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    same = {k: model.experiment[k] for k in ("StopTime", "Interval", "Tolerance")}
    _same(model.simulate(**same), model.simulate())
    other = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    other.experiment["StopTime"] = 1.2
    first = model.simulate(StopTime=1.2)
    again = model.simulate(StopTime=1.2)  # the kept variant
    assert first.time[-1] == again.time[-1] == 1.2
    _same(first, other.simulate())
    _same(again, other.simulate())
    _same(model.simulate(), st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml").simulate())


def test_kept_variants_are_bounded_and_keyed_by_value_and_type() -> None:
    model = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    compiled = model.compile()
    for k in range(VARIANTS_KEPT + 3):
        r = model.simulate(StopTime=1.0 + 0.01 * k)
        assert r.time[-1] == 1.0 + 0.01 * k
    assert len(compiled._variants) == VARIANTS_KEPT
    # a parameter override and the same parameter with another value: two variants
    a = model.simulate(params={"clutch1.fn_max": 30.0})
    b = model.simulate(params={"clutch1.fn_max": 35.0})
    assert not np.array_equal(a["clutch1.tau"], b["clutch1.tau"])
    _same(model.simulate(params={"clutch1.fn_max": 30.0}), a)
