"""stiction's own components through Modelica: a ``SlipWheel`` (not in the MSL) exports as
``Stiction.Components.SlipWheel``, which the importer maps back, bit-identically."""

from __future__ import annotations

import runpy

import numpy as np
from paths import EXAMPLES

import stiction as st
from stiction.modelica.names import MSL_CLASSES, OWN_COMPONENTS


def test_the_vehicle_stop_with_its_slip_wheel_round_trips_through_modelica_bit_identically() -> None:
    model = runpy.run_path(str(EXAMPLES / "vehicle_stop.py"))["build"]()
    text = model.to_modelica()
    assert "  Stiction.Components.SlipWheel tyre(radius=0.3, " in text
    back = st.Model.from_modelica(text)
    assert back.components["tyre"].type == "SlipWheel"
    assert back.components["tyre"].params == model.components["tyre"].params
    r, r_back = model.simulate(), back.simulate()
    assert r.names == r_back.names
    np.testing.assert_array_equal(r.data, r_back.data)


def test_a_slip_wheel_that_locks_under_a_normal_force_input_round_trips() -> None:
    """The optional input (fN) and a skid: the lock-up event survives the round trip."""
    m = st.Model("skid")
    m.add("wheel", st.Inertia(J=1.0, w=50.0))
    m.add("tyre", st.SlipWheel(radius=0.3, mu_pos=[[0.0, 0.8], [10.0, 0.6]], useNormalForceInput=True))
    m.add("load", st.Constant(k=2000.0))
    m.add("car", st.translational.Mass(m=200.0, v=15.0))
    m.add("brake", st.Brake(fn_max=3000.0))
    m.add("press", st.Step(startTime=0.2))
    for a, b in [
        ("wheel.flange_b", "tyre.flangeR"),
        ("tyre.flangeT", "car.flange_a"),
        ("load.y", "tyre.fN"),
        ("brake.flange_b", "wheel.flange_a"),
        ("press.y", "brake.f_normalized"),
    ]:
        m.connect(a, b)
    m.experiment.update(StopTime=2.0, Interval=1e-3)
    back = st.Model.from_modelica(m.to_modelica())
    r, r_back = m.simulate(), back.simulate()
    assert r["tyre.locked"].min() == 0.0  # it skids: the round trip carries the stick/slip switching
    np.testing.assert_array_equal(r.data, r_back.data)
    assert [(e.component, e.new_mode) for e in r.events] == [(e.component, e.new_mode) for e in r_back.events]


def test_every_own_component_has_a_stiction_class_and_no_msl_one() -> None:
    for ctype in OWN_COMPONENTS:
        assert MSL_CLASSES[ctype] == f"Stiction.Components.{ctype}"
    assert not any(cls.startswith("Stiction.") for t, cls in MSL_CLASSES.items() if t not in OWN_COMPONENTS)


def test_an_unknown_class_of_the_stiction_namespace_is_refused_at_its_place() -> None:
    text = "model M\n  Stiction.Components.Hovercraft h;\nend M;"
    try:
        st.Model.from_modelica(text)
    except st.ModelError as error:
        assert "Stiction.Components.Hovercraft" in str(error) and ":2:" in str(error)
    else:
        raise AssertionError("an unknown Stiction class was accepted")
