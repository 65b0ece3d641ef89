"""MassWithStopAndFriction in an FMU (issue 31): the FMU runtime steps the same engine, so the
hard stops' resets (MSL's ``reinit``) happen in it too: MSL's Translational Friction example
exported with ``stop2`` bouncing between its stops runs to the same trajectory as
``Model.simulate``, never past its stop."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
from paths import EXAMPLES

import stiction as st


def test_fmu_resets_at_the_hard_stops_as_simulate(tmp_path: Path) -> None:
    model = st.Model.load(EXAMPLES / "msl-translational" / "Friction.toml")
    outputs = ["stop2.s", "stop2.v", "stop1.s"]
    fmu = model.to_fmu(tmp_path / "Friction.fmu", outputs=outputs)
    res = fmpy.simulate_fmu(str(fmu), stop_time=5.0, output_interval=0.001, output=outputs)
    r = model.simulate()
    for name in outputs:
        ref = np.interp(res["time"], r.time, r[name])
        assert np.abs(res[name] - ref).max() < 1e-3 * np.ptp(r[name]), name
    # stop2 started at -5 m/s reaches its lower stop smin + L/2 = -0.4 and never passes it
    assert res["stop2.s"].min() >= -0.4 - 1e-12
    assert res["stop2.s"].min() < -0.4 + 1e-3
