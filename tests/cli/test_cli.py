"""The `stiction` command end to end: simulate an MSL example, plot it, compare it.

Runs the real entry point (`python -m stiction`) in a subprocess, as a user would.
"""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from paths import MSL_DATA, REPO

from stiction.results.comparison import read_signal_list
from stiction.results.io.csv import read_csv, write_csv

MODEL = REPO / "examples" / "msl" / "CoupledClutches.toml"
REFERENCE = MSL_DATA / "CoupledClutches.csv"
SIGNALS = MSL_DATA / "CoupledClutches.signals.txt"
TIMEOUT = 120.0  # s; the run takes ~10 ms, importing matplotlib for the plot ~1 s


def _stiction(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stiction", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        check=False,
    )


@pytest.fixture(scope="module")
def simulated(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """`stiction simulate CoupledClutches.toml -o x.csv --plot x.png`, run once."""
    out = tmp_path_factory.mktemp("cli")
    csv_file, png_file = out / "x.csv", out / "x.png"
    proc = _stiction("simulate", MODEL, "-o", csv_file, "--plot", png_file)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    assert f"wrote {csv_file}" in proc.stdout and f"wrote {png_file}" in proc.stdout
    return csv_file, png_file


def test_simulate_writes_an_msl_style_csv(simulated: tuple[Path, Path]) -> None:
    """Header of quoted MSL names with `time` first; flange torques and modes included."""
    csv_file, _ = simulated
    header_line = csv_file.read_text().splitlines()[0]
    header = next(csv.reader([header_line]))
    assert header_line == ",".join(f'"{n}"' for n in header)  # every name quoted
    assert header[0] == "time"
    for name in ("J1.w", "J1.flange_a.tau", "clutch1.w_rel", "clutch1.mode", "clutch3.mode"):
        assert name in header, name
    names, data = read_csv(csv_file)
    t = data[:, 0]
    assert t[0] == 0.0 and t[-1] == pytest.approx(1.5)
    assert np.all(np.diff(t) >= 0.0)  # never decreasing; events are written twice
    assert data[0, names.index("J1.w")] == 10.0


def test_modes_are_written_as_integers(simulated: tuple[Path, Path]) -> None:
    """`clutchk.mode` cells are integer literals (−1, 0, 1, 2), as in MSL result files."""
    csv_file, _ = simulated
    with csv_file.open(newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        columns = [header.index(f"clutch{k}.mode") for k in (1, 2, 3)]
        cells = {row[i] for row in reader for i in columns}
    assert cells <= {"-1", "0", "1", "2"}, cells
    assert {"-1", "0", "2"} <= cells  # slipping, stuck and free all occur in this example


def test_simulate_writes_a_png_plot(simulated: tuple[Path, Path]) -> None:
    """The --plot file is a real, non-trivial PNG image."""
    _, png_file = simulated
    content = png_file.read_bytes()
    assert content[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(content) > 10_000  # axes, curves and labels, not an empty canvas


def test_compare_against_the_msl_reference_exits_0(simulated: tuple[Path, Path]) -> None:
    """`stiction compare x.csv CoupledClutches.csv --signals @… -v` passes every signal."""
    csv_file, _ = simulated
    proc = _stiction("compare", csv_file, REFERENCE, "--signals", f"@{SIGNALS}", "-v")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    signals = read_signal_list(SIGNALS)
    for name in signals:
        assert f"PASS {name}" in proc.stdout.splitlines()
    assert f"{len(signals)}/{len(signals)} signals passed" in proc.stdout


def test_compare_against_a_perturbed_reference_exits_1(simulated: tuple[Path, Path], tmp_path: Path) -> None:
    """Shifting one reference signal by 1 % of its range (5 tube heights) fails it: exit 1."""
    csv_file, _ = simulated
    names, data = read_csv(REFERENCE)
    bad = data.copy()
    col = names.index("clutch1.w_rel")
    bad[:, col] += 0.01 * np.ptp(data[:, col])
    perturbed = tmp_path / "CoupledClutches.csv"
    write_csv(perturbed, names, bad)
    proc = _stiction("compare", csv_file, perturbed, "--signals", f"@{SIGNALS}")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    failed = [line for line in proc.stdout.splitlines() if line.startswith("FAIL")]
    assert len(failed) == 1 and failed[0].startswith("FAIL clutch1.w_rel"), proc.stdout
    assert "Traceback" not in proc.stderr


def test_bench_prints_what_every_variable_costs_against_the_states() -> None:
    """`stiction bench MODEL` prints a row per model whose after/states column is the run
    with every variable computed after it (median + "+all vars") over the run that records the
    states (median), and whose all/states column is the run that records every variable as it
    goes ("record=all") over the same."""
    proc = _stiction("bench", "--repeat", "3", MODEL)
    assert proc.returncode == 0, proc.stderr
    header, row = proc.stdout.splitlines()[-2:]
    assert "after/states" in header and "all/states" in header and row.startswith("CoupledClutches")
    fields = row.split()
    median, table, after = float(fields[1]), float(fields[5]), float(fields[6].rstrip("×"))
    recording, ratio = float(fields[7]), float(fields[8].rstrip("×"))
    assert table > 0.0 and recording > 0.0
    assert after == pytest.approx((median + table) / median, abs=0.01 + 1e-3 * after)
    assert ratio == pytest.approx(recording / median, abs=0.01 + 1e-3 * ratio)
