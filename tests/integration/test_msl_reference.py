"""The MSL examples of this issue against the MSL regression references (tube method).

CoupledClutches and Friction are simulated from examples/msl with their own experiment
settings (Tolerance 1e-6, as the Dymola reference runs) and compared with the MAP-LIB
reference trajectories in tests/data/msl, on exactly the signals MSL compares
(``<Example>.signals.txt``, friction ``mode`` signals included), with the MSL tube
tolerance 2e-3.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from paths import MSL_DATA, REPO

import stiction as st
from stiction.results.comparison import read_signal_list
from stiction.results.io.csv import read_csv

MSL_DIR = MSL_DATA
EXAMPLES = ["CoupledClutches", "Friction"]
MSL_TOLERANCE = 2e-3  # CSV Compare tube size used by the Modelica Association


@cache
def _simulated(example: str) -> st.Result:
    """Our result for one example, run with the model file's own experiment."""
    return st.Model.load(REPO / "examples" / "msl" / f"{example}.toml").simulate()


def _reference(example: str) -> tuple[list[str], np.ndarray]:
    return read_csv(MSL_DIR / f"{example}.csv")


def _signals(example: str) -> list[str]:
    return read_signal_list(MSL_DIR / f"{example}.signals.txt")


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_stays_inside_the_msl_tube(example: str) -> None:
    """Every MSL-compared signal, modes included, lies inside the 2e-3 reference tube."""
    result = _simulated(example)
    _, data = _reference(example)
    assert result.time[0] == data[0, 0] and result.time[-1] == pytest.approx(data[-1, 0])
    report = st.compare(
        result,
        MSL_DIR / f"{example}.csv",
        tolerance=MSL_TOLERANCE,
        signals=MSL_DIR / f"{example}.signals.txt",
    )
    listed = _signals(example)
    assert [s.name for s in report] == listed
    assert any(n.endswith(".mode") for n in listed)  # the discrete state is compared too
    assert report.passed, str(report)


@pytest.mark.parametrize("example", EXAMPLES)
def test_modes_are_integers_in_the_msl_range(example: str) -> None:
    """Friction modes are the MSL integers −1, 0, 1, 2 (3 "unknown" never leaves init)."""
    result = _simulated(example)
    for name in (n for n in _signals(example) if n.endswith(".mode")):
        values = set(np.unique(result[name]).tolist())
        assert values <= {-1.0, 0.0, 1.0, 2.0}, (name, values)


@pytest.mark.parametrize("example", EXAMPLES)
def test_one_percent_offset_of_one_signal_fails_only_that_signal(example: str) -> None:
    """Negative control: shifting one signal by 1 % of its reference range leaves the tube.

    The tube half-height is 2e-3 of the range, so a 1 % offset is 5 half-heights: at least
    wherever the reference is flat, the shifted point is 4 half-heights outside. Every
    listed signal is tried in turn, and only the shifted one may fail.
    """
    result = _simulated(example)
    ref_names, ref_data = _reference(example)
    for name in _signals(example):
        ref = ref_data[:, ref_names.index(name)]
        bad = result.data.copy()
        bad[:, result.names.index(name)] += 0.01 * (ref.max() - ref.min())
        report = st.compare(
            (result.names, bad),
            (ref_names, ref_data),
            tolerance=MSL_TOLERANCE,
            signals=MSL_DIR / f"{example}.signals.txt",
        )
        assert report.failed == [name], str(report)
