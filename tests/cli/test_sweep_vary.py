"""``stiction sweep --vary`` with units and tables (issue 29): ``J.w=60 rpm:120 rpm:2``,
``brake.fn_max=10 N,0.03 kN`` and ``brake.mu_pos=TABLE;TABLE`` (TOML arrays, cells may be
expressions over top-level parameters)."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import pytest

MODEL = """name = "braked"
connect = [["J.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"]]

[experiment]
StopTime = 5.0

[parameters]
mu0 = 0.5

[components]
J = { type = "Inertia", J = 1.0, w = 10.0 }
brake = { type = "Brake", fn_max = 20.0, mu_pos = [[0, 0.5]] }
press = { type = "Constant", k = 1.0 }
"""


def _sweep(tmp_path: Path, *vary: str) -> tuple[subprocess.CompletedProcess[str], list[dict[str, str]]]:
    model, out = tmp_path / "m.toml", tmp_path / "s.csv"
    model.write_text(MODEL)
    args = [arg for v in vary for arg in ("--vary", v)]
    proc = subprocess.run(
        [sys.executable, "-m", "stiction", "sweep", str(model), *args, "--metric", "max(J.w)"]
        + ["--metric", "time_of(brake.locked)", "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    rows = list(csv.DictReader(out.open())) if proc.returncode == 0 else []
    return proc, rows


def test_a_range_with_units(tmp_path: Path) -> None:
    proc, rows = _sweep(tmp_path, "J.w=60 rpm:120 rpm:2", "brake.fn_max=10 N,0.03 kN")
    assert proc.returncode == 0, proc.stderr
    assert [float(r["J.w"]) for r in rows] == pytest.approx([2 * math.pi] * 2 + [4 * math.pi] * 2)
    assert [float(r["brake.fn_max"]) for r in rows] == [10.0, 30.0, 10.0, 30.0]


def test_tables_separated_by_semicolons(tmp_path: Path) -> None:
    proc, rows = _sweep(tmp_path, 'brake.mu_pos=[[0, 0.25]];[[0, "mu0"]] ; [[0,"2*mu0"]]')
    assert proc.returncode == 0, proc.stderr
    times = [float(r["time_of(brake.locked)"]) for r in rows]
    assert times == pytest.approx([times[0], times[0] / 2, times[0] / 4])  # mu 0.25, 0.5, 1.0


@pytest.mark.parametrize(
    ("vary", "words"),
    [
        ("J.w=100 km/h:300 rpm:3", "'100 km/h' is a speed, not an angular velocity"),
        ("brake.mu_pos=[[0, 0.4]", "is not a table written as a TOML array"),
        ("J.w=fast,slow", "'fast' is not a number or a quantity"),
    ],
)
def test_a_bad_value_is_a_usage_error(tmp_path: Path, vary: str, words: str) -> None:
    proc, _ = _sweep(tmp_path, vary)
    assert proc.returncode == 2 and words in proc.stderr, proc.stderr
    assert "Traceback" not in proc.stderr
