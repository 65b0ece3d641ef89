"""More MSL rotational examples against their MAP-LIB references (tube method, 2e-3).

SimpleGearShift (planetary gear, brake and clutch), First (ideal gear, no friction),
OneWayClutch (actively engaged freewheel, Pulse engagement), OneWayClutchDisengaged
(freewheel alone) and Backlash (ElastoBacklash soft contact; MAP-LIB has no column of its
ElastoBacklash2 branch, tests/model/test_backlash2.py checks that against its closed form), each run with its model file's MSL experiment settings. Where MSL has a
``.signals.txt`` we compare exactly those signals (mode signals included); where it has none
(OneWayClutch, First) every column of the reference file is compared, as MSL does.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from paths import MSL_DATA, REPO

import stiction as st
from stiction.results.io.csv import read_csv

MSL_DIR = MSL_DATA
EXAMPLES = ["SimpleGearShift", "First", "OneWayClutch", "OneWayClutchDisengaged", "Backlash"]


def _signals(example: str) -> Path | None:
    path = MSL_DIR / f"{example}.signals.txt"
    return path if path.exists() else None


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_stays_inside_the_msl_tube(example: str) -> None:
    """Every compared signal lies inside the MSL tube, and a 1 % offset of one would not."""
    result = st.Model.load(REPO / "examples" / "msl" / f"{example}.toml").simulate()
    reference = MSL_DIR / f"{example}.csv"
    report = st.compare(result, reference, tolerance=2e-3, signals=_signals(example))
    assert len(report) >= 4
    assert report.passed, str(report)
    # Negative control on the first compared signal: the check can fail.
    ref_names, ref_data = read_csv(reference)
    name = next(iter(report)).name
    bad = result.data.copy()
    ref = ref_data[:, ref_names.index(name)]
    bad[:, result.names.index(name)] += 0.01 * (np.ptp(ref) or 1.0)
    assert st.compare((result.names, bad), reference, signals=_signals(example)).failed == [name]


def test_simple_gear_shift_changes_gear_ratio_from_0_4_to_1() -> None:
    """Brake holding the ring: carrier = sun/(1 + 1.5); clutch locked: everything turns at one speed."""
    r = st.Model.load(REPO / "examples" / "msl" / "SimpleGearShift.toml").simulate()
    t, engine, load = r.time, r["engine.w"], r["load.w"]
    before = (t > 1.0) & (t < 2.0)
    np.testing.assert_allclose(load[before], engine[before] / 2.5, rtol=1e-9, atol=1e-12)
    after = t > 2.2
    np.testing.assert_allclose(load[after], engine[after], rtol=1e-9)
    assert set(np.unique(r["clutch.mode"][after])) == {0.0}
    assert set(np.unique(r["brake.mode"][after])) == {2.0}


def test_one_way_clutch_never_slides_backward() -> None:
    """A freewheel: w_rel ≥ 0 up to the solver tolerance, and no loss while stuck.

    In OneWayClutch w_rel touches 0 tangentially at t = 1.5 s, where the drive torque changes
    sign (spec §7.6: "tolerance-sensitive"); within one step the integrator dips to about
    −5e-8 there without a sign change at a step end, so the bound is the Tolerance (1e-6).
    """
    for example in ("OneWayClutch", "OneWayClutchDisengaged"):
        r = st.Model.load(REPO / "examples" / "msl" / f"{example}.toml").simulate()
        assert r["oneWayClutch.w_rel"].min() > -1e-6, example
        stuck = r["oneWayClutch.stuck"] == 1.0
        assert stuck.any() and (~stuck).any()
        # lossPower is zero whenever stuck (MSL), and never negative
        assert np.all(r["oneWayClutch.lossPower"][stuck] == 0.0)
        assert r["oneWayClutch.lossPower"].min() >= -1e-9


def test_the_backlash_switches_inside_a_contact_are_events() -> None:
    """MSL writes the ElastoBacklash's switches inside a contact (no pulling torque, the
    damper's share capped at the spring's) with noEvent. Stepping over those kinks cost the
    integrator its order: at the default Tolerance 1e-6, 0.09 rad/s off a tight run (1e-10),
    and 2.5e-3 still at 1e-8. As events, the run converges at the method's order."""
    model = st.Model.load(REPO / "examples" / "msl" / "Backlash.toml")
    tight = model.simulate(Tolerance=1e-10)
    errors = []
    for tol in (1e-6, 1e-8):
        r = model.simulate(Tolerance=tol)
        errors.append(
            np.abs(
                r["elastoBacklash.w_rel"] - np.interp(r.time, tight.time, tight["elastoBacklash.w_rel"])
            ).max()
        )
    assert errors[0] < 5e-3 and errors[1] < errors[0] / 100, errors
