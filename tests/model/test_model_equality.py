"""Two models are equal when they mean the same (issue 29): numbers by value, parameter
expressions by their syntax, not by how they were typed."""

from __future__ import annotations

import stiction as st


def model(t2: str, start: str, variable: str, height: float) -> st.Model:
    m = st.Model("m")
    m.parameters.update({"T": 0.5, "T2": t2})
    m.add("s", st.Step(startTime=st.expr(start), height=height))
    m.variable("x", variable)
    return m


def test_spacing_and_number_types_do_not_matter() -> None:
    assert model("2*T", "T2+0.1", "s.y*2", 1) == model("2 * T", "T2 + 0.1", "(s.y) * 2", 1.0)


def test_a_different_expression_is_a_different_model() -> None:
    assert model("2*T", "T2+0.1", "s.y*2", 1) != model("3*T", "T2+0.1", "s.y*2", 1)
    assert model("2*T", "T2+0.1", "s.y*2", 1) != model("2*T", "T2-0.1", "s.y*2", 1)
    assert model("2*T", "T2+0.1", "s.y*2", 1) != model("2*T", "T2+0.1", "s.y*3", 1)
    assert model("2*T", "T2+0.1", "s.y*2", 1) != model("2*T", "T2+0.1", "s.y*2", 2)


def test_a_model_read_back_from_modelica_equals_the_original() -> None:
    m = model("2*T", "T2 + 0.1", "s.y*2", 1)
    m.add("J", st.Inertia(J=1.0, w=0))
    assert st.Model.from_modelica(m.to_modelica()).components == m.components
