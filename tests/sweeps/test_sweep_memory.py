"""A metrics-only sweep keeps nothing per variant in Python beyond its table: the traced
peak of 2000 variants exceeds that of 200 by no more than the table's growth plus a
constant (one batch of work). Keeping a Python record or result tuple per variant (a few
hundred bytes each) would exceed it several times over."""

from __future__ import annotations

import tracemalloc

from paths import EXAMPLES

import stiction as st
from stiction.sweeps import sample, sweep

METRICS = ["max(J1.w)", "events()"]
# one batch's Python objects (its override lists, the arrays the core returns) and the
# interpreter's own noise
CONSTANT = 64 * 1024


def short_coupled_clutches() -> st.Model:
    """CoupledClutches over 0.2 s: memory per variant does not depend on the run's length."""
    model = st.Model.load(EXAMPLES / "msl" / "CoupledClutches.toml")
    model.experiment["StopTime"] = 0.2
    return model


def traced_peak(model: st.Model, n: int) -> tuple[int, int]:
    """(traced peak of the sweep in bytes, the table's size in bytes)."""
    variants = sample(n, seed=1, dists={"clutch1.fn_max": (10.0, 30.0)})
    tracemalloc.start()
    try:
        result = sweep(model, variants, METRICS, workers=2, batch_size=100, progress=False)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert (result.table["status"] == "ok").all()
    return peak, int(result.table.memory_usage(deep=True).sum())


def test_a_sweeps_memory_grows_with_its_table_only():
    model = short_coupled_clutches()
    sweep(model, sample(20, seed=2, dists={"clutch1.fn_max": (10.0, 30.0)}), METRICS, progress=False)
    small, small_table = traced_peak(model, 200)
    large, large_table = traced_peak(model, 2000)
    growth, table_growth = large - small, large_table - small_table
    assert table_growth > 0
    assert growth <= table_growth + CONSTANT, (
        f"the peak grew {growth} B from 200 to 2000 variants, the table {table_growth} B: "
        f"{(growth - table_growth) / 1800:.0f} B per variant beyond it"
    )
