"""``stiction fit``: the command fits, writes the fitted model and the estimates, and refuses
bad bounds in one line."""

from __future__ import annotations

import pandas as pd
import pytest
from click.testing import CliRunner
from models import flywheel, trace

import stiction as st
from stiction.cli import main


def test_fit_command_writes_the_fitted_model(tmp_path):
    trace(flywheel(), {"J.w": "speed"}, 0.005, seed=1).to_csv(tmp_path / "data.csv", index=False)
    flywheel(mu=[0.33, 0.27, 0.22], peak=1.2).save(tmp_path / "model.toml")
    args = [
        "fit",
        str(tmp_path / "model.toml"),
        str(tmp_path / "data.csv"),
        "--param",
        "brake.peak=1:2",
        "--param",
        "brake.mu_pos[:,2]=0.05:0.8",
        "--output",
        "J.w=speed",
        "-o",
        str(tmp_path / "fitted.toml"),
        "--table",
        str(tmp_path / "estimates.csv"),
    ]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert "brake.peak" in result.output
    fitted = st.Model.load(tmp_path / "fitted.toml")
    assert fitted["brake"].params["peak"] == pytest.approx(1.3, rel=0.01)
    assert fitted["brake"].params["mu_pos"][2][1] == pytest.approx(0.2, rel=0.01)
    table = pd.read_csv(tmp_path / "estimates.csv")
    assert set(table["parameter"]) == {
        "brake.peak",
        "brake.mu_pos[1,2]",
        "brake.mu_pos[2,2]",
        "brake.mu_pos[3,2]",
    }


def test_fit_command_refuses_bounds_in_one_line(tmp_path):
    trace(flywheel(), {"J.w": "speed"}, 0.0, seed=1).to_csv(tmp_path / "data.csv", index=False)
    flywheel().save(tmp_path / "model.toml")
    args = ["fit", str(tmp_path / "model.toml"), str(tmp_path / "data.csv"), "--param", "brake.peak=2:1"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2
    assert "'brake.peak': low must be below high" in result.output
