"""When does it stop? Asked of a speed, the answer comes from the modes (issue 29).

A locked element keeps a = 0 and its slip where the event band left it: about ±1e-10 rad/s,
not 0 (here −1.0018e-10). So asked of the speed alone, "J.w == 0" never held and "J.w < 0"
held at the lock although the flywheel never turned backward. ``time_of`` (metrics, sweeps),
``Result.first`` and ``Result.lock_times`` read a speed that a locked element holds — its own
relative speed, or a shaft it holds against ground — as 0 while it is locked and on the left
row of its lock (the same instant, the slip already past the band); the columns keep the
integrated values.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from paths import REPO

import stiction as st


def _braked() -> st.Model:
    m = st.Model("braked_flywheel")
    m.add("J", st.Inertia(J=2.0, phi=0.0, w=100.0))
    m.add("brake", st.Brake(fn_max=2000.0, mu_pos=[[0, 0.42], [100, 0.35]], peak=1.15))
    m.add("press", st.Ramp(height=1.0, duration=0.2, startTime=0.5))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


@pytest.fixture(scope="module")
def braked() -> st.Result:
    return _braked().simulate(StopTime=2.0, Interval=1e-3)


def test_the_locked_speed_is_inside_the_band_not_zero(braked: st.Result) -> None:
    lock = braked.lock_times("brake")[0]
    after = braked.time > lock
    w = braked["J.w"][after]
    assert np.all(w != 0.0) and np.all(np.abs(w) < 1.01e-10)  # the column as integrated


def test_questions_about_stopping_take_the_mode(braked: st.Result) -> None:
    lock = braked.lock_times("brake")[0]
    assert braked.metric("time_of(J.w == 0)") == lock
    assert braked.metric("time_of(brake.w == 0)") == lock
    assert braked.metric("time_of(J.w <= 0)") == lock
    assert math.isnan(braked.metric("time_of(J.w < 0)"))  # it never turned backward
    assert math.isnan(braked.metric("time_of(brake.w < 0)"))
    assert braked.first("J.w == 0") == lock
    assert braked.first("J.w < 0") is None
    assert braked.first("J.w", lambda w: w < 0) is None
    assert braked.first("J.w <= 0") == lock
    assert braked.lock_times("J") == braked.lock_times("brake") == [lock]
    # a question that is not about stopping is answered as before
    assert braked.metric("time_of(J.w < 50)") == braked.first("J.w", lambda w: w < 50)


def test_a_sweep_answers_the_same(braked: st.Result) -> None:
    variants = {"brake.fn_max": [2000.0], "StopTime": [2.0], "Interval": [1e-3]}
    sweep = st.sweep(_braked(), variants, ["time_of(J.w == 0)", "time_of(J.w < 0)"], progress=False)
    row = sweep.table.iloc[0]
    assert row["time_of(J.w == 0)"] == braked.metric("time_of(J.w == 0)")
    assert math.isnan(row["time_of(J.w < 0)"])


def test_a_clutchs_relative_speed_between_two_shafts() -> None:
    r = st.Model.load(REPO / "examples" / "msl" / "CoupledClutches.toml").simulate()
    locked = r["clutch2.locked"] != 0.0
    left_of_lock = np.zeros_like(locked)
    left_of_lock[:-1] = locked[1:] & (r.time[1:] == r.time[:-1])
    held = np.asarray(r._source.held_rows("clutch2.w_rel"))
    assert held.any() and np.array_equal(held, locked | left_of_lock)
    w = np.where(held, 0.0, r["clutch2.w_rel"])
    after = r.time > r.lock_times("clutch2")[0]
    assert r.first("clutch2.w_rel", lambda v: v == 0.0) == r.time[np.flatnonzero(w == 0.0)[0]]
    assert np.all(w[after & held] == 0.0)
    assert not np.any(r._source.held_rows("J1.w"))  # a shaft no element holds against ground
