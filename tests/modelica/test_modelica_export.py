"""Export to Modelica and back: the same model (components, parameters, connections,
experiment, derived variables) and the identical result, for every example."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from paths import REPO

import stiction as st

EXAMPLES = REPO / "examples" / "msl"
SOURCES = [
    *sorted(EXAMPLES.glob("*.toml")),
    *sorted(p for p in EXAMPLES.glob("*.mo")),
    REPO / "examples" / "braked_flywheel.toml",
]


def _load(path: Path) -> st.Model:
    return st.Model.from_modelica(path) if path.suffix == ".mo" else st.Model.load(path)


@pytest.mark.parametrize("path", SOURCES, ids=[f"{p.stem}{p.suffix}" for p in SOURCES])
def test_export_then_import_is_the_same_model_and_result(path: Path, tmp_path: Path) -> None:
    model = _load(path)
    out = tmp_path / f"{model.name}.mo"
    text = model.to_modelica(out)
    assert "Modelica.Mechanics.Rotational.Components." in text and "connect(" in text
    back = st.Model.from_modelica(out)
    assert back == model  # components (parameters, order), connections, experiment, variables
    r0, r1 = model.simulate(), back.simulate()
    assert r1.names == r0.names
    assert np.array_equal(r1.data, r0.data)


def test_export_is_plain_qualified_modelica() -> None:
    text = st.Model.load(EXAMPLES / "OneWayClutch.toml").to_modelica()
    assert text.startswith("model OneWayClutch\n") and text.endswith("end OneWayClutch;\n")
    assert "Modelica.Mechanics.Rotational.Components.OneWayClutch oneWayClutch(" in text
    assert "startForward(start=false, fixed=true)" in text
    assert "inertiaIn(J=1.0, phi(start=0.0, fixed=true), w(start=-0.5, fixed=true))" in text
    assert "annotation(experiment(StartTime=0.0, StopTime=2.0, Interval=0.0005, Tolerance=1e-06));" in text
    sign = st.Model.load(EXAMPLES / "CompareBrakingTorque.toml").to_modelica()
    assert "reg=Modelica.Mechanics.Rotational.Types.Regularization.Linear" in sign


def test_file_backed_time_table_exports_as_combi_time_table(tmp_path: Path) -> None:
    src = REPO / "examples"
    for name in ("brake_force_profile.toml", "brake_force_profile.csv"):
        shutil.copy(src / name, tmp_path / name)
    model = st.Model.load(tmp_path / "brake_force_profile.toml")
    text = model.to_modelica(tmp_path / "Profile.mo")
    assert "Modelica.Blocks.Sources.CombiTimeTable profile(table=[0.0, 0.0; 0.3, 0.0; 0.5, 0.8;" in text
    assert "connect(profile.y[1], brake.f_normalized);" in text
    back = st.Model.from_modelica(tmp_path / "Profile.mo")
    assert back.components["profile"].type == "TimeTable" and "file" not in back.components["profile"].params
    r0, r1 = model.simulate(), back.simulate()
    assert np.array_equal(r1.data, r0.data)


def test_cli_import_and_export(tmp_path: Path, cli_runner) -> None:
    from stiction.cli import main

    toml = tmp_path / "cc.toml"
    done = cli_runner.invoke(main, ["import", str(EXAMPLES / "CoupledClutches.mo"), "-o", str(toml)])
    assert done.exit_code == 0, done.stderr
    mo = tmp_path / "CC.mo"
    done = cli_runner.invoke(main, ["export", str(toml), "-o", str(mo)])
    assert done.exit_code == 0, done.stderr
    assert (
        st.Model.from_modelica(mo)
        == st.Model.load(toml)
        == st.Model.from_modelica(EXAMPLES / "CoupledClutches.mo")
    )


@pytest.mark.parametrize("path", SOURCES, ids=[f"{p.stem}{p.suffix}" for p in SOURCES])
def test_an_independent_modelica_parser_reads_the_export(path: Path) -> None:
    """pymoca (an ANTLR grammar of full Modelica) parses what we write, with the same
    declarations and connect equations."""
    pymoca_parser = pytest.importorskip("pymoca.parser")
    model = _load(path)
    tree = pymoca_parser.parse(model.to_modelica())
    cls = tree.classes[model.name]
    declared = [*model.parameters, *model.components, *model.variables]
    assert [s for s in cls.symbols if s in declared] == declared
    assert len(cls.equations) == len(model.connections)
    if path.suffix == ".mo":  # our hand-written MSL-style examples are valid Modelica too
        assert model.name in _class_names(pymoca_parser.parse(path.read_text()))


def _class_names(node: Any) -> set[str]:
    """Every class name in a pymoca tree (``within`` nests them in packages)."""
    names = set()
    for name, cls in getattr(node, "classes", {}).items():
        names |= {name} | _class_names(cls)
    return names


DECLARED = """
model Declared
  import SI = Modelica.Units.SI;
  parameter SI.Inertia Jx(min=0, displayUnit="kg.m2") = 2 "inertia of the \\"flywheel\\"";
  parameter Real k = 3;
  parameter SI.Time T2 = 0.4 "when it starts";
  Modelica.Mechanics.Rotational.Components.Inertia J1(J=Jx*k, w(start=1, fixed=true));
  annotation(experiment(StopTime=1));
end Declared;
"""


def test_a_parameter_keeps_its_declaration_through_export_and_the_model_file() -> None:
    """Type, attributes and description of a top-level parameter survive .mo → model → .mo and
    the model file; an independent parser reads them back from the export."""
    model = st.Model.from_modelica(DECLARED)
    assert model.declarations == {
        "Jx": {
            "type": "Modelica.Units.SI.Inertia",
            "min": 0.0,
            "displayUnit": "kg.m2",
            "description": 'inertia of the "flywheel"',
        },
        "T2": {"type": "Modelica.Units.SI.Time", "description": "when it starts"},
    }
    text = model.to_modelica()
    assert 'parameter Modelica.Units.SI.Inertia Jx(min=0.0, displayUnit="kg.m2") = 2.0' in text
    assert st.Model.from_modelica(text) == model
    assert st.Model.loads(model.to_toml()) == model
    pymoca_parser = pytest.importorskip("pymoca.parser")
    symbol = pymoca_parser.parse(text).classes["Declared"].symbols["Jx"]
    assert str(symbol.type) == "Modelica.Units.SI.Inertia" and "flywheel" in symbol.comment


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ('x = { unit = "s" }', "'x' is not a parameter"),
        ('T2 = { units = "s" }', "unknown key 'units'.*did you mean 'unit'"),
        ("T2 = { min = true }", "'T2.min' must be text or a number"),
    ],
)
def test_a_bad_declaration_names_the_parameter_and_key(table: str, message: str) -> None:
    text = f'name = "M"\nconnect = []\n[parameters]\nT2 = 0.4\n[declarations]\n{table}\n'
    with pytest.raises(st.ModelError, match=message):
        st.Model.loads(text)


def test_an_attribute_the_model_file_does_not_keep_is_left_out_of_the_declaration() -> None:
    text = """
model M
  parameter Real k(stateSelect=StateSelect.prefer, unit="1") = 3;
  Modelica.Mechanics.Rotational.Components.Inertia J1(J=k, w(start=1, fixed=true));
end M;
"""
    model = st.Model.from_modelica(text)
    assert model.declarations == {"k": {"unit": "1"}}
    assert st.Model.loads(model.to_toml()) == model
