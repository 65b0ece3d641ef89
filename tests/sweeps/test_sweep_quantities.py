"""Sweeps take quantities and tables with expression cells (issue 29): ``"100 rpm"`` in a
column is converted once to the parameter's unit; a table whose cells are expressions is
evaluated with each variant's top-level parameters; a quantity of the wrong kind raises
``ModelError`` before anything runs."""

from __future__ import annotations

import math

import pytest

import stiction as st

RPM = 2 * math.pi / 60


def _model(parameters: bool = True) -> st.Model:
    m = st.Model("braked")
    if parameters:
        m.parameters["mu0"] = 0.5
    m.add("J", st.Inertia(J=1.0, w=10.0))
    m.add("brake", st.Brake(fn_max=20.0, mu_pos=[[0, 0.5]]))
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment["StopTime"] = 5.0
    return m


def test_quantity_columns_are_converted_to_the_parameters_unit() -> None:
    result = st.sweep(_model(), {"J.w": ["60 rpm", "120 rpm"]}, ["max(J.w)"], progress=False)
    assert result.table["J.w"].tolist() == pytest.approx([60 * RPM, 120 * RPM])  # the table shows SI
    assert result.table["max(J.w)"].tolist() == pytest.approx([60 * RPM, 120 * RPM])
    assert list(result.table["status"]) == ["ok", "ok"]


def test_tables_with_expression_cells_follow_each_variant() -> None:
    m = _model()
    tables = [[[0, "mu0"]], [[0, "2*mu0"]]]
    grid = st.grid({"mu0": [0.25, 0.5], "brake.mu_pos": tables})
    result = st.sweep(m, grid, ["time_of(brake.locked)"], progress=False)
    t = result.table["time_of(brake.locked)"].tolist()
    # friction mu0, 2*mu0 for mu0 = 0.25 and 0.5: 0.25, 0.5, 0.5, 1.0
    assert t[1] == pytest.approx(t[2]) and t[0] == pytest.approx(2 * t[1]) and t[1] == pytest.approx(2 * t[3])


def test_a_table_expression_without_its_parameter_raises() -> None:
    with pytest.raises(st.ModelError, match="no parameter 'mu0'"):
        st.sweep(_model(parameters=False), {"brake.mu_pos": [[[0, "mu0"]]]}, ["max(J.w)"], progress=False)


def test_a_quantity_of_the_wrong_kind_raises_before_running() -> None:
    with pytest.raises(st.ModelError, match=r"parameter 'w': '100 km/h' is a speed, not an angular velocity"):
        st.sweep(_model(), {"J.w": ["100 km/h"]}, ["max(J.w)"], progress=False)
