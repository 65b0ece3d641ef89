"""Bad models are refused with a message naming the culprit, in Python and on the CLI.

Each case is a model-file text. In Python, loading and simulating it raises
``st.ModelError`` (a ValueError) whose message names the component and the parameter or
port. Through ``python -m stiction simulate`` the same text gives exit code 2 and exactly
one line ``error: …`` on stderr, without a traceback.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import stiction as st
from stiction import _core  # a missing build must fail here, not skip

TIMEOUT = 60.0  # s; a run of these tiny models takes well under a second

GOOD = """\
name = "flywheel"
connect = [
  ["J.flange_b", "brake.flange_a"],
  ["press.y", "brake.f_normalized"],
]

[experiment]
StopTime = 0.5
Interval = 0.01

[components]
J = { type = "Inertia", J = 2.0, phi = 0.0, w = 10.0 }
brake = { type = "Brake", fn_max = 100.0 }
press = { type = "Constant", k = 1.0 }
"""


def _edit(old: str, new: str) -> str:
    assert old in GOOD
    return GOOD.replace(old, new, 1)


BRAKE = 'brake = { type = "Brake", fn_max = 100.0 }'
CONNECT_PRESS = '  ["press.y", "brake.f_normalized"],\n'

GEARBOX = """\
name = "gearbox"
connect = [
  ["pulse.y", "drive.tau"],
  ["drive.flange", "J1.flange_a"],
  ["J1.flange_b", "gear.flange_a"],
  ["gear.flange_b", "backlash.flange_a"],
  ["backlash.flange_b", "planet.sun"],
  ["planet.ring", "ground.flange"],
  ["planet.carrier", "J2.flange_a"],
]

[experiment]
StopTime = 0.5
Interval = 0.01

