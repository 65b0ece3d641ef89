"""The MSL tube comparison, on the real MAP-LIB reference data."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from paths import MSL_DATA

from stiction.cli import main
from stiction.results.comparison import compare, read_signal_list, tube
from stiction.results.io.csv import read_csv
from stiction.results.result import Result

MSL_DIR = MSL_DATA
EXAMPLES = sorted(p.stem for p in MSL_DIR.glob("*.csv"))
WITH_SIGNALS = [e for e in EXAMPLES if (MSL_DIR / f"{e}.signals.txt").exists()]
TOL = 2e-3


def _load(example: str) -> tuple[list[str], np.ndarray]:
    return read_csv(MSL_DIR / f"{example}.csv")


def _half_sizes(names: list[str], data: np.ndarray, name: str) -> tuple[float, float]:
    t, y = data[:, 0], data[:, names.index(name)]
    return TOL * (t[-1] - t[0]), TOL * (y.max() - y.min())


def test_reference_files_are_there() -> None:
    assert {"CoupledClutches", "Friction", "SimpleGearShift"} <= set(EXAMPLES)


@pytest.mark.parametrize("example", EXAMPLES)
def test_reference_against_itself_passes(example: str) -> None:
    names, data = _load(example)
    report = compare((names, data), (names, data))
    assert report.passed, str(report)
    assert len(report) == len(names) - 1


@pytest.mark.parametrize("example", WITH_SIGNALS)
def test_time_shift_of_half_the_tube_width_passes(example: str) -> None:
    names, data = _load(example)
    shifted = data.copy()
    shifted[:, 0] += 0.5 * TOL * (data[-1, 0] - data[0, 0])
    for signals in (None, MSL_DIR / f"{example}.signals.txt"):
        report = compare((names, shifted), (names, data), signals=signals)
        assert report.passed, str(report)


@pytest.mark.parametrize("example", ["CoupledClutches", "Friction"])
def test_offset_of_three_tube_heights_fails_and_names_the_signal(example: str) -> None:
    names, data = _load(example)
    signals = read_signal_list(MSL_DIR / f"{example}.signals.txt")
    target = next(n for n in signals if n.endswith((".w", ".w_rel")))
    _, y_half = _half_sizes(names, data, target)
    bad = data.copy()
    bad[:, names.index(target)] += 3 * y_half
    report = compare((names, bad), (names, data), signals=MSL_DIR / f"{example}.signals.txt")
    assert not report.passed
    assert report.failed == [target]
    verdict = report[target]
    assert verdict.max_excess == pytest.approx(2.0, rel=1e-6)  # 3Y above, the tube reaches +1Y
    assert verdict.worst_time is not None
    assert f"FAIL {target}  max excess 2×tube at t=" in str(report)


def test_missing_signal_fails() -> None:
    names, data = _load("CoupledClutches")
    keep = [i for i, n in enumerate(names) if n != "J1.w"]
    report = compare(([names[i] for i in keep], data[:, keep]), (names, data))
    assert not report.passed
    assert report.failed == ["J1.w"]
    assert report["J1.w"].missing == "result"
    assert "FAIL J1.w  missing in result" in str(report).splitlines()


def test_signal_list_file_selects_the_signals() -> None:
    names, data = _load("CoupledClutches")
    listed = MSL_DIR / "CoupledClutches.signals.txt"
    expected = [n for n in listed.read_text().split() if n != "time"]
    report = compare((names, data), MSL_DIR / "CoupledClutches.csv", signals=listed)
    assert [s.name for s in report] == expected
    assert "clutch1.startForward" not in expected  # in the CSV, not compared by MSL
    assert report.passed
    assert str(report).splitlines()[0] == f"PASS {expected[0]}"


def test_signal_list_as_sequence_and_result_object() -> None:
    names, data = _load("Friction")
    report = compare(Result(names, data), (names, data), signals=["time", "inertia3.w"])
    assert [s.name for s in report] == ["inertia3.w"]
    assert report.passed


def test_nan_in_result_fails() -> None:
    names, data = _load("First")
    bad = data.copy()
    bad[100, 2] = np.nan
    report = compare((names, bad), (names, data))
    assert report.failed == [names[2]]
    assert report[names[2]].max_excess == np.inf


def test_jump_inside_the_time_window_is_tolerated() -> None:
    # Reference: a unit step at t = 1 written twice (left and right value), on [0, 2].
    t_ref = np.array([0.0, 0.5, 1.0, 1.0, 1.5, 2.0])
    y_ref = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
    ref = (["time", "y"], np.column_stack([t_ref, y_ref]))
    tol = 0.01  # X = 0.02 s, Y = 0.01

    def step_at(t_step: float) -> tuple[list[str], np.ndarray]:
        t = np.array([0.0, 0.9, t_step, t_step, 1.2, 2.0])
        y = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
        return ["time", "y"], np.column_stack([t, y])

    assert compare(step_at(1.015), ref, tolerance=tol).passed
    assert compare(step_at(0.985), ref, tolerance=tol).passed
    late = compare(step_at(1.03), ref, tolerance=tol)
    assert not late.passed
    assert late["y"].worst_time == pytest.approx(1.03)
    lower, upper, x_half, y_half = tube(t_ref, y_ref, np.array([0.5, 0.99, 1.5]), tol)
    assert (x_half, y_half) == pytest.approx((0.02, 0.01))
    assert lower == pytest.approx([-0.01, -0.01, 0.99])
    assert upper == pytest.approx([0.01, 1.01, 1.01])


def test_compare_is_fast_on_the_largest_file() -> None:
    names, data = _load("Friction")
    start = time.perf_counter()
    compare((names, data), (names, data))
    assert time.perf_counter() - start < 0.5


def test_csv_reader_matches_the_file() -> None:
    names, data = _load("CoupledClutches")
    assert names[0] == "time" and names[2] == "J1.w"
    assert data.shape == (3021, 18)
    assert data[0, 2] == 10.0 and data[-1, 0] == 1.5
    assert np.all(np.diff(data[:, 0]) >= 0)


# --- command line ---------------------------------------------------------------------
def test_cli_compare_pass_exits_0(tmp_path: Path, cli_runner: CliRunner) -> None:
    ref = MSL_DIR / "Friction.csv"
    result = cli_runner.invoke(main, ["compare", str(ref), str(ref)])
    assert result.exit_code == 0, result.output
    assert "PASS" not in result.output  # a summary by default: failures and the count
    assert result.output.splitlines()[0].endswith("signals passed (tolerance 0.002)")
    assert "signals from" in result.output  # Friction.signals.txt found next to the reference
    verbose = cli_runner.invoke(main, ["compare", str(ref), str(ref), "-v"])
    assert "PASS inertia3.w" in verbose.output
    assert "brake.startForward" not in result.output


def test_cli_compare_fail_exits_1(tmp_path: Path, cli_runner: CliRunner) -> None:
    names, data = _load("Friction")
    bad = data.copy()
    _, y_half = _half_sizes(names, data, "inertia3.w")
    bad[:, names.index("inertia3.w")] += 3 * y_half
    test_file = tmp_path / "bad.csv"
    Result(names, bad).to_csv(test_file)
    args = [
        "compare",
        str(test_file),
        str(MSL_DIR / "Friction.csv"),
        "--tolerance",
        "2e-3",
    ]
    result = cli_runner.invoke(main, args)
    assert result.exit_code == 1, result.output
    assert "FAIL inertia3.w" in result.output


def test_cli_compare_with_signals_option(tmp_path: Path, cli_runner: CliRunner) -> None:
    signals = tmp_path / "list.txt"
    signals.write_text("time\nJ1.w\n")
    ref = MSL_DIR / "CoupledClutches.csv"
    result = cli_runner.invoke(main, ["compare", str(ref), str(ref), "--signals", f"@{signals}", "-v"])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[:2] == ["PASS J1.w", "1/1 signals passed (tolerance 0.002)"]
    listed = cli_runner.invoke(
        main, ["compare", str(ref), str(ref), "--signals", "J1.w, clutch1.w_rel", "-v"]
    )
    assert listed.output.splitlines()[:2] == ["PASS J1.w", "PASS clutch1.w_rel"]
    bare = cli_runner.invoke(main, ["compare", str(ref), str(ref), "--signals", str(signals)])
    assert bare.exit_code == 2 and f"write @{signals}" in bare.stderr


def test_exact_zero_reference_passes_round_off_with_the_floor(tmp_path: Path, cli_runner: CliRunner) -> None:
    """A torque that is exactly 0 in the reference and 1.8e-12 in the result (round-off) passes
    with the absolute floor; MSL's bare method (floor 0, Y = 2e-18) fails it."""
    t = np.linspace(0.0, 1.0, 101)
    ref, res = tmp_path / "ref.csv", tmp_path / "res.csv"
    Result(["time", "J.flange_b.tau"], np.column_stack([t, np.zeros_like(t)])).to_csv(ref)
    Result(["time", "J.flange_b.tau"], np.column_stack([t, np.full_like(t, 1.8e-12)])).to_csv(res)
    assert compare(res, ref).passed
    assert not compare(res, ref, floor=0.0).passed
    assert cli_runner.invoke(main, ["compare", str(res), str(ref)]).exit_code == 0
    strict = cli_runner.invoke(main, ["compare", str(res), str(ref), "--floor", "0"])
    assert strict.exit_code == 1 and "FAIL J.flange_b.tau" in strict.output
    off = Result(["time", "J.flange_b.tau"], np.column_stack([t, np.full_like(t, 1e-6)]))
    assert not compare(off, ref).passed  # the floor is far below a real torque


def test_cli_compare_missing_file_exits_2_without_traceback(tmp_path: Path, cli_runner: CliRunner) -> None:
    ref = MSL_DIR / "Friction.csv"
    result = cli_runner.invoke(main, ["compare", str(tmp_path / "nope.csv"), str(ref)])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ")
    assert len(result.stderr.strip().splitlines()) == 1
    assert "Traceback" not in result.output + result.stderr
