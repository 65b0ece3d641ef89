"""Results easy to use: energy per component, first/lock times, named modes, a unique time
index for pandas, units in plots and DataFrames; Model.set with construction's checks."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from paths import MSL_EXAMPLES

import stiction as st

# A flywheel (J = 2, w0 = 10) braked from t = 0 by mu·cgeo·fn = 0.5·1·100 = 50 N·m: it stops
# at t = J·w0/50 = 0.4 s, having dissipated its kinetic energy J·w0²/2 = 100 J.
T_LOCK, E_LOSS = 0.4, 100.0


def braked_model() -> st.Model:
    m = st.Model("braked")
    m.add("J", st.Inertia(J=2.0, phi=0.0, w=10.0))
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=[[0.0, 0.5]]))
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


@pytest.fixture(scope="module")
def braked() -> st.Result:
    return braked_model().simulate(StopTime=1.0, Interval=1e-3)


def test_energy_of_one_component_is_its_dissipated_work(braked: st.Result) -> None:
    assert braked.energy("brake") == pytest.approx(E_LOSS, rel=1e-9)
    course = braked.energy("brake", cumulative=True)
    assert course.shape == braked.time.shape and np.all(np.diff(course) >= 0.0)
    assert course[-1] == pytest.approx(braked["system.dissipatedEnergy"][-1], rel=1e-9)
    with pytest.raises(KeyError, match="dissipate: brake"):
        braked.energy("J")


def test_first_and_lock_times(braked: st.Result) -> None:
    assert braked.first("brake.locked") == pytest.approx(T_LOCK, abs=1e-9)
    assert braked.lock_times("brake") == [braked.first("brake.locked")]
    assert braked.first("J.w", lambda w: w < 5.0) == pytest.approx(0.2, abs=1.01e-3)
    assert braked.first("J.w", lambda w: w < -1.0) is None


def test_events_carry_mode_names(braked: st.Result) -> None:
    stop = next(e for e in braked.events if e.component == "brake" and e.time > 0)
    assert (stop.old, stop.new) == ("sliding forward", "stuck")
    assert "brake: sliding forward → stuck" in str(stop)
    assert braked.events[0].old == "unknown"


def test_to_pandas_with_a_unique_index_round_trips_through_resample(braked: st.Result) -> None:
    every = braked.to_pandas()
    assert not every["time"].is_unique  # event instants have a left and a right row
    df = braked.to_pandas(events="last")
    assert df.index.is_unique and df.index.is_monotonic_increasing
    assert len(df) == every["time"].nunique()
    t_lock = next(e.time for e in braked.events if e.new == "stuck")
    assert df.loc[t_lock, "brake.locked"] == 1.0  # the value after the event
    assert braked.to_pandas(events="first").loc[t_lock, "brake.locked"] == 0.0  # before
    assert df.attrs["units"]["J.w"] == "rad/s" and df.attrs["units"]["brake.tau"] == "N.m"
    grid = df.set_axis(pd.to_timedelta(df.index, unit="s")).resample("50ms").first()
    assert len(grid) == 21
    back = np.interp(grid.index.total_seconds(), df.index, df["J.w"])
    np.testing.assert_allclose(grid["J.w"].to_numpy(), back, rtol=0, atol=1e-12)
    np.testing.assert_allclose(grid["J.w"].iloc[:8], 10.0 - 25.0 * np.arange(8) * 0.05, atol=1e-9)
    assert np.all(np.isfinite(np.gradient(df["J.w"].to_numpy(), df.index.to_numpy())))
    with pytest.raises(ValueError, match="events"):
        braked.to_pandas(events="middle")


def test_plots_show_units_and_named_modes(braked: st.Result) -> None:
    fig = braked.plot("J.w", "brake.mode")
    speed, mode = fig.axes
    assert speed.get_ylabel() == "J.w [rad/s]"
    assert [t.get_text() for t in mode.get_yticklabels()] == [
        "sliding backward",
        "stuck",
        "sliding forward",
        "free",
    ]


def test_model_set_checks_like_construction() -> None:
    m = st.Model("m").add("brake", st.Brake(fn_max=100.0))
    m.set("brake.fn_max", 1800)
    assert m["brake"].params["fn_max"] == 1800
    for name, value, message in [
        ("brake.fn_mx", 1.0, "did you mean 'fn_max'"),
        ("brake.peak", 0.5, r"parameter 'peak': must be >= 1"),
        ("brake.mu_pos", [0.5, 0.4], "flat list"),
        ("brak.fn_max", 1.0, "did you mean 'brake'"),
    ]:
        with pytest.raises(st.ModelError, match=message):
            m.set(name, value)
    assert m["brake"].params == {"fn_max": 1800}


def test_every_name_of_a_fresh_result_is_its_table_column() -> None:
    """Reading names one by one (states from the rows, the first algebraic one computing the
    table, the rest views of it) gives the table's columns bit for bit, and the closed form:
    the brake's friction torque is 50 N·m while the flywheel slides."""
    m = braked_model()
    fresh, whole = m.simulate(StopTime=1.0, Interval=1e-3), m.simulate(StopTime=1.0, Interval=1e-3)
    raw = fresh._source
    assert raw.is_direct("J.w") and raw.is_direct("brake.mode") and not raw.is_direct("brake.tau")
    with pytest.raises(KeyError):
        raw.is_direct("J.nothing")
    columns = {name: fresh[name] for name in fresh.names}
    for i, name in enumerate(whole.names):
        assert np.array_equal(columns[name], whole.data[:, i], equal_nan=True), name
    sliding = fresh.time < T_LOCK - 1e-3
    assert np.allclose(np.abs(columns["brake.tau"][sliding]), 50.0, rtol=1e-12)


