"""Issue 31's bad input, refused by name before any run, whichever way the model is written
(TOML, Python, Modelica): a rotational flange joined to a translational one, a mass with
m <= 0, a wheel with radius <= 0, a vehicle with a negative drag area (A or Cd)."""

from __future__ import annotations

from collections.abc import Callable

import pytest

import stiction as st
from stiction import ModelError

tr = st.translational
VEHICLE = {"m": 800.0, "J": 1.0, "R": 0.3}

# (case, TOML type, MSL class, parameters, the parameter named)
CASES = [
    ("mass m = 0", "Translational.Mass", "Modelica.Mechanics.Translational.Components.Mass", {"m": 0.0}, "m"),
    (
        "mass m < 0",
        "Translational.Mass",
        "Modelica.Mechanics.Translational.Components.Mass",
        {"m": -2.0},
        "m",
    ),
    (
        "rolling wheel radius = 0",
        "IdealRollingWheel",
        "Modelica.Mechanics.Rotational.Components.IdealRollingWheel",
        {"radius": 0.0},
        "radius",
    ),
    ("slip wheel radius < 0", "SlipWheel", "Stiction.Components.SlipWheel", {"radius": -0.3}, "radius"),
    (
        "vehicle A < 0",
        "Translational.Vehicle",
        "Modelica.Mechanics.Translational.Components.Vehicle",
        {**VEHICLE, "A": -1.5},
        "A",
    ),
    (
        "vehicle Cd < 0",
        "Translational.Vehicle",
        "Modelica.Mechanics.Translational.Components.Vehicle",
        {**VEHICLE, "Cd": -0.3},
        "Cd",
    ),
]
IDS = [case[0] for case in CASES]


def _toml_value(value: float) -> str:
    return repr(float(value))


def _refused(build: Callable[[], object], *words: str) -> str:
    with pytest.raises(ModelError) as info:
        build()
    message = str(info.value)
    for word in words:
        assert word in message, message
    return message


@pytest.mark.parametrize(("case", "ctype", "cls", "params", "bad"), CASES, ids=IDS)
def test_from_toml(case: str, ctype: str, cls: str, params: dict[str, float], bad: str) -> None:
    body = ", ".join(f"{k} = {_toml_value(v)}" for k, v in params.items())
    text = f'name = "bad"\n[components]\nx = {{ type = "{ctype}", {body} }}\n'
    _refused(lambda: st.Model.loads(text), "component 'x'", ctype, f"parameter '{bad}'")


@pytest.mark.parametrize(("case", "ctype", "cls", "params", "bad"), CASES, ids=IDS)
def test_from_python(case: str, ctype: str, cls: str, params: dict[str, float], bad: str) -> None:
    factory = (
        getattr(tr, ctype.removeprefix("Translational."))
        if ctype.startswith("Translational.")
        else getattr(st, ctype)
    )
    _refused(lambda: factory(**params), ctype, f"parameter '{bad}'")


@pytest.mark.parametrize(("case", "ctype", "cls", "params", "bad"), CASES, ids=IDS)
def test_from_modelica(case: str, ctype: str, cls: str, params: dict[str, float], bad: str) -> None:
    mods = ", ".join(f"{k}={v!r}" for k, v in params.items())
    text = f"model Bad\n  {cls} x({mods});\nend Bad;\n"
    _refused(lambda: st.Model.from_modelica(text), "'x'", f"'{bad}'", ":2:")


def test_a_bad_value_through_a_parameter_is_refused_at_check_before_a_run() -> None:
    """m = { expr = "mass" } with mass = 0 is known only when the expressions are evaluated: the check
    (run by simulate before it integrates) names the component and the parameter."""
    text = 'name = "bad"\n[parameters]\nmass = 0.0\n[components]\ncar = { type = "Translational.Mass", m = { expr = "mass" } }\n'
    model = st.Model.loads(text)
    _refused(model.check, "car", "'m'")


JOINED = {
    "toml": lambda: st.Model.loads(
        'name = "bad"\nconnect = [["J.flange_b", "car.flange_a"]]\n[components]\n'
        'J = { type = "Inertia", J = 1.0 }\ncar = { type = "Translational.Mass", m = 1.0 }\n'
    ),
    "python": lambda: (
        st.Model("bad")
        .add("J", st.Inertia(J=1.0))
        .add("car", tr.Mass(m=1.0))
        .connect("car.flange_a", "J.flange_b")
    ),
    "modelica": lambda: st.Model.from_modelica(
        "model Bad\n  Modelica.Mechanics.Rotational.Components.Inertia J(J=1);\n"
        "  Modelica.Mechanics.Translational.Components.Mass car(m=1);\n"
        "equation\n  connect(J.flange_b, car.flange_a);\nend Bad;\n"
    ),
}


@pytest.mark.parametrize("source", sorted(JOINED))
def test_a_rotational_flange_joined_to_a_translational_one_is_refused_where_it_is_written(
    source: str,
) -> None:
    _refused(
        JOINED[source],
        "rotational flange 'J.flange_b'",
        "translational flange 'car.flange_a'",
        "IdealRollingWheel",
    )


def test_the_engine_refuses_the_join_too_when_the_connections_are_edited_directly() -> None:
    """``Model.connections`` is a public list: a pair appended there bypasses ``connect``; the
    engine's check still refuses it, naming both flanges, before any run."""
    m = st.Model("bad").add("J", st.Inertia(J=1.0)).add("car", tr.Mass(m=1.0))
    m.connections.append(("J.flange_b", "car.flange_a"))
    _refused(m.check, "rotational flange 'J.flange_b'", "translational flange 'car.flange_a'")
