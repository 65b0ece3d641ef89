"""A sweep over a name the model does not have raises ModelError before any variant runs
(issue 29), naming the parameter with a suggestion; a bad value stays that variant's status."""

from __future__ import annotations

import pytest
from paths import EXAMPLES

import stiction as st


@pytest.fixture(scope="module")
def model() -> st.Model:
    return st.Model.load(EXAMPLES / "msl" / "CoupledClutches.toml")


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("clutch1.fn_mx", r"sweep 'clutch1.fn_mx'.*parameter 'fn_mx'.*did you mean 'fn_max'"),
        ("clutchx.fn_max", r"sweep 'clutchx.fn_max'.*did you mean .*'clutch1'"),
        ("Stoptime", r"sweep 'Stoptime'.*did you mean 'StopTime'"),
    ],
)
def test_an_unknown_name_raises_before_anything_runs(model: st.Model, name: str, message: str) -> None:
    with pytest.raises(st.ModelError, match=message):
        st.sweep(model, {name: [1.0, 2.0]}, ["max(J1.w)"], progress=False)
    with pytest.raises(st.ModelError, match=message):  # a compiled model too
        st.sweep(model.compile(), {name: [1.0, 2.0]}, ["max(J1.w)"], progress=False)


def test_a_bad_value_is_only_that_variants_status(model: st.Model) -> None:
    result = st.sweep(
        model, {"clutch1.fn_max": [10.0, -2.0], "J1.w": [0.0, 1.0]}, ["max(J1.w)"], progress=False
    )
    status = list(result.table["status"])
    assert status[0] == "ok"
    assert "fn_max" in status[1] and ">= 0" in status[1]
