"""``stiction bench --json`` / ``--compare`` (issue 34): figures saved and read back, each
compared with the saved run, and the worse ones beyond the noise marked."""

from __future__ import annotations

import math

import pytest
from click.testing import CliRunner
from paths import MSL_EXAMPLES

from stiction.cli.app import main as cli
from stiction.cli.bench_floor import NOISE, compare_figures, read_figures, write_figures


def test_figures_round_trip_and_compare(tmp_path) -> None:
    figures = {"CoupledClutches.median_ms": 0.39, "ladder1000.python_share": 0.12}
    path = tmp_path / "bench.json"
    write_figures(path, figures)
    assert read_figures(path) == figures
    rows = compare_figures(figures, read_figures(path))
    assert [r.ratio for r in rows] == [1.0, 1.0] and not any(r.worse() for r in rows)
    slower = {
        "CoupledClutches.median_ms": 0.39 * (1 + 2 * NOISE),
        "ladder1000.python_share": 0.12,
        "new_ms": 1.0,
    }
    rows = {r.name: r for r in compare_figures(slower, figures)}
    assert rows["CoupledClutches.median_ms"].worse() and "WORSE" in rows["CoupledClutches.median_ms"].line()
    assert not rows["ladder1000.python_share"].worse()
    assert math.isnan(rows["new_ms"].ratio) and not rows["new_ms"].worse()


def test_a_file_of_another_kind_is_refused(tmp_path) -> None:
    path = tmp_path / "other.json"
    path.write_text('{"figures": {}}', encoding="utf-8")
    with pytest.raises(ValueError, match="not a bench file"):
        read_figures(path)


def test_bench_saves_and_compares_in_one_command(tmp_path) -> None:
    out, again = tmp_path / "ref.json", tmp_path / "now.json"
    model = str(MSL_EXAMPLES / "Friction.toml")
    runner = CliRunner()
    first = runner.invoke(cli, ["bench", "--repeat", "2", "--warmup", "0", model, "--json", str(out)])
    assert first.exit_code == 0, first.output
    saved = read_figures(out)
    assert saved["Friction.median_ms"] > 0
    second = runner.invoke(
        cli, ["bench", "--repeat", "2", "--warmup", "0", model, "--compare", str(out), "--json", str(again)]
    )
    assert second.exit_code == 0, second.output
    assert "Friction.median_ms" in second.output and "figures worse beyond the noise" in second.output
    assert set(read_figures(again)) == set(saved)


def test_the_ladder_splits_its_time_outside_the_run() -> None:
    """The figures of the ladder read through Python: the engine's own parse and compile is part
    of the load and not Python's; Python's share is what is left outside the run."""
    from stiction.cli.bench_floor import ladder_figures

    f = ladder_figures(8, 3, "system.kineticEnergy")
    load, simulate, engine, core = (f[f"ladder8.{k}_ms"] for k in ("load", "simulate", "engine_load", "core"))
    total = f["ladder8.total_ms"]
    assert min(load, simulate, engine, core) > 0 and total == pytest.approx(load + simulate)
    outside, python = f["ladder8.outside_run_share"], f["ladder8.python_share"]
    assert outside == pytest.approx((total - core) / total)
    assert python == pytest.approx(max(0.0, total - core - engine) / total)
    assert 0 <= python < outside < 1
    assert f["ladder8.system.kineticEnergy_ms"] > 0
