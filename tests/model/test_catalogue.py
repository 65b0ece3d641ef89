"""The component catalogue: one source (the core) for classes, docstrings, stubs, docs, CLI."""

from __future__ import annotations

import importlib.util
import inspect
import sys

import pytest
from paths import REPO

import stiction as st
from stiction.cli import main
from stiction.model.catalogue import catalogue, show_value

ROOT = REPO


def test_every_parameter_has_description_unit_and_default_or_is_required() -> None:
    missing = []
    for info in catalogue().values():
        # stiction's own components (beyond MSL: SlipWheel) say so in their class
        assert info.msl_class.startswith("Modelica.") or info.msl_class == f"stiction.{info.name}", info.name
        for p in info.parameters:
            where = f"{info.name}.{p.name}"
            if not p.description:
                missing.append(f"{where}: description")
            numeric = p.kind in ("Real", "start value") or p.kind.startswith("table")
            if numeric and not p.unit:
                missing.append(f"{where}: unit")
            if p.default is None and not p.required and p.kind != "String":
                missing.append(f"{where}: default")
    assert missing == []


def test_docstring_and_describe_list_every_parameter_with_default_and_unit() -> None:
    for name, info in catalogue().items():
        text = str(st.describe(name))
        doc = getattr(st, name).__doc__ if name.isidentifier() else text
        for p in info.parameters:
            for where in (doc, text):
                line = next((ln for ln in where.splitlines() if ln.startswith(f"{p.name} : ")), None)
                assert line is not None, f"{name}.{p.name} missing"
                assert (f"[{p.unit}]" in line) == bool(p.unit), line
                shown = show_value(p.default)
                assert ("required" in line) if p.required else (shown in line or p.default is None)


def test_brake_reference_is_msl() -> None:
    brake = st.describe("Brake")
    assert brake.msl_class == "Modelica.Mechanics.Rotational.Components.Brake"
    fn_max, peak = brake.parameter("fn_max"), brake.parameter("peak")
    assert (fn_max.required, fn_max.unit, fn_max.range) == (True, "N", ">= 0")
    assert (peak.default, peak.range) == (1.0, ">= 1")
    assert [show_value(v) for v in (True, 1e10, 0.5, 293.15, [[0.0, 0.5]])] == [
        "true",
        "1e+10",
        "0.5",
        "293.15",
        "[[0, 0.5]]",
    ]
    assert brake.parameter("mu_pos").default == [[0.0, 0.5]]
    ports = {p.name: p for p in brake.ports}
    assert ports["support"].enabled_by == "useSupport" and ports["flange_a"].enabled_by is None
    assert ports["heatPort"].kind == "heat port" and ports["f_normalized"].kind == "signal input"
    units = {v.name: v.unit for v in brake.variables}
    assert units["tau"] == "N.m" and units["w"] == "rad/s" and units["lossPower"] == "W"
    with pytest.raises(st.ModelError, match="did you mean 'fn_max'"):
        brake.parameter("fn_mx")
    with pytest.raises(st.ModelError, match="did you mean 'Brake'"):
        st.describe("Brak")


def test_signatures_are_the_catalogue_parameters() -> None:
    sig = inspect.signature(st.Brake)
    assert list(sig.parameters) == [p.name for p in st.describe("Brake").parameters]
    assert sig.parameters["fn_max"].default is inspect.Parameter.empty  # required
    assert sig.parameters["peak"].default == 1.0
    assert all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in sig.parameters.values())
    # unknown names still reach the core's check with its suggestion
    with pytest.raises(st.ModelError, match="did you mean 'fn_max'"):
        st.Model("m").add("b", st.Brake(fn_mx=1.0))


def test_catalogue_variables_are_what_a_run_reports() -> None:
    m = st.Model("m")
    m.add("J", st.Inertia(J=1.0, w=1.0))
    # every conditional port and variable on (the wear record's `wearVolume`, `thickness`)
    wear = st.wear.Energy(alpha=1e-13, A=1e-3, thickness=0.01)
    m.add("brake", st.Brake(fn_max=10.0, useSupport=True, useHeatPort=True, wear=wear))
    m.add("fix", st.Fixed())
    m.add("disc", st.HeatCapacitor(C=10.0))
    m.add("f", st.Constant(k=0.5))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("brake.support", "fix.flange")
    m.connect("brake.heatPort", "disc.port")
    m.connect("f.y", "brake.f_normalized")
    r = m.simulate(StopTime=0.01)
    for comp, type_name in [("brake", "Brake"), ("J", "Inertia"), ("disc", "HeatCapacitor")]:
        reported = {n.split(".", 1)[1] for n in r.names if n.startswith(comp + ".")}
        assert reported == {v.name for v in st.describe(type_name).variables}


def test_a_model_input_may_feed_a_signal_block() -> None:
    """Found by the catalogue (a Gain alone): a block reading a model input is not a loop."""
    m = st.Model("m")
    m.add("g", st.Gain(k=2.0))
    m.add("src", st.Torque())
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.connect("g.y", "src.tau")
    m.connect("src.flange", "J.flange_a")
    m.input("g.u", start=3.0)
    r = m.simulate(StopTime=1.0)
    assert r["J.w"][-1] == pytest.approx(6.0)


def test_generated_files_are_current() -> None:
    spec = importlib.util.spec_from_file_location("generate", ROOT / "scripts" / "generate.py")
    assert spec is not None and spec.loader is not None
    generate = importlib.util.module_from_spec(spec)
    sys.modules["generate"] = generate
    spec.loader.exec_module(generate)
    for path, text in generate.targets().items():
        assert path.read_text() == text, f"{path} is stale: run scripts/generate.py"


def test_cli_list_and_describe(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as done:
        main(["list"])
    assert done.value.code == 0
    out = capsys.readouterr().out
    assert len(out.splitlines()) == len(catalogue())
    assert "Brake" in out and "Modelica.Mechanics.Rotational.Components.Brake" in out
    with pytest.raises(SystemExit):
        main(["describe", "Brake"])
    out = capsys.readouterr().out
    assert "fn_max : Real [N], required, >= 0" in out and "support: flange (if useSupport = true)" in out


def test_the_public_namespace_is_the_api() -> None:
    """dir(st) shows __all__ (and __version__), nothing imported for the package's own use."""
    assert dir(st) == sorted([*st.__all__, "__version__"])
    assert not {"annotations", "Any", "version", "PackageNotFoundError"} & set(dir(st))
    for name in st.__all__:
        assert getattr(st, name) is not None
    for name in ("ModelError", "SimulationError", "StictionError", "UsageError", "SingularSystemError"):
        assert issubclass(getattr(st, name), Exception) and getattr(st, name).__module__ == "stiction"
