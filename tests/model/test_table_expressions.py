"""A scalar inside a table may be a parameter expression (issue 29): ``mu_pos = [[0, "mu0"],
[100, "0.9*mu0"]]`` in a model file, ``st.expr("mu0")`` cells in Python, evaluated against the
top-level parameters before the engine sees the model, so that changing ``mu0`` moves the
table; a Modelica model keeps them as ``mu_pos=[0, mu0; 100, 0.9 * mu0]``. A cell may also be a
quantity in its column's unit (``"10 rpm"``)."""

from __future__ import annotations

import math

import pytest

import stiction as st

TEXT = """name = "braked"
connect = [["J.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"]]

[experiment]
StopTime = 3.0

[parameters]
mu0 = 0.5

[components]
J = { type = "Inertia", J = 1.0, w = 10.0 }
brake = { type = "Brake", fn_max = 20.0, mu_pos = [[0, "mu0"], [100, "0.9*mu0"]] }
press = { type = "Constant", k = 1.0 }
"""


def _engine_table(m: st.Model) -> str:
    return next(line for line in m.engine_toml().splitlines() if line.startswith("brake"))


def test_cells_are_evaluated_against_the_top_level_parameters() -> None:
    m = st.Model.loads(TEXT)
    assert m["brake"].params["mu_pos"] == [[0, "mu0"], [100, "0.9 * mu0"]]  # kept as text
    assert "mu_pos = [[0, 0.5], [100, 0.45]]" in _engine_table(m)
    m.parameters["mu0"] = 0.4
    assert "mu_pos = [[0, 0.4], [100, 0.36000000000000004]]" in _engine_table(m)
    assert st.Model.loads(m.to_toml()) == m  # saved as written


def test_python_takes_expr_cells_and_whole_table_expressions() -> None:
    cells = st.Brake(fn_max=20.0, mu_pos=[[0, st.expr("mu0")], [100, st.expr("0.9*mu0")]])
    assert cells.params["mu_pos"] == [[0, "mu0"], [100, "0.9 * mu0"]]
    whole = st.Brake(fn_max=20.0, mu_pos=st.expr("[0, mu0; 100, 0.9*mu0]"))
    assert whole.params["mu_pos"] == [[0.0, "mu0"], [100.0, "0.9 * mu0"]]
    assert st.Brake(fn_max=1.0, mu_pos=[["10 rpm", 0.5]]).params["mu_pos"] == [[10 * 2 * math.pi / 60, 0.5]]


def test_a_run_and_a_sweep_over_the_parameter_move_the_table() -> None:
    m = st.Model.loads(TEXT)
    fast = m.simulate(params={"mu0": 1.0}).first("brake.locked")
    slow = m.simulate().first("brake.locked")
    assert fast == pytest.approx(slow / 2, rel=1e-6)  # twice the friction: locks in half the time
    table = st.sweep(m, {"mu0": [0.5, 1.0]}, ["time_of(brake.locked)"], progress=False).table
    assert list(table["status"]) == ["ok", "ok"]
    assert table["time_of(brake.locked)"].tolist() == pytest.approx([slow, fast], rel=1e-9)


def test_set_takes_expression_cells() -> None:
    m = st.Model.loads(TEXT)
    m.set("brake.mu_pos", [[0, "2*mu0"]])
    assert "mu_pos = [[0, 1.0]]" in _engine_table(m)
    with pytest.raises(st.ModelError, match=r"parameter 'mu_pos': row 1, column 2: no parameter 'mu9'"):
        m.set("brake.mu_pos", [[0, "mu9"]])


@pytest.mark.parametrize(
    ("cell", "message"),
    [
        ("0.9*", r"parameter 'mu_pos': row 2, column 2: syntax error"),
        ("10 N", r"row 2, column 2: '10 N' is a force, not a dimensionless number \[1\]"),
    ],
)
def test_a_bad_cell_names_its_row_and_column(cell: str, message: str) -> None:
    with pytest.raises(st.ModelError, match=message):
        st.Model.loads(TEXT.replace('"0.9*mu0"', f'"{cell}"'))


def test_modelica_export_and_import_keep_the_expressions() -> None:
    m = st.Model.loads(TEXT)
    text = m.to_modelica()
    assert "mu_pos=[0, mu0; 100, 0.9 * mu0]" in text
    again = st.Model.from_modelica(text)
    assert again["brake"].params["mu_pos"] == [[0.0, "mu0"], [100.0, "0.9 * mu0"]]
    assert "mu_pos = [[0.0, 0.5], [100.0, 0.45]]" in _engine_table(again)


def test_a_running_simulation_takes_a_table_with_expression_cells() -> None:
    m = st.Model.loads(TEXT)
    sim = m.simulation()
    sim.advance_to(0.1)
    sim.set_parameter("brake.mu_pos", [[0, "2*mu0"]])  # mu0 = 0.5: a coefficient of 1
    sim.advance_to(0.2)
    assert sim["brake.mu"] == pytest.approx(1.0)
