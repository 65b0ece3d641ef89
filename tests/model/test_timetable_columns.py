"""A TimeTable of several value columns (MSL's CombiTimeTable with ``columns``): each output
y[i] is the one-column TimeTable of its column, bit for bit, through exact Speed sources (its
derivatives) and torques (its values); wrong columns and offsets are refused by name; the
Modelica import maps ``y[i]`` connects and the export writes them back."""

from __future__ import annotations

import numpy as np
import pytest

import stiction as st

ROWS = [
    [0.0, 0.0, 1.0, -2.0],
    [0.5, 2.0, 1.0, -2.0],
    [0.5, 3.0, 0.0, 1.0],
    [1.2, 3.0, -1.5, 1.0],
    [2.0, 0.5, -1.5, 4.0],
]
OFFSETS = [0.25, -1.0, 0.5]
DRIVEN = """
[components.s{i}]
type = "Speed"
exact = true
[components.J{i}]
type = "Inertia"
J = 2.0
[components.tau{i}]
type = "Torque"
[components.K{i}]
type = "Inertia"
J = 0.5
phi = 0.0
w = 0.0
"""


def _model(tables: str, outputs: list[str], extrapolation: str) -> st.Model:
    text = f'name = "columns"\n[experiment]\nStopTime = 3.0\nInterval = 0.01\n{tables}'
    text = text.replace("EXTRAPOLATION", extrapolation)
    connect = []
    for i, out in enumerate(outputs):
        text += DRIVEN.format(i=i)
        connect += [
            [out, f"s{i}.w_ref"],
            [f"s{i}.flange", f"J{i}.flange_a"],
            [out, f"tau{i}.tau"],
            [f"tau{i}.flange", f"K{i}.flange_a"],
        ]
    return st.Model.loads(f"connect = {connect!r}\n".replace("'", '"') + text)


def _wide(extrapolation: str) -> st.Model:
    table = (
        f'[components.tab]\ntype = "TimeTable"\ntable = {ROWS!r}\ncolumns = [3, 2, 4]\n'
        f'offset = [{OFFSETS[1]}, {OFFSETS[0]}, {OFFSETS[2]}]\nstartTime = 0.3\nextrapolation = "EXTRAPOLATION"\n'
    )
    return _model(table, ["tab.y[1]", "tab.y[2]", "tab.y[3]"], extrapolation)


def _narrow(extrapolation: str) -> st.Model:
    tables = ""
    for c, column in enumerate((2, 1, 3)):  # the wide table's columns 3, 2, 4
        rows = [[r[0], r[column]] for r in ROWS]
        tables += (
            f'[components.tab{c}]\ntype = "TimeTable"\ntable = {rows!r}\noffset = {OFFSETS[column - 1]}\n'
            'startTime = 0.3\nextrapolation = "EXTRAPOLATION"\n'
        )
    return _model(tables, ["tab0.y", "tab1.y", "tab2.y"], extrapolation)


@pytest.mark.parametrize("extrapolation", ["LastTwoPoints", "HoldLastPoint"])
def test_each_output_is_the_one_column_table_of_its_column_bit_for_bit(extrapolation: str) -> None:
    wide, narrow = _wide(extrapolation), _narrow(extrapolation)
    r_wide, r_narrow = wide.simulate(), narrow.simulate()
    assert np.array_equal(r_wide.time, r_narrow.time)
    for i in range(3):
        for var in (f"J{i}.phi", f"J{i}.w", f"K{i}.phi", f"K{i}.w", f"tau{i}.tau"):
            assert np.array_equal(r_wide[var], r_narrow[var]), var
        assert np.array_equal(r_wide[f"tab.y[{i + 1}]"], r_narrow[f"tab{i}.y"])
    # and they are the table at t = 1 s (0.7 s after startTime): columns 3 and 2, with offsets
    t = r_wide.time
    at = np.searchsorted(t, 1.0)
    assert r_wide["tab.y[1]"][at] == pytest.approx(OFFSETS[1] - 1.5 * 0.2 / 0.7)
    assert r_wide["tab.y[2]"][at] == pytest.approx(OFFSETS[0] + 3.0)


def _refusal(**params: object) -> str:
    m = st.Model("bad")
    m.add("tab", st.TimeTable(table=ROWS, **params))
    with pytest.raises(st.ModelError) as err:
        m.compile()
    return str(err.value)


def test_a_column_outside_the_table_is_refused_by_name() -> None:
    message = _refusal(columns=[2, 5])
    assert "tab" in message and "columns" in message and "column 5" in message


def test_offsets_of_another_length_are_refused_by_name() -> None:
    message = _refusal(offset=[1.0, 2.0])
    assert "tab" in message and "offset" in message and "2 values for 3 output columns" in message


MO = """
model M
  Modelica.Blocks.Sources.CombiTimeTable tab(table=[0, 1, 2; 1, 3, 4], columns={3, 2}, offset={0.5, 1});
  Modelica.Mechanics.Rotational.Sources.Torque t1;
  Modelica.Mechanics.Rotational.Sources.Torque t2;
  Modelica.Mechanics.Rotational.Components.Inertia J1(J=1, phi(start=0, fixed=true), w(start=0, fixed=true));
  Modelica.Mechanics.Rotational.Components.Inertia J2(J=1, phi(start=0, fixed=true), w(start=0, fixed=true));
equation
  connect(tab.y[1], t1.tau);
  connect(tab.y[2], t2.tau);
  connect(t1.flange, J1.flange_a);
  connect(t2.flange, J2.flange_a);
  annotation(experiment(StopTime=1));
end M;
"""


def test_modelica_columns_import_and_export_round_trip() -> None:
    m = st.Model.from_modelica(MO)
    assert m.components["tab"].params == {
        "table": [[0.0, 1.0, 2.0], [1.0, 3.0, 4.0]],
        "columns": [3, 2],
        "offset": [0.5, 1.0],
    }
    assert set(m.connections) >= {("tab.y[1]", "t1.tau"), ("tab.y[2]", "t2.tau")}
    r = m.simulate()
    assert r["J1.w"][-1] == pytest.approx(0.5 + 3.0, rel=1e-9)  # ∫ (0.5 + 2 + 2t) dt over 1 s
    text = m.to_modelica()
    assert "CombiTimeTable" in text and "tab.y[2]" in text
    back = st.Model.from_modelica(text)
    assert back.components["tab"].params == m.components["tab"].params
    assert np.array_equal(back.simulate()["J2.w"], r["J2.w"])


@pytest.mark.parametrize(
    ("modifier", "words"),
    [
        ("columns={2, 4}", "column 4 is not a value column"),
        ("offset={1, 2, 3}", "offset must have one value or one per output column"),
    ],
)
def test_modelica_refusals_name_the_modifier_and_its_place(modifier: str, words: str) -> None:
    text = MO.replace("columns={3, 2}, offset={0.5, 1}", modifier)
    with pytest.raises(st.ModelError) as err:
        st.Model.from_modelica(text)
    assert words in str(err.value) and "<modelica>:3:" in str(err.value)
