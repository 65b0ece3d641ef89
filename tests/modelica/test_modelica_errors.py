"""Bad Modelica is refused with file:line:column, the name at fault and what is supported;
the language forms of the subset (imports, packages, MSL 3.2 names, tables) are read."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

HEAD = "within Modelica.Mechanics.Rotational.Examples;\nmodel M\n"
OK_BODY = """  Rotational.Components.Inertia J(J=1, w(start=1, fixed=true));
  Rotational.Components.Brake brake(fn_max=10);
  Modelica.Blocks.Sources.Constant c(k=1);
equation
  connect(J.flange_b, brake.flange_a);
  connect(c.y, brake.f_normalized);
"""


def _error(text: str) -> str:
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text)
    return str(info.value)


# (what is wrong, the text, "line:col", words the message must hold)
BAD = [
    ("syntax error", HEAD + "  Rotational.Components.Inertia J(J=1;\nend M;", "3:38", ["expected ')'"]),
    ("unknown MSL class", HEAD + "  Rotational.Components.Flywheel J;\nend M;", "3:3", ["Flywheel", "J"]),
    (
        "unknown modifier",
        HEAD + "  Rotational.Components.Inertia J(Jx=1);\nend M;",
        "3:35",
        ["Jx", "Inertia"],
    ),
    (
        "attributes on a parameter",
        HEAD + "  Rotational.Components.Inertia J(J(start=1));\nend M;",
        "3:35",
        ["'J'", "parameter"],
    ),
    (
        "unsupported equation",
        HEAD + OK_BODY + "  J.w = 2;\nend M;",
        "9:3",
        ["unsupported equation", "J . w = 2", "connect"],
    ),
    (
        "connect to a missing port",
        HEAD + OK_BODY + "  connect(J.flange_c, brake.flange_b);\nend M;",
        "9:11",
        ["flange_c", "ports: flange_a, flange_b"],
    ),
    (
        "connect to a missing component",
        HEAD + OK_BODY + "  connect(K.flange_a, brake.flange_b);\nend M;",
        "9:11",
        ["no component 'K'"],
    ),
    (
        "undefined name in a parameter",
        HEAD + "  parameter Real a = b + 1;\n" + OK_BODY + "end M;",
        "3:22",
        ["'b'", "undefined"],
    ),
    (
        "cyclic parameters",
        HEAD + "  parameter Real a = b;\n  parameter Real b = 2*a;\n" + OK_BODY + "end M;",
        "3:18",
        ["cyclic", "a -> b -> a"],
    ),
    ("missing end", HEAD + OK_BODY, "9:1", ["expected 'end'", "end of file"]),
    ("wrong end name", HEAD + OK_BODY + "end N;", "9:5", ["'M'", "end N"]),
    (
        "type mismatch",
        HEAD + "  parameter Boolean b = 2.5;\n" + OK_BODY + "end M;",
        "3:25",
        ["type mismatch", "'b'", "Boolean"],
    ),
    (
        "a sign before a string (found by the fuzzer)",
        HEAD + '  parameter Real a = - "a description";\n' + OK_BODY + "end M;",
        "3:22",
        ["type mismatch", "operator '-'", "a description"],
    ),
    (
        "type mismatch in a component",
        HEAD + "  Rotational.Components.Inertia J(J=true);\nend M;",
        "3:35",
        ["'J'", "expected a number"],
    ),
    ("when equation", HEAD + OK_BODY + "  when time > 1 then\n  end when;\nend M;", "9:3", ["when"]),
    ("algorithm", HEAD + OK_BODY + "algorithm\nend M;", "9:1", ["algorithm"]),
    (
        "conditional component",
        HEAD + "  Rotational.Components.Inertia J(J=1) if false;\nend M;",
        "3:40",
        ["conditional", "'J"],
    ),
    (
        "replaceable component",
        HEAD + "  replaceable Rotational.Components.Inertia J;\nend M;",
        "3:3",
        ["replaceable"],
    ),
    (
        "min violated",
        HEAD + "  parameter SI.Inertia Jm(min=0) = -1;\n" + OK_BODY + "end M;",
        "3:27",
        ["'Jm'", "min"],
    ),
    (
        "engine range check placed at its modifier",
        HEAD + "  Rotational.Components.Brake b(fn_max=10, peak=0.5);\nend M;",
        "3:44",
        ["'peak'"],
    ),
    ("unterminated string", HEAD + '  parameter String s = "abc;\nend M;', "3:24", ["unterminated string"]),
    ("unterminated comment", HEAD + "  /* never closed\nend M;", "3:3", ["unterminated comment"]),
    ("stray character", HEAD + "  parameter Real a = 1 $ 2;\nend M;", "3:24", ["unexpected '$'"]),
    (
        "variable without binding",
        HEAD + "  Real x;\n" + OK_BODY + "end M;",
        "3:8",
        ["'x'", "no binding"],
    ),
    (
        "der of a parameter binding",
        HEAD + "  parameter Real p = der(q);\n" + OK_BODY + "end M;",
        "3:22",
        ["der"],
    ),
]


@pytest.mark.parametrize(("what", "text", "where", "words"), BAD, ids=[b[0] for b in BAD])
def test_bad_modelica_is_refused_with_its_place(what: str, text: str, where: str, words: list[str]) -> None:
    message = _error(text)
    assert message.startswith(f"<modelica>:{where}:"), message
    for word in words:
        assert word in message, (word, message)


def test_comment_marks_inside_strings_are_text() -> None:
    m = st.Model.from_modelica(
        HEAD + '  parameter String s = "/* not a comment // either";\n' + OK_BODY + "end M;"
    )
    assert m.parameters["s"] == "/* not a comment // either"


def test_errors_name_the_file(tmp_path: Path) -> None:
    path = tmp_path / "Bad.mo"
    path.write_text(HEAD + "  Rotational.Components.Flywheel J;\nend M;")
    with pytest.raises(st.ModelError, match=rf"^{path}:3:3: unknown MSL class"):
        st.Model.from_modelica(path)


def test_cli_reports_bad_modelica_in_one_line(tmp_path: Path, cli_runner) -> None:
    from stiction.cli import main

    path = tmp_path / "Bad.mo"
    path.write_text(HEAD + OK_BODY + "  J.w = 2;\nend M;")
    result = cli_runner.invoke(main, ["simulate", str(path)])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: {path}:9:3: unsupported equation")
    assert "Traceback" not in result.stderr


def test_forms_of_the_subset() -> None:
    """Qualified, alias and wildcard imports; a package; MSL 3.2 names; a matrix and an array
    literal; constants and functions; several models picked by name."""
    text = """
    package Drives "users' package"
      import SI = Modelica.SIunits;
      import Modelica.Mechanics.Rotational.Components;
      import Modelica.Blocks.Sources.*;
      model A
        parameter SI.Frequency f(displayUnit="Hz") = 2/Modelica.Constants.pi;
        parameter Real w0 = sqrt(4) + exp(0) - cos(0) "= 2";
        parameter Boolean heat = false;
        parameter Real w100 = Modelica.SIunits.Conversions.from_rpm(100) "MSL 3.2 spelling";
        Components.Inertia J(J=1, phi(fixed=true, start=0), w(start=w0, fixed=true));
        Components.Brake brake(fn_max=10, mue_pos=[0, 0.5; 1, 0.3], useHeatPort=heat);
        Sine s(freqHz=f, amplitude=0.5, offset=0.5);
        Modelica.Mechanics.Rotational.Components.BearingFriction b(tau_pos={{0, 0.1}, {1, 0.2}});
        Modelica.Thermal.HeatTransfer.Celsius.FixedTemperature amb(T=20);
      equation
        connect(J.flange_b, brake.flange_a);
        connect(s.y, brake.f_normalized);
        connect(J.flange_a, b.flange_b);
        annotation(experiment(StartTime=0, StopTime=0.5, Interval=1e-3, Tolerance=1e-7));
      end A;
      model B
        Components.Inertia J(J=2);
      end B;
    end Drives;
    """
    a = st.Model.from_modelica(text, model="A")
    assert a.parameters == {
        "f": pytest.approx(2 / 3.141592653589793),
        "w0": 2.0,
        "heat": False,
        "w100": pytest.approx(10.471975511965976),
    }
    assert a.components["J"].params == {"J": 1.0, "phi": 0.0, "w": {"expr": "w0"}}  # fixed start w0
    assert a.components["brake"].params == {
        "fn_max": 10.0,
        "mu_pos": [[0.0, 0.5], [1.0, 0.3]],
        "useHeatPort": {"expr": "heat"},
    }
    assert a.components["s"].params["f"] == {"expr": "f"}
    assert a.parameter_values()["s.f"] == pytest.approx(0.6366197723675814)
    assert a.components["b"].params["tau_pos"] == [[0.0, 0.1], [1.0, 0.2]]
    assert a.components["amb"].type == "Celsius.FixedTemperature"
    assert a.experiment == {"StartTime": 0.0, "StopTime": 0.5, "Interval": 1e-3, "Tolerance": 1e-7}
    assert st.Model.from_modelica(text, model="Drives.B").components["J"].params == {"J": 2.0}
    with pytest.raises(st.ModelError, match="several models"):
        st.Model.from_modelica(text)
    r = a.simulate()
    assert r["J.w"][0] == 2.0 and r["J.w"][-1] < 2.0  # the brake slows it down


def test_combi_time_table_reads_as_a_time_table() -> None:
    text = """
    model T
      Modelica.Blocks.Sources.CombiTimeTable profile(table=[0, 0; 1, 1; 2, 1],
        extrapolation=Modelica.Blocks.Types.Extrapolation.HoldLastPoint);
      Modelica.Mechanics.Rotational.Sources.Torque torque;
      Modelica.Mechanics.Rotational.Components.Inertia J(J=1, phi(start=0, fixed=true), w(start=0, fixed=true));
    equation
      connect(profile.y[1], torque.tau);
      connect(torque.flange, J.flange_a);
      annotation(experiment(StopTime=3));
    end T;
    """
    m = st.Model.from_modelica(text)
    assert m.components["profile"].type == "TimeTable"
    assert m.components["profile"].params == {
        "table": [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]],
        "extrapolation": "HoldLastPoint",
    }
    assert m.connections[0] == ("profile.y", "torque.tau")
    r = m.simulate()
    assert r["J.w"][-1] == pytest.approx(0.5 + 1.0 + 1.0, rel=1e-6)  # ∫ torque dt


def test_derived_variable_may_use_a_parameter() -> None:
    text = (
        HEAD
        + "  parameter Real k = 3;\n  Real kw = k*J.w;\n"
        + OK_BODY
        + "  annotation(experiment(StopTime=0.1));\nend M;"
    )
    m = st.Model.from_modelica(text)
    assert m.variables == {"kw": "k * J.w"}
    r = m.simulate()
    assert np.array_equal(r["kw"], 3.0 * r["J.w"])
    m.parameters["k"] = 4.0  # a sweep changes the derived variable too
    assert np.array_equal(m.simulate()["kw"], 4.0 * r["J.w"])


def test_damaged_text_gives_a_model_error_never_another_exception() -> None:
    """Every cut and 150 random small edits of an MSL example: a ModelError or a model."""
    import random

    examples = MSL_EXAMPLES
    text = (examples / "SimpleGearShift.mo").read_text()
    rng = random.Random(11)
    damaged = [text[:cut] for cut in range(0, len(text), 53)]
    for _ in range(150):
        i = rng.randrange(len(text))
        edit = rng.choice(["", "(", ")", ";", "=", '"', "{", ".", "x", "1e", "/*", "end", "der("])
        damaged.append(text[:i] + edit + text[i + rng.randrange(0, 5) :])
    for variant in damaged:
        try:
            st.Model.from_modelica(variant)
        except st.ModelError as exc:
            assert str(exc).startswith("<modelica>:"), str(exc)


def test_reals_without_a_range_accept_any_finite_value() -> None:
    """The import checks one component per distinct values of the parameters that can be
    wrong, treating a Real without a declared range as always valid (500 steps differing in
    startTime are one check). This holds the engine to that: every such Real, at extreme
    finite values, passes its component's check."""
    from stiction.model.catalogue import catalogue
    from stiction.modelica.value_check import batch_problem, free_reals

    refused = []
    for stype, keys in free_reals().items():
        info = catalogue()[stype]
        base = {p.name: 1.0 for p in info.parameters if p.required and p.kind == "Real"}
        if batch_problem([("c", stype, base)], ".") is not None:
            continue  # needs a file or table to exist at all (TimeTable)
        refused += [
            (stype, key, value)
            for key in keys
            for value in (-1e300, -1.0, 0.0, 1e300)
            if batch_problem([("c", stype, {**base, key: value})], ".") is not None
        ]
    assert refused == []
    assert "startTime" in free_reals()["Step"] and "J" not in free_reals()["Inertia"]


# Found by fuzzing (tests/properties/test_fuzz_modelica.py): each crashed with a Python exception before.
ARITHMETIC = [
    ("a 400-digit literal", "9" * 400, ["Integer literal", "out of range"]),
    ("a 5000-digit literal (found by the fuzzer)", "9" * 5000, ["Integer literal", "out of range"]),
    ("1e400", "1e400", ["too large for a Real"]),
    ("an Integer power too large", "10^400", ["too large"]),
    ("division by zero", "1/0", ["division by zero"]),
    ("nesting deeper than the stack", "(" * 5000 + "1" + ")" * 5000, ["nested too deeply"]),
    ("a 20000-term sum", "1+" * 20000 + "1", ["deeper than 200 levels"]),
]


@pytest.mark.parametrize(("what", "value", "words"), ARITHMETIC, ids=[a[0] for a in ARITHMETIC])
def test_values_python_cannot_hold_are_located_errors(what: str, value: str, words: list[str]) -> None:
    message = _error(HEAD + f"  parameter Real p = {value};\n" + OK_BODY + "end M;")
    assert message.startswith("<modelica>:3:"), message
    for word in words:
        assert word in message, (word, message)
