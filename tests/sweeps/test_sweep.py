"""Sweeps: every metric and trajectory of a variant equals the single run with the same
overrides; failing variants are rows with their error; Dask gives the local table; an
interrupted sweep with ``out=`` resumes without running a variant twice; a compiled model
is reused while the model is unchanged and pickles."""

from __future__ import annotations

import pickle

import numpy as np
import pandas as pd
import pytest
from paths import EXAMPLES

import stiction as st
from stiction.sweeps import grid, sample, sweep
from stiction.sweeps import runner as sweep_module

COUPLED = st.Model.load(EXAMPLES / "msl" / "CoupledClutches.toml")
FLYWHEEL = st.Model.load(EXAMPLES / "braked_flywheel.toml")

COUPLED_METRICS = [
    "final(J4.w)",
    "max(J1.w)",
    "min(clutch2.tau)",
    "integral(clutch1.lossPower)",
    "mean(J3.w)",
    "time_of(clutch3.locked)",
    "events(clutch2)",
    "events()",
]
FLYWHEEL_METRICS = [
    "time_of(brake.locked)",
    "max(disc.T)",
    "integral(brake.lossPower)",
    "final(flywheel.phi)",
]


def same(a: float, b: float) -> bool:
    return (np.isnan(a) and np.isnan(b)) or a == b or abs(a - b) <= 1e-12 * max(abs(a), abs(b))


def on_grid(result: st.Result, name: str, time: np.ndarray) -> np.ndarray:
    """The single run's value at each grid time: the last row at that instant."""
    t, v = result.time, result[name]
    rows = [np.flatnonzero(np.abs(t - tg) <= 1e-12 * max(1.0, abs(tg)))[-1] for tg in time]
    return v[rows]


@pytest.mark.parametrize(
    ("model", "metrics", "dists", "output"),
    [
        (
            COUPLED,
            COUPLED_METRICS,
            {"clutch1.fn_max": (5.0, 40.0), "sin1.f": (1.0, 8.0), "J1.w": (5.0, 15.0)},
            "J2.w",
        ),
        (
            FLYWHEEL,
            FLYWHEEL_METRICS,
            {"brake.fn_max": (800.0, 3000.0), "brake.peak": (1.0, 1.5)},
            "brake.tau",
        ),
    ],
    ids=["CoupledClutches", "braked_flywheel"],
)
def test_metrics_and_trajectories_equal_single_runs(model, metrics, dists, output):
    variants = sample(20, seed=7, dists=dists)
    result = sweep(model, variants, metrics, outputs=[output], progress=False)
    assert list(result.table.columns) == [*dists, *metrics, "status", "wall_s"]
    assert (result.table["status"] == "ok").all()
    for k, row in variants.iterrows():
        single = model.simulate(params=row.to_dict())
        for metric in metrics:
            expected, got = single.metric(metric), result.table.loc[k, metric]
            assert same(got, expected), f"variant {k} {metric}: sweep {got}, single {expected}"
        np.testing.assert_array_equal(result.trajectories[output][k], on_grid(single, output, result.time))
    # the overrides acted: the variants differ
    assert result.table[metrics[1]].nunique() > 1


def test_a_failing_variant_is_a_row_with_its_error():
    variants = grid({"brake.fn_max": [1500.0, -10.0, 2500.0]})
    result = sweep(FLYWHEEL, variants, ["time_of(brake.locked)"], progress=False)
    status = list(result.table["status"])
    assert status[0] == status[2] == "ok"
    assert "brake" in status[1] and "fn_max" in status[1], status[1]
    assert np.isnan(result.table.loc[1, "time_of(brake.locked)"])


def test_bad_metrics_and_names_are_refused_before_any_run():
    with pytest.raises(st.ModelError, match="J1.ww"):
        sweep(COUPLED, grid({"clutch1.fn_max": [10.0]}), ["max(J1.ww)"], progress=False)
    with pytest.raises(st.ModelError, match="clutch9"):
        COUPLED.compile().simulate({"clutch9.fn_max": 1.0})
    with pytest.raises(st.ModelError, match="fn_max"):
        COUPLED.compile().simulate({"clutch1.fnmax": 1.0})


def test_results_do_not_depend_on_workers_or_batches():
    variants = sample(24, seed=3, dists={"clutch2.fn_max": (5.0, 30.0)})
    one = sweep(COUPLED, variants, COUPLED_METRICS[:3], workers=1, batch_size=5, progress=False)
    two = sweep(COUPLED, variants, COUPLED_METRICS[:3], workers=2, batch_size=11, progress=False)
    pd.testing.assert_frame_equal(one.table.drop(columns="wall_s"), two.table.drop(columns="wall_s"))


def test_a_structural_override_equals_the_edited_model():
    edited = st.Model.loads(COUPLED.to_toml().replace('type = "Fixed"', 'type = "Fixed", phi0 = 0.25'))
    metrics = ["final(torque.phi)", "max(J4.w)"]
    swept = sweep(COUPLED, grid({"fixed.phi0": [0.25]}), metrics, progress=False)
    expected = edited.simulate()
    for metric in metrics:
        assert swept.table.loc[0, metric] == expected.metric(metric)
    # the housing's angle moved the source's relative angle
    assert expected.metric(metrics[0]) == pytest.approx(
        COUPLED.simulate().metric(metrics[0]) - 0.25, abs=1e-12
    )


