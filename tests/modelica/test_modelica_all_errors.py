"""A Modelica file is read to its end and every error in it is reported at once, each at its
``file:line:column``, sorted by place, as a compiler does (issue 29): a user fixing a
hand-written model sees the whole list, not one error per run. Connection errors (two signal
inputs no output drives, a flange to a heat port, a disabled support) carry the place of their
``connect``."""

from __future__ import annotations

from pathlib import Path

import pytest

import stiction as st

# A brake engineer's wheel stop, written as users write Modelica: qualified imports, an alias,
# nested modifiers, descriptions and annotations; five different mistakes in it.
WHEEL_STOP = """within;
model WheelStop "a wheel stopped by a brake"
  import Modelica.Mechanics.Rotational.Components;
  import SI = Modelica.Units.SI;
  parameter SI.Inertia Jw = 2.0 "wheel inertia";
  parameter SI.Force fn = 2*fn_nominal "pressing force";
  Components.Inertia wheel(J=Jw, phi(start=0, fixed=true), w(start=100, fixed=true))
    annotation (Placement(transformation(extent={{-60,-10},{-40,10}})));
  Components.Brake brake(fn_max=fn, peek=1.2, mu_pos=[0, 0.4; 100, 0.35], useHeatPort=false)
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Components.Flywheel fly(J=3) "no such class in MSL";
  Components.Clutch clutch(fn_max=100, cgeo=-1) annotation (Placement());
  Modelica.Blocks.Sources.Ramp press(height=1, duration=0.2, startTime=0.5);
equation
  connect(wheel.flange_b, brake.flange_a) annotation (Line(points={{-40,0},{-10,0}}));
  connect(fly.flange_a, wheel.flange_a);
  connect(brake.f_normalized, clutch.f_normalized);
  connect(clutch.flange_c, wheel.flange_a);
  annotation (experiment(StopTime=2, Interval=1e-3));
end WheelStop;
"""


def _at(text: str, needle: str, nth: int = 0) -> tuple[int, int]:
    """Line and column (from 1) of the ``nth`` occurrence of ``needle`` in ``text``."""
    offset = -1
    for _ in range(nth + 1):
        offset = text.index(needle, offset + 1)
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _refused(text: str, **kwargs: str) -> st.ModelError:
    with pytest.raises(st.ModelError) as info:
        st.Model.from_modelica(text, **kwargs)
    return info.value


def test_every_error_of_a_file_is_reported_at_its_place() -> None:
    error = _refused(WHEEL_STOP)
    expected = [
        (*_at(WHEEL_STOP, "fn_nominal"), "'fn_nominal' is undefined"),
        (*_at(WHEEL_STOP, "peek"), "unknown modifier 'peek'"),
        (*_at(WHEEL_STOP, "Components.Flywheel"), "unknown MSL class"),
        (*_at(WHEEL_STOP, "cgeo=-1"), "parameter 'cgeo'"),
        (*_at(WHEEL_STOP, "connect(brake.f_normalized"), "signal inputs with no output driving them"),
        (*_at(WHEEL_STOP, "clutch.flange_c"), "no port 'flange_c'"),
    ]
    assert [(line, col) for line, col, _ in error.errors] == [(line, col) for line, col, _ in expected]
    for (_, _, message), (_, _, words) in zip(error.errors, expected, strict=True):
        assert words in message, (words, message)
    lines = str(error).splitlines()
    assert len(lines) == len(expected)
    for text, (line, col, words) in zip(lines, expected, strict=True):
        assert text.startswith(f"<modelica>:{line}:{col}: "), text
        assert words in text, (words, text)


def test_no_error_follows_from_another() -> None:
    """An unknown class is one error, not one more per connect to it; a parameter that cannot
    be evaluated is one error, not one more per parameter or modifier that uses it."""
    text = """model M
  import Modelica.Mechanics.Rotational.Components;
  parameter Real a = 1/0;
  parameter Real b = 2*a;
  Components.Inertia J(J=b, w(start=a, fixed=true));
  Components.Flywheel fly(J=3);
equation
  connect(J.flange_a, fly.flange_b);
  connect(fly.flange_a, J.flange_b);
end M;
"""
    error = _refused(text)
    assert [(line, col) for line, col, _ in error.errors] == [
        _at(text, "/0"),
        _at(text, "Components.Flywheel"),
    ]
    assert "division by zero" in error.errors[0][2]


