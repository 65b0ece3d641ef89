"""Generated large drivetrains (issue 10): they run with the banded per-mode solve (above 40
unknowns) and the union-find rank test, and their physics closes. No timing here: see
scripts/bench_scaling.py."""

from __future__ import annotations

import numpy as np
import pytest
from paths import DATA

import stiction as st
from stiction.testing import chain_toml, ladder_toml


@pytest.mark.parametrize("n", [30, 120])
def test_a_generated_chain_locks_in_turn_and_keeps_momentum(n: int) -> None:
    res = st.Model.loads(chain_toml(n)).simulate()
    stop = float(res.time[-1])
    # no torque to the housing: Σ J·w grows by the drive's torque (1 N·m) only
    momentum = sum(res[f"J{k}.w"][-1] for k in range(n + 1))
    assert momentum == pytest.approx(10.0 + stop, rel=1e-6)
    for k in range(1, n + 1):
        locks = res.lock_times(f"clutch{k}")
        assert len(locks) == 1, f"clutch{k} locks {locks}"  # engages once, never chatters
        assert locks[0] >= 0.05 * k
    assert np.ptp([res[f"J{k}.w"][-1] for k in range(n + 1)]) < 1e-6


@pytest.mark.slow
def test_a_chain_of_1000_clutches_locks_each_once_and_keeps_momentum() -> None:
    """The issue's size: 1001 inertias, 2000 events, banded incremental solves throughout."""
    n = 1000
    res = st.Model.loads(chain_toml(n)).simulate()
    stop = float(res.time[-1])
    momentum = sum(res[f"J{k}.w"][-1] for k in range(n + 1))
    assert momentum == pytest.approx(10.0 + stop, rel=1e-6)
    locks = {e.component for e in res.events if e.new_mode == 0}
    assert len(locks) == n and res.stats["events"] == 2 * n  # each clutch slides, then locks once
    assert np.ptp([res[f"J{k}.w"][-1] for k in range(n + 1)]) < 1e-6


@pytest.mark.slow
def test_a_ladder_of_1000_elements_closes_its_energy_and_no_element_chatters() -> None:
    n = 1000
    res = st.Model.loads(ladder_toml(n)).simulate()
    assert res.audit().ok(), str(res.audit())
    changes: dict[str, list[float]] = {}
    for e in res.events:
        changes.setdefault(e.component, []).append(e.time)
    # engaging, then stopping, braked at 0.8 s and stopping again: a few changes, never a burst
    for name, times in changes.items():
        assert len(times) <= 5, (name, times)
        assert all(t2 - t0 > 1e-3 for t0, t2 in zip(times, times[2:])), (name, times)
    assert all(abs(res[f"J{k}.w"][-1]) < 1e-6 for k in range(3, n, 4))  # the brakes hold at the end


@pytest.mark.parametrize("kind", ["chain", "ladder"])
def test_the_dense_oracle_fixtures_are_what_the_generator_writes(kind: str) -> None:
    """crates/stiction-core/tests/dense_oracle.rs runs these against the dense LU."""

    fixture = DATA / f"{kind}100.toml"
    generate = chain_toml if kind == "chain" else ladder_toml
    assert fixture.read_text() == generate(100)


def test_a_generated_ladder_runs_and_its_brakes_hold() -> None:
    n = 60
    res = st.Model.loads(ladder_toml(n)).simulate()
    for k in range(3, n, 4):
        assert len(res.lock_times(f"brake{k}")) <= 1
    assert abs(res["J3.w"][-1]) < 1e-6  # braked to the housing at the end


