"""A number outside its parameter's range is refused where it is typed (issue 29): when a
component is built in Python, when a model file is read and when Modelica is imported, with
the engine's words, as ``Model.set`` and a run refuse it."""

from __future__ import annotations

import pytest

import stiction as st


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: st.Inertia(J=-1.2), r"^Inertia: parameter 'J': must be >= 0, got -1.2$"),
        (lambda: st.Brake(fn_max=10, peak=0.5), r"^Brake: parameter 'peak': must be >= 1, got 0.5$"),
        (lambda: st.Clutch(fn_max=10, cgeo=-1), r"^Clutch: parameter 'cgeo': must be >= 0, got -1$"),
        (lambda: st.Component("Brake", {"fn_max": -3.0}), r"parameter 'fn_max': must be >= 0, got -3$"),
    ],
)
def test_building_a_component_checks_its_ranges(make, message: str) -> None:
    with pytest.raises(st.ModelError, match=message):
        make()


def test_the_same_rule_as_set_and_the_engine() -> None:
    m = st.Model("m")
    m.add("J", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match=r"parameter 'J': must be >= 0, got -1"):
        m.set("J.J", -1.0)
    assert st.Inertia(J=0.0).params == {"J": 0.0}  # the bound itself is inside


def test_a_model_file_names_the_component() -> None:
    text = 'name = "m"\n[components.J]\ntype = "Inertia"\nJ = -2.0\n'
    with pytest.raises(st.ModelError, match=r"component 'J' \(Inertia\): parameter 'J': must be >= 0"):
        st.Model.loads(text)


def test_modelica_places_it_at_the_modifier() -> None:
    text = "model M\n  Modelica.Mechanics.Rotational.Components.Inertia J(J=-2);\nend M;\n"
    with pytest.raises(st.ModelError, match=r"^<modelica>:2:54: component 'J' \(Inertia\): parameter 'J'"):
        st.Model.from_modelica(text)