[components]
pulse = { type = "Pulse", amplitude = 10.0, width = 50.0, period = 0.2 }
drive = { type = "Torque" }
J1 = { type = "Inertia", J = 1.0, phi = 0.0, w = 0.0 }
gear = { type = "LossyGear", ratio = 2.0, lossTable = [[0.0, 0.9, 0.8, 0.1, 0.1], [10.0, 0.85, 0.75, 0.2, 0.2]] }
backlash = { type = "ElastoBacklash", c = 1e4, d = 10.0, b = 0.001 }
planet = { type = "IdealPlanetary", ratio = 2.0 }
ground = { type = "Fixed" }
J2 = { type = "Inertia", J = 3.0, phi = 0.0, w = 0.0 }
"""


def _edit_gearbox(old: str, new: str) -> str:
    assert GEARBOX.count(old) == 1, old
    return GEARBOX.replace(old, new, 1)


LOSS_ROW2 = "[10.0, 0.85, 0.75, 0.2, 0.2]"

# case: (model text, regular expressions the message must contain)
CASES: dict[str, tuple[str, list[str]]] = {
    "negative inertia": (_edit("J = 2.0,", "J = -1.0,"), [r"'J'", r"parameter 'J'", r">= 0|-1"]),
    "NaN inertia": (_edit("J = 2.0,", "J = nan,"), [r"'J'", r"parameter 'J'", r"(?i)nan|finite"]),
    "brake without fn_max": (
        _edit(BRAKE, 'brake = { type = "Brake", mu_pos = [[0, 0.5]] }'),
        [r"'brake'", r"fn_max", r"(?i)missing|required"],
    ),
    "mu_pos not increasing": (
        _edit(BRAKE, 'brake = { type = "Brake", fn_max = 100.0, mu_pos = [[0, 0.5], [10, 0.4], [5, 0.3]] }'),
        [r"'brake'", r"mu_pos", r"(?i)increasing"],
    ),
    "mu_pos repeated speed": (
        _edit(BRAKE, 'brake = { type = "Brake", fn_max = 100.0, mu_pos = [[0, 0.5], [0, 0.4]] }'),
        [r"'brake'", r"mu_pos", r"(?i)strictly increasing"],
    ),
    "mu_pos with 3 columns": (
        _edit(BRAKE, 'brake = { type = "Brake", fn_max = 100.0, mu_pos = [[0, 0.5, 0.1], [10, 0.4, 0.1]] }'),
        [r"'brake'", r"mu_pos", r"(?i)2 columns|columns"],
    ),
    "peak below 1": (
        _edit(BRAKE, 'brake = { type = "Brake", fn_max = 100.0, peak = 0.5 }'),
        [r"'brake'", r"peak", r">= 1|0\.5"],
    ),
    "unknown component type": (
        _edit('type = "Brake"', 'type = "Brakee"'),
        [r"'brake'", r"Brakee", r"(?i)unknown component type", r"'Brake'"],
    ),
    "unknown parameter": (
        _edit("fn_max = 100.0", "fn_max = 100.0, fnmax = 3.0"),
        [r"'brake'", r"'fnmax'", r"(?i)unknown parameter", r"'fn_max'"],
    ),
    "support without useSupport": (
        _edit(CONNECT_PRESS, CONNECT_PRESS + '  ["brake.support", "ground.flange"],\n')
        + 'ground = { type = "Fixed" }\n',
        [r"brake", r"support", r"useSupport"],
    ),
    "signal output wired to a flange": (
        _edit(CONNECT_PRESS, CONNECT_PRESS + '  ["press.y", "J.flange_a"],\n'),
        [r"press\.y", r"J\.flange_a", r"(?i)signal", r"(?i)flange"],
    ),
    "unconnected f_normalized": (
        _edit(CONNECT_PRESS, ""),
        [r"'brake'", r"f_normalized", r"(?i)not connected"],
    ),
    "lossTable speed repeated": (
        _edit_gearbox(LOSS_ROW2, "[0.0, 0.85, 0.75, 0.2, 0.2]"),
        [r"'gear'", r"lossTable", r"(?i)strictly increasing"],
    ),
    "lossTable speed decreasing": (
        _edit_gearbox(LOSS_ROW2, "[-1.0, 0.85, 0.75, 0.2, 0.2]"),
        [r"'gear'", r"lossTable", r"(?i)strictly increasing"],
    ),
    "lossTable efficiency 0": (
        _edit_gearbox("[0.0, 0.9, 0.8,", "[0.0, 0.0, 0.8,"),
        [r"'gear'", r"lossTable", r"eta_mf1", r"\(0, 1\]|> 0"],
    ),
    "lossTable efficiency 1.2": (
        _edit_gearbox(LOSS_ROW2, "[10.0, 0.85, 1.2, 0.2, 0.2]"),
        [r"'gear'", r"lossTable", r"eta_mf2", r"1\.2"],
    ),
    "lossTable with 4 columns": (
        _edit_gearbox(
            "[[0.0, 0.9, 0.8, 0.1, 0.1], [10.0, 0.85, 0.75, 0.2, 0.2]]",
            "[[0.0, 0.9, 0.8, 0.1], [10.0, 0.85, 0.75, 0.2]]",
        ),
        [r"'gear'", r"lossTable", r"(?i)5 columns"],
    ),
    "negative backlash": (
        _edit_gearbox("b = 0.001", "b = -0.001"),
        [r"'backlash'", r"parameter 'b'", r"-0\.001"],
    ),
    "planetary ratio 0": (
        _edit_gearbox('"IdealPlanetary", ratio = 2.0', '"IdealPlanetary", ratio = 0.0'),
        [r"'planet'", r"parameter 'ratio'", r"(?i)> 0|positive"],
    ),
    "planetary ratio negative": (
        _edit_gearbox('"IdealPlanetary", ratio = 2.0', '"IdealPlanetary", ratio = -1.5'),
        [r"'planet'", r"parameter 'ratio'", r"-1\.5"],
    ),
    "pulse width 0": (
        _edit_gearbox("width = 50.0", "width = 0.0"),
        [r"'pulse'", r"parameter 'width'", r"\(0, 100\]|> 0"],
    ),
}


def _cli(model: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stiction", "simulate", str(model), "-o", str(tmp_path / "out.csv")],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        check=False,
    )


def _assert_one_error_line(proc: subprocess.CompletedProcess[str], patterns: list[str]) -> str:
    assert proc.returncode == 2, (proc.returncode, proc.stdout, proc.stderr)
    assert "Traceback" not in proc.stdout + proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr
    for pattern in patterns:
        assert re.search(pattern, lines[0]), (pattern, lines[0])
    return lines[0]


def test_the_good_model_runs() -> None:
    """Control: the unedited model simulates, so each failure below is due to its edit."""
    r = st.Model.loads(GOOD).simulate()
    assert r["J.w"][0] == 10.0 and r["brake.mode"][-1] == 0  # braked to a stop in 0.4 s


def test_the_good_gearbox_model_runs() -> None:
    """Control for the LossyGear / ElastoBacklash / IdealPlanetary / Pulse cases below.

    The pulse drives the lossy gear forward, through the backlash into the planetary, whose
    ring is held, so the carrier turns at sun/(1 + ratio).
    """
    r = st.Model.loads(GEARBOX).simulate()
    assert r["J2.w"][-1] > 0.0 and 1.0 in r["gear.mode"]
    np.testing.assert_allclose(3.0 * r["planet.carrier.phi"], r["planet.sun.phi"], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("case", list(CASES))
def test_bad_model_raises_model_error_naming_the_culprit(case: str) -> None:
    """Python: loading or simulating the bad model raises st.ModelError with the names."""
    text, patterns = CASES[case]
    with pytest.raises(st.ModelError) as info:
        st.Model.loads(text).simulate()
    assert isinstance(info.value, ValueError)
    for pattern in patterns:
        assert re.search(pattern, str(info.value)), (pattern, str(info.value))


@pytest.mark.parametrize("case", list(CASES))
def test_bad_model_on_the_cli_exits_2_with_one_error_line(case: str, tmp_path: Path) -> None:
    """CLI: exit code 2, a single `error: …` line naming the culprit, no traceback, no CSV."""
    text, patterns = CASES[case]
    model = tmp_path / "bad.toml"
    model.write_text(text)
    line = _assert_one_error_line(_cli(model, tmp_path), patterns)
    assert str(model) in line  # the file is named too
    assert not (tmp_path / "out.csv").exists()


def test_toml_syntax_error(tmp_path: Path) -> None:
    """A TOML syntax error names the file and the line, in Python and on the CLI."""
    text = _edit("J = 2.0,", "J = 2.0,,")
    with pytest.raises(st.ModelError, match=r"(?i)invalid TOML.*line 12"):
        st.Model.loads(text)
    model = tmp_path / "syntax.toml"
    model.write_text(text)
    _assert_one_error_line(_cli(model, tmp_path), [r"(?i)invalid toml", r"syntax\.toml", r"line 12"])


SHAFT_WITHOUT_INERTIA = """\
name = "massless_shaft"
connect = [
  ["J1.flange_b", "c1.flange_a"],
  ["c1.flange_b", "c2.flange_a"],
  ["c2.flange_b", "J2.flange_a"],
  ["press.y", "c1.f_normalized"],
  ["press.y", "c2.f_normalized"],
]

