"""Models to and from TOML, components, and results to CSV and back."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import stiction as st
from stiction.cli import main
from stiction.results.io.csv import read_csv

# The design document's example, verbatim: `connect` after [components] lands
# under it in TOML.
DESIGN_TOML = """\
name = "braked_flywheel"
[experiment]
StopTime = 2.0
Interval = 1e-3
Tolerance = 1e-6

[components]
J     = { type = "Inertia", J = 2.0, phi = { start = 0.0, fixed = true }, w = 10.0 }
brake = { type = "Brake", fn_max = 100.0, mu_pos = [[0, 0.5], [10, 0.4]], \
peak = 1.2, useHeatPort = true }
disc  = { type = "HeatCapacitor", C = 500.0, T = 293.15 }
press = { type = "Step", height = 1.0, startTime = 0.5 }

connect = [
  ["J.flange_b", "brake.flange_a"],
  ["press.y", "brake.f_normalized"],
  ["brake.heatPort", "disc.port"],
]
"""


def braked_flywheel() -> st.Model:
    m = st.Model("braked_flywheel")
    m.add("J", st.Inertia(J=2.0, phi={"start": 0.0, "fixed": True}, w=10.0))
    m.add(
        "brake",
        st.Brake(fn_max=100.0, mu_pos=[[0, 0.5], [10, 0.4]], peak=1.2, useHeatPort=True),
    )
    m.add("disc", st.HeatCapacitor(C=500.0, T=293.15))
    m.add("press", st.Step(height=1.0, startTime=0.5))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "disc.port")
    m.experiment.update(StopTime=2.0, Interval=1e-3, Tolerance=1e-6)
    return m


def synthetic_result() -> st.Result:
    names = ["time", "J1.w", "clutch.mode", "clutch.startForward", "clutch.locked", "x"]
    data = np.array(
        [
            [0.0, 10.0, -1.0, 0.0, 0.0, 0.1],
            [0.5, 1.0 / 3.0, -1.0, 0.0, 0.0, 1e-300],
            [0.5, 1.0 / 3.0, 0.0, 1.0, 1.0, -2.5e17],
            [1.0, math.pi, 2.0, 0.0, 0.0, math.nan],
        ]
    )
    events = [(0.5, "clutch", -1, 0, "w_rel crossed zero")]
    return st.Result(names, data, events, {"steps": 12, "rhs_evals": 30, "events": 1, "wall_ms": 0.4})


# --- components -----------------------------------------------------------------------
def test_components_are_typed_data() -> None:
    j = st.Inertia(J=2.0, phi=0.0, w=np.float64(10.0))
    assert isinstance(j, st.Component) and isinstance(j, st.Inertia)
    assert (j.type, j.params) == ("Inertia", {"J": 2.0, "phi": 0.0, "w": 10.0})
    assert type(j.params["w"]) is float
    assert repr(j) == "Inertia(J=2.0, phi=0.0, w=10.0)"
    assert j == st.Component("Inertia", {"J": 2.0, "phi": 0.0, "w": 10.0})
    assert "Mechanics.Rotational.Components.Inertia" in (st.Inertia.__doc__ or "")
    with pytest.raises(TypeError):
        st.Inertia(2.0)  # type: ignore[call-arg]  # keyword arguments only
    table = st.TimeTable(table=np.array([[0, 1], [1, 2]]))
    assert table.params["table"] == [[0, 1], [1, 2]]
    with pytest.raises(st.ModelError, match="'J'"):
        st.Inertia(J=None)


def test_every_listed_component_type_has_a_factory() -> None:
    listed = [
        "Inertia",
        "Fixed",
        "Spring",
        "Damper",
        "SpringDamper",
        "IdealGear",
        "Torque",
        "ConstantTorque",
        "TorqueStep",
        "LinearSpeedDependentTorque",
        "QuadraticSpeedDependentTorque",
        "SignTorque",
        "InverseSpeedDependentTorque",
        "ConstantSpeed",
        "Brake",
        "Clutch",
        "Constant",
        "Step",
        "Ramp",
        "Sine",
        "Product",
        "Feedback",
        "Add",
        "Gain",
        "TimeTable",
        "HeatCapacitor",
        "ThermalConductor",
        "Convection",
        "FixedTemperature",
    ]
    for name in listed:
        cls = getattr(st, name)
        assert cls().type == name and issubclass(cls, st.Component) and cls.__doc__


# --- TOML -----------------------------------------------------------------------------
def test_toml_round_trip() -> None:
    m = braked_flywheel()
    text = m.to_toml()
    again = st.Model.loads(text)
    assert again == m
    assert again.to_toml() == text
    assert isinstance(again["J"], st.Inertia)
    # `connect` is written at the top level, before any table
    assert text.index("connect = [") < text.index("[experiment]") < text.index("[components]")


def test_connect_under_components_is_accepted() -> None:
    m = st.Model.loads(DESIGN_TOML)
    assert m == braked_flywheel()
    assert "connect" not in m.components


def test_connect_in_both_places_is_combined() -> None:
    extra = 'connect = [["J.flange_a", "brake.flange_b"]]\n'
    m = st.Model.loads(DESIGN_TOML.replace("[experiment]", extra + "[experiment]"))
    assert m.connections[0] == ("J.flange_a", "brake.flange_b")
    assert len(m.connections) == 4


def test_long_tables_are_written_as_sections() -> None:
    m = st.Model("table")
    m.add("tab", st.TimeTable(table=[[float(i), 0.5 * i] for i in range(30)]))
    m.add("k", st.Constant(k=1.0))
    text = m.to_toml()
    assert "[components.tab]" in text and "[components.k]" in text
    assert st.Model.loads(text) == m
    assert list(st.Model.loads(text).components) == ["tab", "k"]


def test_save_and_load(tmp_path: Path) -> None:
    m = braked_flywheel()
    path = tmp_path / "flywheel.toml"
    m.save(path)
    loaded = st.Model.load(path)
    assert loaded == m
    assert loaded.base_dir == tmp_path.resolve()
    nameless = tmp_path / "nameless.toml"
    nameless.write_text(DESIGN_TOML.replace('name = "braked_flywheel"\n', ""))
    assert st.Model.load(nameless).name == "nameless"


@pytest.mark.parametrize(
    ("text", "culprit"),
    [
        ("name = 'x'\n[components]\nJ = { J = 1.0 }\n", "'J'"),
        ("name = 'x'\nconnect = [['J.flange_a']]\n", r"connect\[0\]"),
        ("name = 'x'\n[experiment]\nStopTme = 1.0\n", "StopTime"),
        ("name = 'x'\nsolver = 'bdf'\n", "'solver'"),
        (
            (
                "name = 'x'\n[components]\nJ = { type = 'Inertia' }\n"
                "connect = [['J.flange_a', 'K.flange_a']]\n"
            ),
            "'K'",
        ),
        ("name = 'x\n", "invalid TOML"),
    ],
)
def test_bad_model_files_raise_model_error(text: str, culprit: str) -> None:
    with pytest.raises(st.ModelError, match=culprit):
        st.Model.loads(text)


def test_model_building_checks() -> None:
    m = st.Model("m")
    m.add("J", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match="already exists"):
        m.add("J", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match="identifier"):
        m.add("2J", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match="unknown component 'K'"):
        m.connect("J.flange_a", "K.flange_b")
    with pytest.raises(st.ModelError, match=r"component\.port"):
        m.connect("J", "J.flange_b")
    assert issubclass(st.ModelError, ValueError)


# --- results --------------------------------------------------------------------------
def test_result_access() -> None:
    r = synthetic_result()
    assert r.names[0] == "time"
    np.testing.assert_array_equal(r.time, [0.0, 0.5, 0.5, 1.0])
    assert r["J1.w"][0] == 10.0
    with pytest.raises(KeyError, match=r"J1\.w"):
        r["J1.ww"]
    assert r.events == [st.Event(0.5, "clutch", -1, 0, "w_rel crossed zero")]
    assert r.events[0].new_mode == 0
    assert r.stats["steps"] == 12
    text = r.summary()
    assert "4 rows, 1 events" in text and "clutch.mode" in text and "steps=12" in text


def test_result_csv_round_trip(tmp_path: Path) -> None:
    r = synthetic_result()
    path = tmp_path / "r.csv"
    r.to_csv(path)
    lines = path.read_text().splitlines()
    assert lines[0] == '"time","J1.w","clutch.mode","clutch.startForward","clutch.locked","x"'
    assert lines[1].split(",")[2:5] == ["-1", "0", "0"]
    assert lines[3].split(",")[2:5] == ["0", "1", "1"]
    names, data = read_csv(path)
    assert names == r.names
    np.testing.assert_array_equal(data, r.data)  # bit-exact, NaN included
    assert st.Result.from_csv(path).names == r.names


def test_result_to_pandas() -> None:
    pytest.importorskip("pandas")
    df = synthetic_result().to_pandas()
    assert df.columns[0] == "time" and df.shape == (4, 6)


def test_result_plot(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    r = synthetic_result()
    fig = r.plot("J1.w", ["clutch.mode", "clutch.locked"], path=tmp_path / "p.png")
    assert len(fig.axes) == 2
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(KeyError):
        r.plot("nope")


# --- with the engine ------------------------------------------------------------------
def test_engine_catalogue_checks_parameters_and_ports() -> None:
    m = st.Model("m")
    with pytest.raises(st.ModelError, match=r"'brake'.*'fn_mx'"):
        m.add("brake", st.Brake(fn_mx=100.0))
    m.add("J", st.Inertia(J=1.0))
    with pytest.raises(st.ModelError, match=r"'J'.*'flange_c'"):
        m.connect("J.flange_c", "J.flange_a")


def test_simulate_braked_flywheel(tmp_path: Path) -> None:
    m = braked_flywheel()
    m.check()
    r = m.simulate(StopTime=1.0)
    assert r.names[0] == "time" and r.time[-1] == pytest.approx(1.0)
    assert r["J.w"][0] == pytest.approx(10.0)
    assert all(isinstance(e, st.Event) for e in r.events)
    assert {"steps", "rhs_evals", "events", "wall_ms"} <= set(r.stats)
    r.to_csv(tmp_path / "r.csv")
    assert st.compare(tmp_path / "r.csv", r).passed


def test_cli_simulate_and_check(tmp_path: Path, cli_runner: CliRunner) -> None:
    model_file = tmp_path / "flywheel.toml"
    braked_flywheel().save(model_file)
    result = cli_runner.invoke(main, ["check", str(model_file)])
    assert result.exit_code == 0, result.output
    out = tmp_path / "out.csv"
    args = ["simulate", str(model_file), "-o", str(out), "--StopTime", "1.0"]
    result = cli_runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    assert read_csv(out)[0][0] == "time"


def test_cli_bad_model_exits_2_without_traceback(tmp_path: Path, cli_runner: CliRunner) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("name = 'x'\n[components]\nJ = { J = 1.0 }\n")
    for command in ("check", "simulate"):
        result = cli_runner.invoke(main, [command, str(bad)])
        assert result.exit_code == 2, result.output
        assert result.stderr.startswith("error: ") and "'J'" in result.stderr
        assert "Traceback" not in result.output + result.stderr
    result = cli_runner.invoke(main, ["check", str(tmp_path / "missing.toml")])
    assert result.exit_code == 2 and result.stderr.startswith("error: ")
