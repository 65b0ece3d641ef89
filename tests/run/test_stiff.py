"""Stiff drivetrains (issue 13) from Python: "auto" is the default, changes to the implicit
method on the stiff shaft and locks the brake when the closed form says; the stiff benchmark
prints one row per solver. No timing here: `stiction bench --stiff` prints the numbers."""

from __future__ import annotations

import pytest
from paths import EXAMPLES, MSL_EXAMPLES

import stiction as st
from stiction.cli import main
from stiction.cli.benchmarks import bench_solvers

STIFF = EXAMPLES / "stiff"
MSL = MSL_EXAMPLES


def test_auto_is_the_default_and_switches_on_the_stiff_shaft() -> None:
    m = st.Model.load(STIFF / "StiffShaft.toml")
    res = m.simulate(StopTime=0.7)
    assert res.experiment is not None and res.experiment["Solver"] == "auto"
    assert res.stats["solver_switches"] == 1
    assert res.stats["lu_setups"] > 0  # the implicit method factors its Newton matrix
    # both inertias run up to 1260 rad/s, the brake (50 N·m at full force) stops J2 at
    # 0.6 + 260 / 22500 s and holds it
    locks = res.lock_times("brake")
    assert len(locks) == 1 and locks[0] == pytest.approx(0.6 + 260 / 22500, abs=1e-6)
    assert abs(res["J2.w"][-1]) < 1e-6


def test_an_msl_example_stays_explicit_under_auto() -> None:
    res = st.Model.load(MSL / "CoupledClutches.toml").simulate()
    explicit = st.Model.load(MSL / "CoupledClutches.toml").simulate(Solver="tsit45")
    assert res.stats["solver_switches"] == 0 and res.stats["lu_setups"] == 0
    assert (res["J1.w"] == explicit["J1.w"]).all()


def test_bench_solvers_reports_every_method(capsys: pytest.CaptureFixture[str]) -> None:
    rows = bench_solvers(st.Model.load(MSL / "First.toml"), ["tsit45", "bdf", "auto"], repeat=1)
    assert [r.solver for r in rows] == ["tsit45", "bdf", "auto"]
    assert rows[0].lu_setups == 0 and rows[1].lu_setups > 0 and rows[2].switches == 0
    assert rows[0].jacobians == 0 and 0 < rows[1].jacobians <= rows[1].lu_setups
    assert rows[0].steps == rows[2].steps  # auto did not switch: the explicit steps exactly
    with pytest.raises(SystemExit) as done:
        main(["bench", "--stiff", str(MSL / "First.toml")])
    assert done.value.code == 0
    out = capsys.readouterr().out
    assert all(f" {s} " in out for s in ("tsit45", "bdf", "esdirk34", "auto"))
