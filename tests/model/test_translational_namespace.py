"""``stiction.translational``: a class per engine type ``Translational.X`` (issue 31), made
from the catalogue like the rotational classes, loaded only when first used."""

from __future__ import annotations

import inspect
import subprocess
import sys

import pytest

import stiction as st
from stiction.errors import ModelError
from stiction.model.catalogue import catalogue
from stiction.model.components import factory


def test_every_translational_type_is_a_class_of_the_namespace_with_its_dotted_type() -> None:
    dotted = sorted(n for n in catalogue() if n.startswith("Translational."))
    assert dotted and sorted(st.translational.__all__) == [n.split(".", 1)[1] for n in dotted]
    for name in dotted:
        cls = getattr(st.translational, name.split(".", 1)[1])
        assert cls.type_name == name and cls.__module__ == "stiction.translational"
        assert factory(name) is cls


def test_a_namespaced_class_is_its_component_and_keeps_its_type_in_toml() -> None:
    mass = st.translational.Mass(m=400.0, v="100 km/h")
    assert mass == st.Component("Translational.Mass", {"m": 400.0, "v": 100 / 3.6})
    assert repr(mass).startswith("translational.Mass(m=400.0")
    # the rotational Fixed and the translational one are two classes of two types
    assert st.translational.Fixed is not st.Fixed and st.translational.Fixed().type == "Translational.Fixed"
    m = st.Model("slide")
    m.add("car", mass)
    m.add("push", st.translational.ConstantForce(f_constant=-400.0))
    m.connect("car.flange_b", "push.flange")
    assert 'type = "Translational.Mass"' in m.to_toml()
    r = m.simulate(StopTime=1.0)
    assert r["car.v"][-1] == pytest.approx(100 / 3.6 - 1.0, rel=1e-9)  # −400 N on 400 kg


def test_help_shows_the_catalogue_and_bad_values_are_refused_by_name() -> None:
    doc = st.translational.Mass.__doc__ or ""
    assert "Modelica.Mechanics.Translational.Components.Mass" in doc and "m : Real [kg]" in doc
    assert list(inspect.signature(st.translational.Mass).parameters)[:2] == ["m", "L"]
    with pytest.raises(ModelError, match=r"Translational\.Mass.*'m'"):
        st.translational.Mass(m=-1.0)
    assert "stiction's own component" in (st.SlipWheel.__doc__ or "")


def test_import_stiction_does_not_load_the_namespace() -> None:
    code = "import sys, stiction; print('stiction.translational' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
