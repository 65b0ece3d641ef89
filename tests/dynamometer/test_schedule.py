"""Schedules that cannot run are refused with the section and the line named; the CLI writes
its report as Parquet and CSV that read back equal."""

from __future__ import annotations

import re

import pytest
from click.testing import CliRunner
from paths import EXAMPLES

import stiction as st
from stiction.cli.app import main
from stiction.dynamometer import DynoReport, ScheduleError, dyno, load_schedule, loads_schedule

RIG = """[dyno]
brake = "brake"
flange = "brake.flange_a"
J = 2.0
temperature = "disc.T"
fn_per_bar = 100.0
"""

GOOD = """
[[section]]
name = "first"
v_initial = 100.0
v_final = 0.0
pressure = 20.0
interval = 1.0
"""


def refused(body: str, line_of: str, *, model: st.Model | None = None) -> str:
    """The error a schedule gives, checked to name the line holding ``line_of``."""
    text = RIG + GOOD + body
    line = 1 + next(k for k, t in enumerate(text.splitlines()) if line_of in t)
    with pytest.raises(ScheduleError) as info:
        schedule = loads_schedule(text)
        dyno(model or cooled(), schedule, progress=False)
    message = str(info.value)
    assert f"(line {line})" in message, message
    return message


def cooled(cooling: bool = True) -> st.Model:
    m = st.Model("brake_rig")
    m.add("brake", st.Brake(fn_max=1e5, cgeo=0.2, mu_pos=[[0.0, 0.4]], useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=500.0, T=350.0))
    m.connect("brake.heatPort", "disc.port")
    if cooling:
        m.add("cooling", st.ThermalConductor(G=4.0))
        m.add("ambient", st.FixedTemperature(T=293.15))
        m.connect("disc.port", "cooling.port_a")
        m.connect("cooling.port_b", "ambient.port")
    return m


def test_a_negative_speed_is_refused_by_section_and_line() -> None:
    message = refused(
        '\n[[section]]\nname = "bad"\nv_initial = 50.0\nv_final = -3.0\npressure = 5.0\n', "v_final = -3"
    )
    assert "section 'bad'" in message and "negative speed" in message


def test_a_final_speed_above_the_initial_is_refused() -> None:
    message = refused(
        '\n[[section]]\nname = "up"\nv_initial = 50.0\nv_final = 80.0\npressure = 5.0\n', "v_final = 80"
    )
    assert "section 'up'" in message and "not below v_initial" in message


def test_an_unknown_key_is_refused_with_a_suggestion() -> None:
    body = '\n[[section]]\nname = "typo"\nv_initial = 50.0\npresure = 5.0\n'
    message = refused(body, "presure")
    assert "section 'typo'" in message and "unknown key 'presure'" in message and "pressure" in message


def test_an_ibt_below_ambient_is_refused() -> None:
    body = '\n[[section]]\nname = "cold"\nv_initial = 50.0\npressure = 5.0\nIBT = 10.0\n'
    message = refused(body, "IBT = 10")
    assert "section 'cold'" in message and "not above the ambient (20 °C)" in message


def test_an_ibt_without_a_cooling_path_is_refused() -> None:
    body = '\n[[section]]\nname = "hot"\nv_initial = 50.0\npressure = 5.0\nIBT = 60.0\n'
    message = refused(body, "IBT = 60", model=cooled(cooling=False))
    assert "section 'hot'" in message and "no cooling path" in message


def test_an_unknown_rig_key_names_its_line() -> None:
    text = RIG.replace("J = 2.0", "J = 2.0\nbrak_es = 1") + GOOD
    with pytest.raises(ScheduleError, match=re.escape("[dyno] (line 5): unknown key 'brak_es'")):
        loads_schedule(text)


def test_the_cli_writes_parquet_and_csv_that_read_back_equal(tmp_path) -> None:
    model = tmp_path / "brake.toml"
    cooled().save(model)
    schedule = tmp_path / "schedule.toml"
    schedule.write_text(RIG + GOOD + GOOD.replace('"first"', '"second"').replace("100.0", "80.0"))
    out = tmp_path / "report"
    result = CliRunner().invoke(
        main, ["dyno", str(model), str(schedule), "-o", str(out), "--quiet", "--no-plots"]
    )
    assert result.exit_code == 0, result.output
    assert "2 stops" in result.output
    parquet, csv = DynoReport.read_stops(out), DynoReport.read_stops(out, "csv")
    assert list(parquet["section"]) == ["first", "second"]
    pd_testing = pytest.importorskip("pandas.testing")
    pd_testing.assert_frame_equal(parquet, csv, check_exact=False, rtol=1e-15)
    # the Python call gives the same table
    direct = dyno(cooled(), loads_schedule(schedule.read_text()), progress=False).stops
    pd_testing.assert_frame_equal(direct, parquet)


def test_a_bad_schedule_is_one_error_line_on_the_command_line(tmp_path) -> None:
    model = tmp_path / "brake.toml"
    cooled().save(model)
    schedule = tmp_path / "schedule.toml"
    schedule.write_text(RIG + GOOD.replace("v_final = 0.0", "v_final = 120.0"))
    result = CliRunner().invoke(main, ["dyno", str(model), str(schedule), "--quiet"])
    assert result.exit_code == 2
    assert "section 'first' (line 11)" in result.output


def test_the_example_schedules_read() -> None:
    for name in ("j2522_like", "iso26867_like"):
        schedule = load_schedule(EXAMPLES / "dyno" / f"{name}.toml")
        assert 150 <= schedule.stops <= 260


def test_an_unknown_top_level_key_names_its_line() -> None:
    with pytest.raises(ScheduleError, match=re.escape("line 2: unknown top-level key 'repeats'")):
        loads_schedule('name = "x"\nrepeats = 3\n' + RIG + GOOD)
