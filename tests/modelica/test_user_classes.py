"""Users' own classes (issue 30): a package with a ``Driveline`` class (clutch + gear +
brake behind its own flanges and inputs) used twice in ``Vehicle2Axles`` with different
parameters imports, runs, and round-trips through ``to_modelica`` bit-identically (the export
writes the flattened components, ``front.clutch``, which read back to the same model)."""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st

VEHICLE = """within;
package Cars "a user's package"
  import Modelica.Constants.pi;
  import SI = Modelica.Units.SI;

  model Driveline "clutch, gear and brake of one axle"
    import Modelica.Mechanics.Rotational.Components;
    parameter Real clutchPeak = 1.1 "peak of the clutch";
    parameter SI.Force clutchForce = 200;
    parameter Real ratio = 3;
    parameter SI.Force brakeForce = 2*clutchForce "twice the clutch";
    Modelica.Mechanics.Rotational.Interfaces.Flange_a flange_a "from the engine";
    Modelica.Mechanics.Rotational.Interfaces.Flange_b flange_b "to the wheel";
    Modelica.Blocks.Interfaces.RealInput engage;
    Modelica.Blocks.Interfaces.RealInput brakeCmd;
    Components.Clutch clutch(peak=clutchPeak, fn_max=clutchForce, phi_rel(fixed=true), w_rel(fixed=true));
    Components.Inertia shaft(J=0.1);
    Components.IdealGear gear(ratio=ratio);
    Components.Brake brake(fn_max=brakeForce);
  equation
    connect(flange_a, clutch.flange_a);
    connect(clutch.flange_b, shaft.flange_a);
    connect(shaft.flange_b, gear.flange_a);
    connect(gear.flange_b, brake.flange_a);
    connect(brake.flange_b, flange_b);
    connect(engage, clutch.f_normalized);
    connect(brakeCmd, brake.f_normalized);
  end Driveline;

  model Vehicle2Axles "two axles driven by one engine"
    extends Modelica.Icons.Example;
    parameter SI.Time tBrake = 1.5;
    Modelica.Mechanics.Rotational.Components.Inertia engine(J=0.5, phi(fixed=true, start=0), w(fixed=true, start=100));
    Driveline front(clutchPeak=1.2, ratio=4);
    Driveline rear(clutchForce=150, brakeForce=500);
    Modelica.Mechanics.Rotational.Components.Inertia wheelF(J=2);
    Modelica.Mechanics.Rotational.Components.Inertia wheelR(J=3);
    Modelica.Blocks.Sources.Ramp engage(duration=0.3, startTime=0.2);
    Modelica.Blocks.Sources.Step brake(startTime=tBrake);
    Modelica.Blocks.Sources.Sine torqueSignal(amplitude=20, f=5/pi);
    Modelica.Mechanics.Rotational.Sources.Torque torque;
    output SI.AngularVelocity slipFront = front.clutch.w_rel;
  equation
    connect(torqueSignal.y, torque.tau);
    connect(torque.flange, engine.flange_a);
    connect(engine.flange_b, front.flange_a);
    connect(engine.flange_b, rear.flange_a);
    connect(front.flange_b, wheelF.flange_a);
    connect(rear.flange_b, wheelR.flange_a);
    connect(engage.y, front.engage);
    connect(front.engage, rear.engage);
    connect(brake.y, front.brakeCmd);
    connect(brake.y, rear.brakeCmd);
    annotation (experiment(StopTime=3, Interval=1e-3));
  end Vehicle2Axles;
end Cars;
"""


def test_a_two_level_model_is_flattened_with_each_instances_parameters() -> None:
    m = st.Model.from_modelica(VEHICLE, model="Vehicle2Axles")
    c = m.components
    assert c["front.clutch"].params["peak"] == 1.2 and c["rear.clutch"].params["peak"] == 1.1
    assert c["front.clutch"].params["fn_max"] == 200.0 and c["rear.clutch"].params["fn_max"] == 150.0
    assert c["front.brake"].params["fn_max"] == 400.0  # the class's default over the modified force
    assert c["rear.brake"].params["fn_max"] == 500.0
    assert c["front.gear"].params["ratio"] == 4.0 and c["rear.gear"].params["ratio"] == 3.0
    conns = {frozenset(x) for x in m.connections}
    assert frozenset(("engine.flange_b", "front.clutch.flange_a")) in conns
    assert frozenset(("engage.y", "rear.clutch.f_normalized")) in conns  # through the chain
    assert frozenset(("front.brake.flange_b", "wheelF.flange_a")) in conns
    assert m.variables["slipFront"] == "front.clutch.w_rel"
    r = m.simulate()
    assert np.isfinite(r["front.clutch.w_rel"]).all()
    # the two axles differ (ratios 4 and 3): the wheels turn at different speeds until the
    # brakes (at tBrake = 1.5 s) stop both
    before = np.searchsorted(r["time"], 1.4)
    assert r["wheelF.w"][before] > 1 and abs(r["wheelF.w"][before] * 4 - r["wheelR.w"][before] * 3) < 1e-6
    assert abs(r["wheelF.w"][-1]) < 1e-6 and abs(r["wheelR.w"][-1]) < 1e-6


def test_the_two_level_model_round_trips_through_to_modelica_bit_identically(tmp_path) -> None:
    m = st.Model.from_modelica(VEHICLE, model="Cars.Vehicle2Axles")
    path = tmp_path / "Vehicle2Axles.mo"
    m.to_modelica(path)
    again = st.Model.from_modelica(path)
    assert again.components.keys() == m.components.keys()
    a, b = m.simulate(), again.simulate()
    for name in ("front.clutch.w_rel", "rear.brake.tau", "wheelF.w", "wheelR.w", "slipFront"):
        assert (a[name] == b[name]).all(), name


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ("Driveline front(clutchPeak=1.2, ratio=4);", "Driveline front(clutchPeek=1.2);"),
        ("connect(engage.y, front.engage);", "connect(engage.y, front.nothing);"),
    ],
)
def test_a_mistake_in_a_class_instance_is_located(change: str, words: str) -> None:
    text = VEHICLE.replace(change, words)
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text, model="Vehicle2Axles")
    line = text[: text.index(words)].count("\n") + 1
    assert any(e[0] == line for e in info.value.errors), (line, info.value.errors)


def test_a_class_with_other_equations_stays_refused_at_its_place() -> None:
    text = VEHICLE.replace("  end Driveline;", "    shaft.w = 0;\n  end Driveline;")
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text, model="Vehicle2Axles")
    line = text[: text.index("shaft.w = 0")].count("\n") + 1
    assert info.value.errors[0][0] == line and "only connect" in str(info.value), str(info.value)


def test_a_quoted_name_is_a_path_and_refused_where_it_clashes_or_is_no_path() -> None:
    inertia = "Modelica.Mechanics.Rotational.Components.Inertia"
    text = f"model M\n  {inertia} 'a.b'(J=2);\n  {inertia} c(J=1);\nequation\n  connect('a.b'.flange_b, c.flange_a);\nend M;\n"
    m = st.Model.from_modelica(text)
    assert m.components["a.b"].params["J"] == 2.0 and m.connections == [("a.b.flange_b", "c.flange_a")]
    refused = [
        ("'my inertia'", "not an identifier or a path", 2),
        ("'c.d'", "'c'.*'c.d' start the same path", 3),  # at the second of the two
    ]
    for bad, words, line in refused:
        with pytest.raises(st.ModelError, match=words) as info:
            st.Model.from_modelica(text.replace("'a.b'(J=2)", f"{bad}(J=2)"))
        assert info.value.errors[0][0] == line, info.value.errors
