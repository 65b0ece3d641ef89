"""st.fit refuses bad input by name before any model run; inputs drive model ports from data."""

from __future__ import annotations

import sys

import pandas as pd
import pytest
from models import flywheel, trace

import stiction as st
import stiction.fitting.problem  # the module whose runs the checks must precede
from stiction.errors import ModelError

PARAMS = {"brake.mu_pos[:, 2]": (0.05, 1.0), "brake.peak": (1.0, 2.0)}


@pytest.fixture
def no_runs(monkeypatch):
    """Any model run fails the test: the checks come first."""

    def refuse(*args, **kwargs):
        raise AssertionError("a model ran before the input was checked")

    monkeypatch.setattr(sys.modules["stiction.fitting.problem"], "run_batch", refuse)


@pytest.fixture(scope="module")
def data() -> pd.DataFrame:
    return trace(flywheel(), {"J.w": "speed"}, 0.005, seed=1)


@pytest.mark.parametrize(
    ("change", "params", "outputs", "words"),
    [
        (lambda d: d.rename(columns={"time": "t_s"}), PARAMS, {"J.w": "speed"}, "no time column"),
        (lambda d: d.iloc[::-1], PARAMS, {"J.w": "speed"}, "times must increase"),
        (lambda d: d, PARAMS, {"J.w": "rpm"}, "no column 'rpm'"),
        (lambda d: d, PARAMS, {"J.omega": "speed"}, "J.omega"),
        (lambda d: d, {"brake.peak": (2.0, 1.0)}, {"J.w": "speed"}, "'brake.peak': low must be below high"),
        (lambda d: d, {"brake.useHeatPort": (0, 1)}, {"J.w": "speed"}, "'brake.useHeatPort'"),
        (lambda d: d, {"brake.extrapolation": (0, 1)}, {"J.w": "speed"}, "not sweepable"),
        (lambda d: d, {"StopTime": (1, 2)}, {"J.w": "speed"}, "not sweepable"),
        (lambda d: d, {"brake.mu": (0, 1)}, {"J.w": "speed"}, "'brake.mu'"),
        (lambda d: d, {"brake.mu_pos[4, 2]": (0, 1)}, {"J.w": "speed"}, "row 4 is outside"),
        (lambda d: d, {"brake.peak[1, 1]": (1, 2)}, {"J.w": "speed"}, "not a table"),
    ],
)
def test_bad_input_is_refused_by_name_before_any_run(no_runs, data, change, params, outputs, words):
    with pytest.raises(ModelError, match=words.replace("[", r"\[").replace("(", r"\(")):
        st.fit(flywheel(), change(data), params, outputs=outputs, progress=False)


def test_whole_table_and_start_values_and_top_level_parameters(data):
    model = flywheel(mu=[0.33, 0.27, 0.22], peak=1.2)
    fit = st.fit(
        model,
        data,
        {"brake.mu_pos": (0.05, 1.0), "brake.peak": (1.0, 2.0)},
        outputs={"J.w": "speed"},
        progress=False,
    )
    assert list(fit.estimates) == [
        "brake.mu_pos[1,2]",
        "brake.mu_pos[2,2]",
        "brake.mu_pos[3,2]",
        "brake.peak",
    ]
    assert fit.estimates["brake.mu_pos[3,2]"] == pytest.approx(0.2, rel=0.01)


def test_a_data_column_drives_a_model_input():
    """A measured pressure drives brake.f_normalized through a TimeTable: the fit finds fn_max."""
    truth = flywheel()
    measured = trace(truth, {"J.w": "speed", "press.y": "pressure"}, 0.0, seed=0)
    start = flywheel()
    start.set("brake.fn_max", 80.0)
    start.set("press.k", 0.1)  # what drove the port before is cut off: the data drive it now
    fit = st.fit(
        start,
        measured,
        {"brake.fn_max": (50.0, 200.0)},
        outputs={"J.w": "speed"},
        inputs={"brake.f_normalized": "pressure"},
        progress=False,
    )
    assert fit.estimates["brake.fn_max"] == pytest.approx(100.0, rel=1e-3)