def test_a_ladder_engaging_in_waves_takes_as_many_steps_at_any_size() -> None:
    """With its clutches engaging in 10 groups, the ladder's time events are the same 11 at any
    N, and so (nearly) are its steps: its cost can be linear in N. Each group's clutches engage
    at one instant, and the audit closes."""
    small, large = (st.Model.loads(ladder_toml(n, waves=10)).simulate() for n in (40, 400))
    for res in (small, large):
        assert res.stats["time_events"] == 11
        assert res.audit().ok(), str(res.audit())
    assert large.stats["steps"] <= 1.3 * small.stats["steps"], (small.stats, large.stats)
    staggered = st.Model.loads(ladder_toml(400)).simulate()
    assert staggered.stats["steps"] > 2 * large.stats["steps"]  # one time event per clutch
    engaged = [e.time for e in large.events if e.component in ("clutch41", "clutch79") and e.time > 0]
    assert engaged == [pytest.approx(0.1, abs=1e-12)] * 2, engaged


def test_redundant_locks_in_a_large_model_carry_no_torque() -> None:
    """Two brakes on the chain's last inertia lock together: the one offered later carries 0."""
    text = chain_toml(40)
    extra = '["J40.flange_b", "brakeA.flange_a"], ["J40.flange_b", "brakeB.flange_a"], '
    extra += '["on.y", "brakeA.f_normalized"], ["on.y", "brakeB.f_normalized"],'
    text = text.replace("connect = [", "connect = [\n  " + extra, 1)
    text += 'brakeA = { type = "Brake", fn_max = 1000.0 }\n'
    text += 'brakeB = { type = "Brake", fn_max = 1000.0 }\n'
    text += 'on = { type = "Step", startTime = 0.0 }\n'
    res = st.Model.loads(text).simulate()
    assert res.lock_times("brakeA") == [0.0] and res.lock_times("brakeB") == [0.0]
    assert np.all(res["brakeB.tau"] == 0.0)
    assert abs(res["brakeA.tau"][-1]) > 0.1  # the chain pulls on J40 once clutch40 engages


def test_bench_scale_prints_a_row_per_model_and_size() -> None:
    from click.testing import CliRunner

    from stiction.cli import main

    out = CliRunner().invoke(main, ["bench", "--scale", "4,12"])
    assert out.exit_code == 0, out.output
    rows = [line.split() for line in out.output.splitlines()[1:]]
    assert [(r[0], r[1]) for r in rows] == [
        ("chain", "4"),
        ("chain", "12"),
        ("ladder", "4"),
        ("ladder", "12"),
        ("ladder-waves", "4"),
        ("ladder-waves", "12"),
    ]
    assert all(float(r[2]) > 0 and int(r[5]) > 0 for r in rows)
    bad = CliRunner().invoke(main, ["bench", "--scale", "4,x"])
    assert bad.exit_code == 2 and "--scale" in bad.output and "'4,x'" in bad.output, bad.output


def test_bench_scale_prints_a_refused_size_and_goes_on(monkeypatch: pytest.MonkeyPatch) -> None:
    """A size the engine refuses (its memory guard) is one row saying why; the others still run."""
    from click.testing import CliRunner

    import stiction.cli.benchmarks
    from stiction.cli import main

    real = stiction.cli.benchmarks.bench_scale

    def guarded(kind: str, n: int) -> stiction.cli.benchmarks.ScaleRow:
        if n > 10:
            raise st.ModelError(
                "experiment: Interval = 0.0015 gives about 11002 rows, more than fits in memory"
            )
        return real(kind, n)

    monkeypatch.setattr(stiction.cli.benchmarks, "bench_scale", guarded)
    out = CliRunner().invoke(main, ["bench", "--scale", "4,20"])
    assert out.exit_code == 0, out.output
    rows = [line.split() for line in out.output.splitlines()[1:]]
    assert [r[:3] for r in rows] == [
        ["chain", "4", rows[0][2]],
        ["chain", "20", "refused:"],
        ["ladder", "4", rows[2][2]],
        ["ladder", "20", "refused:"],
        ["ladder-waves", "4", rows[4][2]],
        ["ladder-waves", "20", "refused:"],
    ]
    assert "more than fits in memory" in out.output