def test_a_result_too_large_for_every_variable_at_once_gives_them_one_at_a_time() -> None:
    """The engine refuses the table of a result too large for memory (a UsageError); reading a
    variable then computes it alone, as for a drivetrain of 10 000 elements."""

    class Huge:
        """The engine's raw result as a 10 000-element run answers: no table, each column."""

        rows = 3

        def is_direct(self, name: str) -> bool:
            return False

        def table(self) -> None:
            raise st.UsageError("every variable of this result is … more than fits in memory")

        def column(self, name: str) -> list[float]:
            return [1.0, 2.0, 3.0]

    r = st.Result(["time", "brake.tau"], source=Huge())
    np.testing.assert_array_equal(r["brake.tau"], [1.0, 2.0, 3.0])
    with pytest.raises(st.UsageError, match="more than fits in memory"):
        _ = r.data


def test_a_large_table_outlives_its_result_and_its_memory_goes_to_a_later_one() -> None:
    """A large table (HeatLosses': 35 MB) is a NumPy array over the engine's memory, which the
    engine reuses for a later table only once no array uses it: a column kept after its result
    is gone keeps its values while later runs compute theirs; once it is gone too, the next table
    is written into that memory, with the values of one written into fresh memory."""
    model = st.Model.load(MSL_EXAMPLES / "HeatLosses.toml")
    kept = model.simulate().data
    assert kept.nbytes >= 32 << 20  # large enough for the engine to keep its memory
    address = kept.__array_interface__["data"][0]
    column, expected = kept[:, 7], kept[:, 7].copy()
    del kept  # the column, a view, still holds the memory
    other = {"params": {"sine.amplitude": 19.0}, "StopTime": 0.99}  # other values, fewer rows
    later = model.simulate(**other).data
    assert later.__array_interface__["data"][0] != address
    np.testing.assert_array_equal(column, expected)
    del later, column  # the last one freed is kept: the first table's memory
    again = model.simulate(**other).data
    assert again.__array_interface__["data"][0] == address
    fresh = model.simulate(**other).data
    assert fresh.__array_interface__["data"][0] != address
    assert again.shape == fresh.shape and again.tobytes() == fresh.tobytes()


@pytest.mark.parametrize("name", ["HeatLosses", "CoupledClutches", "OneWayClutch"])
def test_a_run_recording_every_variable_gives_the_table_computed_after_it(name: str) -> None:
    """`simulate(record="all")` computes every variable while the run goes on: the same run
    (events, steps) and the same table, bit for bit, as every variable computed after the run;
    a parameter override and a compiled model's variants take the same path."""
    model = st.Model.load(MSL_EXAMPLES / f"{name}.toml")
    after, live = model.simulate(), model.simulate(record="all")
    assert live.events == after.events and live.stats["steps"] == after.stats["steps"]
    assert live.data.shape == after.data.shape and live.data.tobytes() == after.data.tobytes()
    compiled = model.compile()
    variant = {"StopTime": 0.5 * model.experiment["StopTime"]}
    expected = compiled.simulate(**variant).data
    assert compiled.simulate(record="all", **variant).data.tobytes() == expected.tobytes()


def test_record_must_be_states_or_all() -> None:
    """Any other `record` is a ValueError naming the choices, before anything runs."""
    model = braked_model()
    with pytest.raises(ValueError, match="record must be one of 'states', 'all', got 'every'"):
        model.simulate(record="every")
    with pytest.raises(ValueError, match="record must be one of"):
        model.compile().simulate(record="All")
