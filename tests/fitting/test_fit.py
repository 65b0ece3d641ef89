"""st.fit: round trips on data stiction made with known parameters and seeded noise."""

from __future__ import annotations

import numpy as np
import pytest
from models import TRUE_MU, TRUE_PEAK, clutches, flywheel, trace

import stiction as st

PARAMS = {"brake.mu_pos[:, 2]": (0.05, 1.0), "brake.peak": (1.0, 2.0)}
LABELS = ["brake.mu_pos[1,2]", "brake.mu_pos[2,2]", "brake.mu_pos[3,2]", "brake.peak"]
TRUTH = dict(zip(LABELS, [*TRUE_MU, TRUE_PEAK], strict=True))
START = flywheel(mu=[0.33, 0.27, 0.22], peak=1.2)


def _within(estimates: dict, truth: dict, rel: float) -> None:
    for name, value in truth.items():
        assert estimates[name] == pytest.approx(value, rel=rel), name


def test_flywheel_round_trip_recovers_table_and_peak_within_one_percent():
    data = trace(flywheel(), {"J.w": "speed"}, 0.005, seed=1)
    fit = st.fit(START, data, PARAMS, outputs={"J.w": "speed"}, progress=False)
    assert fit.method == "output-error"
    _within(fit.estimates, TRUTH, 0.01)
    for name, (low, high) in fit.intervals.items():
        assert low < fit.estimates[name] < high
    # the fitted model carries the estimates and reproduces the data to the noise
    assert fit.model["brake"].params["peak"] == pytest.approx(fit.estimates["brake.peak"])
    again = fit.model.simulate()
    assert np.interp(data.time, again.time, again["J.w"]) == pytest.approx(fit.fitted["J.w"], abs=1e-6)
    assert fit.residuals["J.w"].std() == pytest.approx(0.005 * np.abs(data.speed).max(), rel=0.1)
    assert list(fit.table["parameter"]) == LABELS
    assert "brake.peak" in fit.report()


def test_clutch2_of_coupled_clutches_round_trip():
    names = {"clutch2.w_rel": "slip", "J2.w": "w2"}
    data = trace(clutches(), names, 0.005, seed=3)
    params = {"clutch2.mu_pos[:, 2]": (0.05, 1.0), "clutch2.peak": (1.0, 2.0)}
    fit = st.fit(clutches(mu=[0.45, 0.4, 0.45], peak=1.2), data, params, outputs=names, progress=False)
    truth = {"clutch2.mu_pos[1,2]": 0.5, "clutch2.mu_pos[2,2]": 0.45, "clutch2.mu_pos[3,2]": 0.4}
    _within(fit.estimates, truth, 0.01)
    # peak shows in the speeds only through the break-away instants: 0.55 % standard error
    low, high = fit.intervals["clutch2.peak"]
    assert low < 1.1 < high
    assert fit.estimates["clutch2.peak"] == pytest.approx(1.1, rel=0.01)


def test_linear_and_output_error_paths_agree():
    measured = {"J.w": "speed", "brake.tau": "torque", "brake.fn": "force", "brake.w": "slip"}
    data = trace(flywheel(), measured, 0.002, seed=5)
    linear = st.fit(
        START,
        data,
        PARAMS,
        outputs={"brake.tau": "torque", "brake.fn": "force", "brake.w": "slip"},
        progress=False,
    )
    assert linear.method == "linear" and linear.runs == 0
    error = st.fit(START, data, PARAMS, outputs={"J.w": "speed"}, method="output-error", progress=False)
    _within(linear.estimates, TRUTH, 0.01)
    _within(linear.estimates, error.estimates, 0.01)


def test_peak_of_a_brake_that_never_sticks_is_reported_unidentifiable():
    data = trace(flywheel(amplitude=60.0), {"J.w": "speed"}, 0.005, seed=2)
    start = flywheel(amplitude=60.0, mu=[0.33, 0.27, 0.22], peak=1.2)
    fit = st.fit(start, data, PARAMS, outputs={"J.w": "speed"}, progress=False)
    assert fit.estimates["brake.peak"] is None and fit.intervals["brake.peak"] is None
    assert "never sticks" in fit.unidentifiable["brake.peak"]
    assert "not identifiable" in fit.report()
    assert fit.estimates["brake.mu_pos[3,2]"] == pytest.approx(0.2, rel=0.01)


def test_linear_peak_without_break_away_is_reported():
    measured = {"brake.tau": "torque", "brake.fn": "force", "brake.w": "slip"}
    data = trace(flywheel(amplitude=60.0), measured, 0.002, seed=2)
    fit = st.fit(START, data, PARAMS, outputs=measured, method="linear", progress=False)
    assert fit.estimates["brake.peak"] is None
    assert "no break-away" in fit.unidentifiable["brake.peak"]


def _covered(fit) -> list[bool]:
    return [fit.intervals[n][0] <= TRUTH[n] <= fit.intervals[n][1] for n in LABELS]


def _coverage(draws: int) -> float:
    hits = []
    for seed in range(draws):
        data = trace(flywheel(), {"J.w": "speed"}, 0.005, seed=100 + seed)
        hits += _covered(st.fit(START, data, PARAMS, outputs={"J.w": "speed"}, progress=False))
    return float(np.mean(hits))


def test_intervals_cover_the_truth_in_a_few_draws():
    assert _coverage(6) >= 0.75


@pytest.mark.slow
def test_intervals_cover_the_truth_in_90_to_99_percent_of_50_draws():
    assert 0.90 <= _coverage(50) <= 0.99


def test_plot_shows_measured_fitted_and_residuals():
    import matplotlib

    matplotlib.use("Agg")
    measured = {"brake.tau": "torque", "brake.fn": "force", "brake.w": "slip"}
    data = trace(flywheel(), measured, 0.002, seed=5)
    fit = st.fit(START, data, PARAMS, outputs=measured, progress=False)
    axes = fit.plot()
    assert axes.shape == (2, 1)
    assert [line.get_label() for line in axes[0][0].get_lines()] == ["measured", "fitted"]
    assert len(axes[1][0].get_lines()[0].get_xdata()) == len(data)
