"""st.fit on a brake dyno trace with fade (docs/fit.md, worked example 2: the rig and its log
are examples/fit/brake_dyno_fade.py): a mu map over speed and temperature, round trip at 0.5 %
noise; a temperature row the data never reach, and a fade table without its reference row,
reported unidentifiable with the reason; table ranges parsed 1-based and inclusive."""

from __future__ import annotations

import re
import runpy

import pytest
from paths import EXAMPLES

import stiction as st
from stiction.fitting.params import parse_params, silent_reason

DYNO = runpy.run_path(str(EXAMPLES / "fit" / "brake_dyno_fade.py"))
MU_CELLS = ["brake.mu_pos[1,2]", "brake.mu_pos[2,2]", "brake.mu_pos[3,2]"]
FADE_CELLS = ["brake.mu_T[2,2]", "brake.mu_T[3,2]", "brake.mu_T[4,2]"]
TRUTH = dict(
    zip(
        MU_CELLS + FADE_CELLS,
        [row[1] for row in DYNO["TRUE_MU"]] + [row[1] for row in DYNO["TRUE_FADE"][1:]],
        strict=True,
    )
)


@pytest.fixture(scope="module")
def five_stops():
    """Five stops heating the disc from 20 to about 525 degC: every fade row is crossed."""
    return DYNO["measure"](DYNO["rig"](DYNO["TRUE_MU"], DYNO["TRUE_FADE"]), 0.005, seed=1)


def test_dyno_trace_round_trip_recovers_the_mu_map(five_stops):
    fit = DYNO["fit_map"](five_stops)
    assert list(fit.estimates) == MU_CELLS + FADE_CELLS
    for name, truth in TRUTH.items():
        assert fit.estimates[name] == pytest.approx(truth, rel=0.01), name
        low, high = fit.intervals[name]
        assert low < truth < high, name
    assert not fit.unidentifiable
    # the fitted model replays the trace to the noise: 0.5 % of each signal's largest value
    assert fit.sigma == pytest.approx(0.005, rel=0.05)


def test_a_temperature_row_the_data_never_reach_is_reported():
    """Three stops heat the disc to about 345 degC: the 450 degC row acts only above 350 degC."""
    truth = DYNO["rig"](DYNO["TRUE_MU"], DYNO["TRUE_FADE"], 3)
    assert truth.simulate()["disc.T"].max() < 623.15
    data = DYNO["measure"](truth, 0.005, seed=2)
    fit = DYNO["fit_map"](data, stops=3)
    assert fit.estimates["brake.mu_T[4,2]"] is None and fit.intervals["brake.mu_T[4,2]"] is None
    reason = fit.unidentifiable["brake.mu_T[4,2]"]
    assert "zero sensitivity" in reason and "above 623.15 K" in reason and "never get there" in reason
    assert re.search(r"brake\.mu_T\[4,2\] +not identifiable: the fitted outputs", fit.report())
    for name in MU_CELLS + FADE_CELLS[:2]:
        assert fit.estimates[name] == pytest.approx(TRUTH[name], rel=0.015), name
    assert fit.runs < 60  # the unreached row is held, not wandered along


def test_mu_pos_with_a_free_reference_row_is_reported_unidentifiable(five_stops):
    """mu = mu_T(T)*mu_pos(w): scaling every speed point up and every factor down by the same
    number changes nothing, so without a fixed row neither table is identified."""
    params = {"brake.mu_pos[:, 2]": (0.05, 1.0), "brake.mu_T[:, 2]": (0.1, 1.5)}
    fit = DYNO["fit_map"](five_stops, params=params)
    assert set(fit.unidentifiable) == {*MU_CELLS, "brake.mu_T[1,2]", *FADE_CELLS}
    assert "cannot tell its effect apart from" in fit.unidentifiable["brake.mu_T[1,2]"]
    assert "brake.mu_pos[1,2]" in fit.unidentifiable["brake.mu_T[1,2]"]


def _brake_with_table() -> st.Model:
    m = st.Model("m")
    m.add("J", st.Inertia(J=1.0))
    table = [[0.0, 293.15, 573.15, 773.15], [0.0, 0.42, 0.40, 0.22], [50.0, 0.40, 0.38, 0.20]]
    fade = [[293.15, 1.0], [473.15, 0.9], [623.15, 0.7], [723.15, 0.5]]
    m.add("brake", st.Brake(fn_max=100.0, mu_table=table, peak_T=fade, useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=500.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("brake.heatPort", "disc.port")
    return m


def test_table_ranges_and_a_2d_tables_coefficients():
    m = _brake_with_table()
    labels = [p.label for p in parse_params(m, {"brake.mu_table": (0.0, 1.0)})]
    assert labels == [f"brake.mu_table[{i},{j}]" for i in (2, 3) for j in (2, 3, 4)]  # no abscissa
    labels = [p.label for p in parse_params(m, {"brake.mu_table[:, 3:end]": (0.0, 1.0)})]
    assert labels == [
        "brake.mu_table[2,3]",
        "brake.mu_table[2,4]",
        "brake.mu_table[3,3]",
        "brake.mu_table[3,4]",
    ]
    labels = [p.label for p in parse_params(m, {"brake.peak_T[2:3, 2]": (0.5, 2.0)})]
    assert labels == ["brake.peak_T[2,2]", "brake.peak_T[3,2]"]
    # where a point acts, for the reason a fit gives when the data never get there
    (cell,) = parse_params(m, {"brake.mu_table[3, 3]": (0.0, 1.0)})
    assert silent_reason(m, cell) == (
        "brake.mu_table cell [3,3] (speed 50, T = 573.15 K) acts only while the slip speed is above 0 "
        "and the temperature is between 293.15 K and 773.15 K in 'brake', and the data never get there"
    )
    (row,) = parse_params(m, {"brake.peak_T[1, 2]": (0.5, 2.0)})
    assert silent_reason(m, row).startswith(
        "brake.peak_T row 1 (293.15 K) acts only while the heat port's temperature is below 473.15 K"
    )
    with pytest.raises(st.ModelError, match=r"brake.peak_T\[3:2, 2\]': row range 3:2 is empty"):
        parse_params(m, {"brake.peak_T[3:2, 2]": (0.5, 2.0)})
    with pytest.raises(st.ModelError, match="row 9 is outside the table's 1..4"):
        parse_params(m, {"brake.peak_T[2:9, 2]": (0.5, 2.0)})
