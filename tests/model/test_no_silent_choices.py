"""No silent choices: default experiment settings, flat or ragged tables, and start values
the initialization guessed or computed are all reported."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st
from stiction.cli import main

ALL = ("StartTime", "StopTime", "Interval", "Tolerance", "Solver")


def _two_shafts() -> st.Model:
    """J (w fixed at 10) and J2 (w guessed 3) joined by a disengaged clutch (w_rel guessed 1)."""
    m = st.Model("two_shafts")
    m.add("J", st.Inertia(J=2.0, w=10.0))
    m.add("J2", st.Inertia(J=1.0, w={"start": 3.0, "fixed": False}))
    m.add("c", st.Clutch(fn_max=10.0, w_rel={"start": 1.0, "fixed": False}))
    m.add("f", st.Constant(k=0.0))
    m.connect("J.flange_b", "c.flange_a")
    m.connect("c.flange_b", "J2.flange_a")
    m.connect("f.y", "c.f_normalized")
    return m


def test_a_missing_experiment_is_reported_as_defaults() -> None:
    r = _two_shafts().simulate()
    assert r.experiment is not None
    assert r.experiment.defaults == ALL
    assert (r.experiment.StopTime, r.experiment["Solver"]) == (1.0, "auto")
    assert "StopTime 1 (default)" in r.summary() and "Solver auto (default)" in r.summary()


def test_given_settings_are_not_defaults_and_solver_is_an_override() -> None:
    m = _two_shafts()
    m.experiment["StopTime"] = 0.5
    r = m.simulate(Tolerance=1e-8, Solver="bdf")
    assert r.experiment is not None
    assert r.experiment.defaults == ("StartTime", "Interval")
    assert (r.experiment.StopTime, r.experiment.Tolerance, r.experiment.Solver) == (0.5, 1e-8, "bdf")
    reference = m.simulate(Tolerance=1e-8)
    np.testing.assert_allclose(r["J2.w"][-1], reference["J2.w"][-1], rtol=1e-6)
    with pytest.raises(st.ModelError, match="Solver"):
        m.simulate(Solver="euler")


def test_initialization_lists_every_start_value_fixed_guessed_or_computed() -> None:
    r = _two_shafts().simulate(StopTime=0.1)
    init = {v.variable: v for v in r.initialization or ()}
    assert init["J.w"].status == "fixed" and init["J.w"].value == 10.0
    assert init["J2.w"].status == "guessed" and init["J2.w"].value == 3.0
    # w_rel = J2.w - J.w follows from the others: its guess 1 is overridden
    assert init["c.w_rel"].status == "computed" and init["c.w_rel"].value == pytest.approx(-7.0)
    assert init["c.w_rel"].start == 1.0
    assert set(init) == {"J.phi", "J2.phi", "c.phi_rel", "J.w", "J2.w", "c.w_rel"}
    assert r["c.w_rel"][0] == pytest.approx(-7.0)


def test_check_verbose_prints_the_initialization(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "m.toml"
    _two_shafts().save(path)
    with pytest.raises(SystemExit) as done:
        main(["check", "--verbose", str(path)])
    assert done.value.code == 0
    out = capsys.readouterr().out
    assert "StopTime 1 (default)" in out and "1 fixed, 3 guessed, 2 computed" in out
    assert any(line.split()[:2] == ["c.w_rel", "computed"] for line in out.splitlines())


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ([0.5, 0.4], r"flat list.*\[\[x1, y1\], \[x2, y2\], …\].*reads \[\[0.5, 0.4\]\]"),
        ([0, 0.5, 10, 0.4], r"reads \[\[0, 0.5\], \[10, 0.4\]\]"),
        ([[0, 0.5], [10]], r"every row must have 2 columns, found \[10\] with 1"),
        ([[0, 0.5], 3], r"mixes rows and single numbers"),
    ],
)
def test_flat_and_ragged_tables_are_refused_with_the_matrix_form(value: list, message: str) -> None:
    m = st.Model("m").add("b", st.Brake(fn_max=1.0, mu_pos=value))
    with pytest.raises(st.ModelError, match=r"component 'b' \(Brake\): parameter 'mu_pos': .*" + message):
        m.check()


def test_a_flat_loss_table_shows_its_five_columns() -> None:
    m = st.Model("m").add("g", st.LossyGear(lossTable=[0, 1, 1, 0, 0]))
    with pytest.raises(
        st.ModelError, match=r"lossTable.*\[\[x1, y1, z1, u1, v1\].*reads \[\[0, 1, 1, 0, 0\]\]"
    ):
        m.check()


def test_cli_solver_option(capsys: pytest.CaptureFixture[str]) -> None:
    model = MSL_EXAMPLES / "First.toml"
    with pytest.raises(SystemExit) as done:
        main(["simulate", str(model), "--Solver", "esdirk34", "--StopTime", "0.1"])
    assert done.value.code == 0
    assert "Solver esdirk34" in capsys.readouterr().out


def test_a_simulation_reports_its_experiment_and_solver() -> None:
    sim = _two_shafts().simulation(Solver="esdirk34", StopTime=0.2)
    sim.run()
    r = sim.result()
    assert r.experiment is not None and r.experiment.Solver == "esdirk34"
    assert r.experiment.defaults == ("StartTime", "Interval", "Tolerance")
    assert r.time[-1] == 0.2