def test_refused_constructs_are_all_reported_before_a_syntax_error() -> None:
    """Constructs the parser refuses but can read past (a conditional or replaceable
    component, an equation, a `when`, an algorithm section) are collected; a syntax error
    stops the reading and comes last."""
    text = """model M
  import Modelica.Mechanics.Rotational.Components;
  replaceable Components.Inertia J1(J=1);
  Components.Inertia J2(J=1) if false;
  Components.Inertia J3(J=1, w(start=1, fixed=true));
  Components.Inertia J4[2](each J=1);
equation
  J3.w = 2;
  when time > 1 then
    J3.phi = 0;
  end when;
  connect(J1.flange_b, J3.flange_a);
algorithm
  x := 1;
end M;
"""
    error = _refused(text)
    expected = [
        (_at(text, "replaceable"), "replaceable"),
        (_at(text, "if false"), "conditional component"),
        (_at(text, "[2]"), "array component"),
        (_at(text, "J3.w = 2"), "unsupported equation"),
        (_at(text, "when"), "unsupported when"),
        (_at(text, "algorithm"), "algorithm"),
    ]
    assert [(line, col) for line, col, _ in error.errors] == [where for where, _ in expected]
    for (_, _, message), (_, words) in zip(error.errors, expected, strict=True):
        assert words in message, (words, message)
    broken = text.replace("connect(J1.flange_b, J3.flange_a);", "connect(J1.flange_b J3.flange_a);")
    error = _refused(broken)
    assert [(line, col) for line, col, _ in error.errors][:4] == [where for where, _ in expected[:4]]
    assert "syntax error" in error.errors[-1][2]
    assert error.errors[-1][:2] == _at(broken, "J3.flange_a);")


SIGNAL_INPUTS = """model Press
  import Modelica.Mechanics.Rotational.Components;
  Components.Inertia J(J=1, w(start=10, fixed=true));
  Components.Brake brake(fn_max=100);
  Components.Clutch clutch(fn_max=100);
  Components.Fixed ground;
  Modelica.Blocks.Sources.Constant force(k=1);
equation
  connect(J.flange_b, brake.flange_a);
  connect(brake.flange_b, clutch.flange_a);
  connect(clutch.flange_b, ground.flange);
  connect(force.y, brake.f_normalized);
  connect(brake.f_normalized, clutch.f_normalized) "the clutch pressed as the brake";
end Press;
"""


def test_a_chain_of_signal_inputs_is_one_connection_set() -> None:
    """Modelica connects sets: the clutch input chained to the brake's is fed by the one
    output driving the set, as if connected to it directly (bit-identical run)."""
    chained = st.Model.from_modelica(SIGNAL_INPUTS)
    assert ("force.y", "clutch.f_normalized") in chained.connections
    direct = st.Model.from_modelica(
        SIGNAL_INPUTS.replace(
            "connect(brake.f_normalized, clutch.f_normalized)", "connect(force.y, clutch.f_normalized)"
        )
    )
    a, b = chained.simulate(), direct.simulate()
    assert (a["clutch.tau"] == b["clutch.tau"]).all() and (a["J.w"] == b["J.w"]).all()


def test_a_connection_set_with_two_outputs_or_none_is_refused_at_its_place() -> None:
    two = SIGNAL_INPUTS.replace(
        "  connect(force.y, brake.f_normalized);",
        "  connect(force.y, brake.f_normalized);\n  connect(other.y, clutch.f_normalized);",
    ).replace("equation", "  Modelica.Blocks.Sources.Constant other(k=0.5);\nequation")
    error = _refused(two)
    line, col = _at(two, "connect(force.y")
    assert error.errors == [(line, col, error.errors[0][2])], error.errors
    assert "2 signal outputs drive it (force.y, other.y)" in str(error), str(error)
    none = SIGNAL_INPUTS.replace("  connect(force.y, brake.f_normalized);\n", "")
    error = _refused(none)
    line, col = _at(none, "connect(brake.f_normalized")
    assert error.errors == [(line, col, error.errors[0][2])], error.errors
    assert "brake.f_normalized, clutch.f_normalized: signal inputs with no output" in str(error), str(error)


