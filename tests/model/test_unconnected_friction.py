"""A friction element's flange connected to nothing is refused by name, before any run
(issue 29): ``stiction check`` said "ok" and a run failed later with "the accelerations are
not determined; give each an Inertia" — the wrong fix. Alone, such a flange's shaft has no
inertia, and once the element slips nothing determines its motion (MSL refuses it too).
Shafts without inertia that something does determine still run (tests/model/test_massless.py,
tests/run/test_robustness.py)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import stiction as st


def _dangling_brake() -> st.Model:
    m = st.Model("dangling")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=10.0))
    m.add("brake", st.Brake(fn_max=100.0))
    m.add("press", st.Constant(k=1.0))
    m.connect("press.y", "brake.f_normalized")
    return m


NOT_CONNECTED = r"component 'brake': brake\.flange_a and brake\.flange_b are not connected"


def test_check_compile_and_simulate_say_the_flange_is_not_connected() -> None:
    m = _dangling_brake()
    for step in (m.check, m.compile, lambda: m.simulate(StopTime=1.0)):
        with pytest.raises(st.ModelError, match=NOT_CONNECTED) as caught:
            step()
        assert "give each an Inertia" not in str(caught.value)
        assert "connect one of them to the shaft it acts on" in str(caught.value)


def test_the_command_line_check_refuses_it(tmp_path: Path) -> None:
    model = tmp_path / "dangling.toml"
    _dangling_brake().save(model)
    proc = subprocess.run(
        [sys.executable, "-m", "stiction", "check", str(model)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 2
    assert "brake.flange_a and brake.flange_b are not connected" in proc.stderr


@pytest.mark.parametrize(
    ("make", "port"),
    [
        (lambda: st.Clutch(fn_max=10.0), "clutch.flange_b"),
        (lambda: st.OneWayClutch(fn_max=10.0), "clutch.flange_b"),
    ],
)
def test_one_open_side_of_a_clutch_is_named(make, port: str) -> None:
    m = st.Model("open_side")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=0.0))
    m.add("clutch", make())
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "clutch.flange_a")
    m.connect("press.y", "clutch.f_normalized")
    with pytest.raises(st.ModelError, match=rf"{port} is not connected"):
        m.check()


def test_an_enabled_support_left_open_is_named() -> None:
    m = st.Model("open_support")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=1.0))
    m.add("bearing", st.BearingFriction(useSupport=True))
    m.connect("J.flange_b", "bearing.flange_a")
    with pytest.raises(st.ModelError, match=r"bearing\.support is not connected"):
        m.check()


def test_a_brake_on_a_shaft_without_inertia_that_something_holds_still_runs() -> None:
    # the brake's shaft is the far end of a spring (no inertia): connected, determined while
    # the brake holds it
    m = st.Model("held")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=1.0))
    m.add("s", st.Spring(c=100.0))
    m.add("b", st.Brake(fn_max=100.0))
    m.add("f", st.Constant(k=1.0))
    m.connect("J.flange_b", "s.flange_a")
    m.connect("s.flange_b", "b.flange_a")
    m.connect("f.y", "b.f_normalized")
    m.check()
    assert m.simulate(StopTime=0.1)["b.mode"][-1] == 0.0
