"""CoupledClutches against an independent high-accuracy solution (the "oracle").

The MSL reference (Dymola, DASSL, tolerance 1e-6) is only good to about 2e-5 rad/s, too
coarse to pin event instants down. The oracle is an event-driven solution of the same
model at rtol = atol = 1e-12, confirmed by a second, unrelated solver to 1.5e-9 s on
every switch instant and 1e-8 rad/s on the speeds. Here we run at Tolerance = 1e-10.
"""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

MODEL = MSL_EXAMPLES / "CoupledClutches.toml"
CLUTCHES = ("clutch1", "clutch2", "clutch3")

# Copied from /work/shared/reference/oracle/CoupledClutches.md ("exact switch instants"):
# the instant of each mode change and the modes (clutch1, clutch2, clutch3) from then on.
# −1 sliding backward, 0 stuck, 1 sliding forward, 2 free.
ORACLE_MODES: list[tuple[float, tuple[int, int, int]]] = [
    (0.0, (-1, 2, 2)),  # clutch1 engaged and slipping; 2 and 3 open
    (0.4, (-1, -1, 2)),  # clutch2 engages (step) and slips
    (0.7096214746937467, (-1, 0, 2)),  # clutch2 locks
    (0.791662359154753, (0, 0, 2)),  # clutch1 locks
    (0.8311085061376531, (-1, 0, 2)),  # clutch1 breaks away
    (0.9, (-1, 0, -1)),  # clutch3 engages (step) and slips
    (0.9068501927975855, (0, 0, -1)),  # clutch1 locks
    (1.0002958598946388, (-1, 0, -1)),  # clutch1 breaks away
    (1.1439674924731575, (-1, 0, 0)),  # clutch3 locks
    (1.25, (2, 0, 0)),  # fn of clutch1 reaches 0: free
]
# Same source: [J1.w, J2.w, J3.w, J4.w] in rad/s.
ORACLE_SPEEDS: dict[float, tuple[float, float, float, float]] = {
    0.4: (6.166326070701574, 3.8336739292985, 0.0, 0.0),
    0.9: (3.5565005666303966, 3.540059602868476, 3.540059602868476, 0.0),
    1.5: (3.247058272418844, 2.4631871666495124, 2.4631871666495138, 2.4631871666495133),
}

TOLERANCE = 1e-10
# At rtol 1e-10 the event functions (slip speeds, |sa| − tau0_max) are located to about
# rtol·|w| / |d(w_rel)/dt| ≲ 1e-10 s (relative accelerations are ≥ 1 rad/s² at every
# switch); the oracle itself is good to 1.5e-9 s. 1e-8 s leaves room for both.
SWITCH_TIME_TOL = 1e-8
# Speeds: ~rtol·10 rad/s of integration error plus the oracle's own 1e-8 rad/s.
SPEED_TOL = 1e-7


@cache
def _result() -> st.Result:
    return st.Model.load(MODEL).simulate(Tolerance=TOLERANCE)


def _mode_timeline(events: list[st.Event]) -> list[tuple[float, tuple[int, int, int]]]:
    """Replay the event log: the modes of the three clutches after each event instant."""
    modes = dict.fromkeys(CLUTCHES, 3)  # 3 = Unknown, the pre-value at initialization
    timeline: list[tuple[float, tuple[int, int, int]]] = []
    for event in sorted(events, key=lambda e: e.time):  # stable: keeps in-instant order
        assert event.component in modes, event
        assert event.old_mode == modes[event.component], f"log skips a mode: {event}"
        modes[event.component] = event.new_mode
        state = (modes["clutch1"], modes["clutch2"], modes["clutch3"])
        if timeline and abs(timeline[-1][0] - event.time) <= 1e-12:
            timeline[-1] = (timeline[-1][0], state)  # same instant: keep the final modes
        else:
            timeline.append((event.time, state))
    return timeline


def test_switch_instants_and_modes_match_the_oracle() -> None:
    """Every mode switch happens at the oracle's instant (±1e-8 s), in the same order."""
    timeline = _mode_timeline(_result().events)
    assert [modes for _, modes in timeline] == [modes for _, modes in ORACLE_MODES]
    errors = [abs(t - t_oracle) for (t, _), (t_oracle, _) in zip(timeline, ORACLE_MODES, strict=True)]
    assert max(errors) < SWITCH_TIME_TOL, errors


def test_mode_signals_follow_the_oracle_between_switches() -> None:
    """The `clutchk.mode` trajectories hold the oracle's modes in every interval."""
    r = _result()
    bounds = [t for t, _ in ORACLE_MODES] + [1.5]
    for (start, modes), end in zip(ORACLE_MODES, bounds[1:], strict=True):
        inside = (r.time > start + 1e-6) & (r.time < end - 1e-6)
        assert inside.sum() > 10, (start, end)  # the output grid is 5e-4 s
        for clutch, mode in zip(CLUTCHES, modes, strict=True):
            np.testing.assert_array_equal(r[f"{clutch}.mode"][inside], mode, err_msg=f"{clutch} {start}")


@pytest.mark.parametrize("t", sorted(ORACLE_SPEEDS))
def test_speeds_match_the_oracle(t: float) -> None:
    """J1.w … J4.w at t = 0.4, 0.9 (event instants, both sides) and 1.5 within 1e-7 rad/s."""
    r = _result()
    rows = np.flatnonzero(np.abs(r.time - t) <= 1e-12)
    assert rows.size >= 1
    for k, expected in enumerate(ORACLE_SPEEDS[t], start=1):
        got = r[f"J{k}.w"][rows]
        assert np.abs(got - expected).max() < SPEED_TOL, (f"J{k}.w", t, got, expected)


def test_speeds_are_consistent_with_the_relative_states() -> None:
    """Kinematics: J(k+1).w = Jk.w + clutchk.w_rel everywhere (the states are relative)."""
    r = _result()
    for k, clutch in enumerate(CLUTCHES, start=1):
        np.testing.assert_allclose(r[f"J{k + 1}.w"], r[f"J{k}.w"] + r[f"{clutch}.w_rel"], rtol=0, atol=1e-12)