PRESSED = """model M
  import Modelica.Mechanics.Rotational.Components;
  import Modelica.Thermal.HeatTransfer.Components.HeatCapacitor;
  Components.Inertia J(J=1, w(start=10, fixed=true));
  Components.Brake brake(fn_max=100, useHeatPort=true);
  HeatCapacitor disc(C=100, T(start=293.15, fixed=true));
  Modelica.Blocks.Sources.Constant k1(k=1);
  Modelica.Blocks.Sources.Constant k2(k=1);
  Components.Fixed ground;
equation
  connect(J.flange_b, brake.flange_a);
  connect(brake.flange_b, ground.flange);
  connect(k1.y, brake.f_normalized);
  connect(brake.heatPort, disc.port) annotation (Line(color={191,0,0}));
  {}
end M;
"""

# (what, the connect, where its error is placed, words of the engine's own message)
CONNECTIONS = [
    ("two signal outputs", "connect(k1.y, k2.y);", "connect", "connects two signal outputs"),
    ("a flange to a heat port", "connect(J.flange_a, disc.port);", "connect", "cannot connect"),
    ("a signal to a flange", "connect(k2.y, J.flange_a);", "connect", "cannot connect"),
    (
        "an input fed twice",
        "connect(k2.y, brake.f_normalized);",
        "connect",
        "already connected to another output",
    ),
    ("a disabled support", "connect(J.flange_a, brake.support);", "brake.support", "set useSupport = true"),
]


@pytest.mark.parametrize(("what", "line", "where", "words"), CONNECTIONS, ids=[c[0] for c in CONNECTIONS])
def test_every_connection_error_names_its_connect(what: str, line: str, where: str, words: str) -> None:
    text = PRESSED.replace("{}", line)
    error = _refused(text)
    start = text.index(line)
    assert str(error).startswith(
        "<modelica>:{}:{}: ".format(*_at(text, where, text.count(where, 0, start)))
    ), str(error)
    assert words in str(error), str(error)
    # the engine, given the same model without positions, refuses it in the same words
    model = st.Model.from_modelica(PRESSED.replace("{}", ""))
    a, b = line.removeprefix("connect(").removesuffix(");").split(", ")
    model.connections.append((a, b))
    with pytest.raises(st.ModelError, match=words):
        model.check()


def test_a_long_list_is_cut_after_fifty() -> None:
    body = "".join(
        f"  Modelica.Mechanics.Rotational.Components.Inertia J{k}(J=1, Jx={k});\n" for k in range(60)
    )
    error = _refused(f"model M\n{body}end M;\n")
    lines = str(error).splitlines()
    assert len(error.errors) == 60
    assert len(lines) == 51 and lines[-1] == "... and 10 more"
    assert all(text.startswith(f"<modelica>:{k + 2}:") for k, text in enumerate(lines[:-1]))


def test_cli_prints_every_error(tmp_path: Path, cli_runner) -> None:
    from stiction.cli import main

    path = tmp_path / "WheelStop.mo"
    path.write_text(WHEEL_STOP)
    result = cli_runner.invoke(main, ["import", str(path), "-o", str(tmp_path / "x.toml")])
    assert result.exit_code == 2
    assert "Traceback" not in result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 6, result.stderr
    wheres = [
        f"{path}:{line}:{col}:" for line, col in (_at(WHEEL_STOP, "fn_nominal"), _at(WHEEL_STOP, "peek"))
    ]
    assert lines[0].startswith(f"error: {wheres[0]} ") and lines[1].startswith(f"error: {wheres[1]} ")
    line, col = _at(WHEEL_STOP, "connect(brake.f_normalized")
    assert any(text.startswith(f"error: {path}:{line}:{col}: ") for text in lines), result.stderr
    assert not (tmp_path / "x.toml").exists()


def test_one_error_reads_as_before() -> None:
    text = "model M\n  Modelica.Mechanics.Rotational.Components.Inertia J(Jx=1);\nend M;\n"
    error = _refused(text)
    assert "\n" not in str(error)
    assert error.errors == [(*_at(text, "Jx"), error.detail)]
    assert isinstance(error, st.ModelError)