def test_an_interrupted_sweep_resumes_without_running_a_variant_twice(tmp_path, monkeypatch):
    variants = sample(30, seed=5, dists={"clutch1.fn_max": (5.0, 40.0)})
    metrics = ["max(J1.w)", "time_of(clutch3.locked)"]
    run = sweep_module.run_batch
    ran: list[float] = []

    def counting(compiled, columns, *args):
        ran.extend(columns["clutch1.fn_max"])
        if len(ran) > 12:
            raise KeyboardInterrupt
        return run(compiled, columns, *args)

    monkeypatch.setattr(sweep_module, "run_batch", counting)
    with pytest.raises(KeyboardInterrupt):
        sweep(COUPLED, variants, metrics, outputs=["J4.w"], out=tmp_path, batch_size=4, progress=False)
    done_before = len(ran) - 4  # the batch that was interrupted wrote nothing
    ran.clear()
    monkeypatch.setattr(
        sweep_module,
        "run_batch",
        lambda c, columns, *a: (ran.extend(columns["clutch1.fn_max"]), run(c, columns, *a))[1],
    )
    resumed = sweep(COUPLED, variants, metrics, outputs=["J4.w"], out=tmp_path, batch_size=4, progress=False)
    assert len(ran) == 30 - done_before and len(set(ran)) == len(ran)
    assert set(ran).isdisjoint(variants["clutch1.fn_max"][:done_before])
    whole = sweep(COUPLED, variants, metrics, outputs=["J4.w"], progress=False)
    pd.testing.assert_frame_equal(resumed.table.drop(columns="wall_s"), whole.table.drop(columns="wall_s"))
    np.testing.assert_array_equal(resumed.trajectories["J4.w"], whole.trajectories["J4.w"])
    with pytest.raises(st.ModelError, match="another sweep"):
        sweep(COUPLED, variants, ["max(J2.w)"], out=tmp_path, progress=False)


def test_the_compiled_model_is_reused_until_the_model_changes_and_pickles():
    model = st.Model.loads(COUPLED.to_toml())
    compiled = model.compile()
    assert model.compile() is compiled
    model.experiment["StopTime"] = 1.0
    assert model.compile() is not compiled
    again = pickle.loads(pickle.dumps(compiled))
    a, b = compiled.simulate({"clutch1.fn_max": 12.0}), again.simulate({"clutch1.fn_max": 12.0})
    np.testing.assert_array_equal(a["J1.w"], b["J1.w"])


def test_a_model_changed_in_place_runs_as_changed():
    """`simulate` keeps the engine text while the model is unchanged; any in-place change
    (a parameter dict, the experiment) must still reach the run and the result's parameters."""
    model = st.Model.loads(COUPLED.to_toml())
    before = model.simulate()
    model.components["clutch1"].params["fn_max"] = 12.0
    changed = model.simulate()
    fresh = st.Model.loads(model.to_toml()).simulate()
    np.testing.assert_array_equal(changed["J1.w"], fresh["J1.w"])
    assert not np.array_equal(changed["J1.w"], before["J1.w"])
    assert changed.parameters["clutch1.fn_max"] == 12.0 and before.parameters["clutch1.fn_max"] != 12.0
    model.experiment["StopTime"] = 1.0
    assert model.simulate().time[-1] == 1.0


@pytest.mark.slow
def test_dask_gives_the_local_table():
    distributed = pytest.importorskip("distributed")
    variants = sample(16, seed=11, dists={"clutch1.fn_max": (5.0, 40.0), "sin1.f": (1.0, 8.0)})
    metrics = ["max(J1.w)", "time_of(clutch3.locked)"]
    local = sweep(COUPLED, variants, metrics, outputs=["J1.w"], progress=False)
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with cluster, distributed.Client(cluster) as client:
        remote = sweep(
            COUPLED, variants, metrics, outputs=["J1.w"], client=client, batch_size=4, progress=False
        )
    pd.testing.assert_frame_equal(local.table.drop(columns="wall_s"), remote.table.drop(columns="wall_s"))
    np.testing.assert_array_equal(local.trajectories["J1.w"], remote.trajectories["J1.w"])


@pytest.mark.parametrize(
    ("script", "args"), [("brake_doe.py", ["--n", "3"]), ("clutch_monte_carlo.py", ["--n", "20"])]
)
def test_the_sweep_examples_run(script, args, tmp_path, monkeypatch):
    import runpy
    import sys

    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.setattr(sys, "argv", [script, *args, "--out", str(tmp_path)])
    runpy.run_path(str(EXAMPLES / "sweeps" / script), run_name="__main__")
    assert list(tmp_path.glob("*.parquet")) and list(tmp_path.glob("*.png"))


def test_a_top_level_parameter_varies_everything_that_depends_on_it():
    model = st.Model.loads(COUPLED.to_toml())
    model.parameters["T2"] = 0.4
    model.parameters["T3"] = "T2 + 0.5"
    model.components["step1"].params["startTime"] = st.expr("T2")
    model.components["step2"].params["startTime"] = st.expr("T3")
    result = sweep(model, grid({"T2": [0.3, 0.6]}), ["time_of(clutch3.locked)", "max(J3.w)"], progress=False)
    for k, t2 in enumerate([0.3, 0.6]):
        edited = st.Model.loads(COUPLED.to_toml())
        edited.components["step1"].params["startTime"] = t2
        edited.components["step2"].params["startTime"] = t2 + 0.5
        single = edited.simulate()
        for metric in ("time_of(clutch3.locked)", "max(J3.w)"):
            assert result.table.loc[k, metric] == single.metric(metric), (t2, metric)
