"""Export writes a parameter as a plain modification and a start value with start/fixed
(issue 29: a FixedTemperature's T came out as T(start=293.15, fixed=true)); an independent
Modelica grammar (pymoca) reads the text."""

from __future__ import annotations

import re

import pytest

import stiction as st


def heated_brake() -> st.Model:
    m = st.Model("HeatedBrake")
    m.add("J", st.Inertia(J=1.0, w=10.0))
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=[[0, 0.5]], useHeatPort=True))
    m.add("press", st.Constant(k=1.0))
    m.add("disc", st.HeatCapacitor(C=500.0, T=300.0))
    m.add("amb", st.FixedTemperature(T=293.15))
    m.add("air", st.ThermalConductor(G=2.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "disc.port")
    m.connect("disc.port", "air.port_a")
    m.connect("air.port_b", "amb.port")
    return m


def test_a_parameter_is_a_plain_modification_and_a_start_value_keeps_start_fixed() -> None:
    text = heated_brake().to_modelica()
    assert re.search(r"FixedTemperature amb\(T=293\.15\)", text), text
    assert re.search(r"HeatCapacitor disc\(C=500\.0, T\(start=300\.0, fixed=true\)\)", text), text
    assert re.search(r"Inertia J\(J=1\.0, w\(start=10\.0, fixed=true\)\)", text), text


def test_the_export_reads_back_and_parses_with_pymoca() -> None:
    model = heated_brake()
    text = model.to_modelica()
    assert st.Model.from_modelica(text) == model
    parser = pytest.importorskip("pymoca.parser")
    tree = parser.parse(text)
    assert tree is not None
