"""`stiction simulate -o out/x.csv` makes the missing folder (issue 29), as `make demo` expects,
and writes the file there."""

from __future__ import annotations

from pathlib import Path

from paths import EXAMPLES

from stiction.cli import main
from stiction.results.io.csv import read_csv


def test_simulate_makes_the_output_folder(tmp_path: Path, cli_runner) -> None:
    target = tmp_path / "out" / "deeper" / "x.csv"
    run = cli_runner.invoke(
        main, ["simulate", str(EXAMPLES / "msl" / "CoupledClutches.toml"), "-o", str(target)]
    )
    assert run.exit_code == 0, run.output
    names, data = read_csv(target)
    assert names[0] == "time" and "J1.w" in names and len(data) > 100
    assert [p.name for p in target.parent.iterdir()] == ["x.csv"]  # no partial file left