def test_a_parameter_out_of_range_where_it_is_used_is_placed_at_each_use() -> None:
    """Found by the fuzzer: ``w_nominal = 0`` passed to speed-dependent torques (which need
    it > 0) raised a ModelError without a place; each use is now an error at its modifier."""
    text = """model M
  import Modelica.Mechanics.Rotational.Sources;
  import Modelica.Units.SI;
  parameter SI.AngularVelocity w_nominal(displayUnit="rpm") = 0 "nominal speed";
  Sources.LinearSpeedDependentTorque linear(tau_nominal=-1, w_nominal=w_nominal);
  Sources.QuadraticSpeedDependentTorque quadratic(
    tau_nominal=-1,
    w_nominal=w_nominal);
end M;
"""
    error = _refused(text)
    assert [(line, col) for line, col, _ in error.errors] == [
        _at(text, "w_nominal=w_nominal"),
        _at(text, "w_nominal=w_nominal", 1),
    ]
    assert all("parameter 'w_nominal': must be > 0, got 0" in message for _, _, message in error.errors)


MIRROR = """model M
  import Modelica.Mechanics.Rotational.Components;
  import Modelica.Thermal.HeatTransfer.Components.HeatCapacitor;
  Components.Inertia J1(J=1, w(start=1, fixed=true));
  Components.Inertia J2(J=1);
  Components.Inertia J3(J=1);
  Components.Inertia J4(J=1);
  Components.Brake b1(fn_max=1);
  Components.Brake b2(fn_max=1);
  HeatCapacitor d1(C=1);
  HeatCapacitor d2(C=1);
  Modelica.Blocks.Sources.Constant k1(k=1);
  Modelica.Blocks.Sources.Constant k2(k=1);
equation
  connect(J1.flange_b, b1.flange_a);
  connect(J4.flange_b, b2.flange_a);
  connect(k1.y, b1.f_normalized);
  connect(k1.y, b2.f_normalized);
  {}
end M;
"""
# two ports of each kind: flange, heat port, signal output, signal input (each input fed by k1)
PORTS = [
    "J2.flange_b",
    "J3.flange_a",
    "d1.port",
    "d2.port",
    "k1.y",
    "k2.y",
    "b1.f_normalized",
    "b2.f_normalized",
]


def test_the_connection_check_is_the_engines() -> None:
    """Every pair of ports of every kind: the import refuses a connect exactly when the
    engine refuses the same model without positions, for the same reason."""
    base = st.Model.from_modelica(MIRROR.replace("{}", ""))
    base.check()
    verdicts = []
    for i, a in enumerate(PORTS):
        for b in PORTS[i + 1 :]:
            if {a, b} in ({"k1.y", "b1.f_normalized"}, {"k1.y", "b2.f_normalized"}):
                continue  # connected already
            if {a, b} == {"b1.f_normalized", "b2.f_normalized"}:
                # Modelica's connection set, which the engine's list of pairs does not know: one
                # output (k1) drives both inputs already, so the set is legal and adds nothing
                st.Model.from_modelica(MIRROR.replace("{}", f"connect({a}, {b});")).check()
                continue
            text = MIRROR.replace("{}", f"connect({a}, {b});")
            try:
                st.Model.from_modelica(text)
                ours = None
            except st.ModelError as exc:
                assert str(exc).startswith("<modelica>:{}:{}: ".format(*_at(text, f"connect({a}, {b})"))), (
                    str(exc)
                )
                ours = str(exc).split("): ", 1)[1]
            model = st.Model.from_modelica(MIRROR.replace("{}", ""))
            model.connections.append((a, b))
            try:
                model.check()
                engine = None
            except st.ModelError as exc:
                engine = str(exc).split(": ", 1)[1]
            verdicts.append((a, b, ours is None, engine is None))
            if ours is not None and engine is not None:
                assert sorted(ours.split()) == sorted(engine.split()), (a, b, ours, engine)  # either order
    assert [v for v in verdicts if v[2] != v[3]] == []
    assert [(a, b) for a, b, ok, _ in verdicts if ok] == [
        ("J2.flange_b", "J3.flange_a"),
        ("d1.port", "d2.port"),
    ]