[experiment]
StopTime = 0.5
Interval = 0.01

[components]
J1 = { type = "Inertia", J = 1.0, phi = 0.0, w = 10.0 }
c1 = { type = "Clutch", fn_max = 100.0 }
c2 = { type = "Clutch", fn_max = 100.0, w_rel = -5.0 }
J2 = { type = "Inertia", J = 1.0, phi = 0.0, w = 0.0 }
press = { type = "Constant", k = 1.0 }
"""


def test_shaft_without_inertia_between_two_clutches(tmp_path: Path) -> None:
    """Two sliding clutches on a massless shaft leave its acceleration undetermined.

    The shaft starts at 5 rad/s (c2.w_rel = −5 fixed), between J1 at 10 and J2 at rest, so
    both clutches slide and nothing holds the shaft. (Were one of them locked, the shaft
    would move with its inertia, a regular mode, and the model would run.)

    The run must stop promptly (the CLI call has a timeout and goes first) with an error
    naming the shaft's ports, not hang in the event iteration or return garbage.
    """
    model = tmp_path / "shaft.toml"
    model.write_text(SHAFT_WITHOUT_INERTIA)
    ports = [r"c1\.flange_b", r"c2\.flange_a", r"(?i)inertia"]
    _assert_one_error_line(_cli(model, tmp_path), ports)
    with pytest.raises((st.ModelError, RuntimeError)) as info:
        st.Model.loads(SHAFT_WITHOUT_INERTIA).simulate()
    for pattern in ports:
        assert re.search(pattern, str(info.value)), (pattern, str(info.value))


def test_model_error_is_the_engines_and_has_its_public_name() -> None:
    """st.ModelError is the class the engine raises, and it prints as `ModelError`.

    Users see the class name in tracebacks and write `except st.ModelError`.
    """
    assert st.ModelError is _core.ModelError
    assert issubclass(st.ModelError, ValueError)
    assert st.ModelError.__name__ == "ModelError", st.ModelError.__name__
