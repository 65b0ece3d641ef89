"""The tutorial's vehicle launch (examples/vehicle_launch.py) does what docs/tutorial.md says."""

from __future__ import annotations

import runpy

import numpy as np
import pytest
from paths import EXAMPLES

EXAMPLE = EXAMPLES / "vehicle_launch.py"


def test_vehicle_launch_locks_then_brakes_to_a_stop_and_its_energy_closes() -> None:
    r = runpy.run_path(str(EXAMPLE))["build"]().simulate()
    assert r.initialization is not None
    status = {v.variable: v.status for v in r.initialization}
    assert status["wheel.w"] == "fixed" and status["clutch.w_rel"] == "computed"
    assert r["clutch.w_rel"][0] == pytest.approx(-150.0)  # engine at 150 rad/s, vehicle at rest
    t_clutch = r.first("clutch.locked")
    assert t_clutch is not None and 0.1 < t_clutch < 2.5  # locks while the throttle is open
    press = next(e for e in r.events if e.component == "brake" and e.new == "sliding forward")
    assert press.time == 2.5 and "time event of throttle (Step), brake_pedal (Step)" in press.cause
    [t_brake] = r.lock_times("brake")
    assert 2.5 < t_brake < 5.0 and abs(r["wheel.w"][-1]) < 1e-6
    # work of the sources = kinetic + potential energy + what clutch, brake, shaft dissipated
    losses = r.energy("clutch") + r.energy("brake") + r.energy("shaft")
    stored = r["system.kineticEnergy"][-1] + r["system.potentialEnergy"][-1] - r["system.kineticEnergy"][0]
    assert losses == pytest.approx(r["system.dissipatedEnergy"][-1], rel=1e-6)
    assert r["system.sourceWork"][-1] == pytest.approx(stored + r["system.dissipatedEnergy"][-1], rel=1e-6)
    assert np.all(np.diff(r.energy("brake", cumulative=True)) >= -1e-6)  # locked: sa·w, w ~ 1e-10
