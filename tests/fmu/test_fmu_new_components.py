"""The issue-30 components in sweeps and FMUs: ElastoBacklash2 (Backlash) and EddyCurrentTorque
(EddyCurrentBrake, whose torque reads the heat capacitor's temperature) export and run in an
FMU to the same results as ``Model.simulate``, and their parameters sweep."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

CASES = {
    "Backlash": ["elastoBacklash2.phi_rel", "elastoBacklash2.w_rel"],
    "EddyCurrentBrake": ["inertia.w", "heatCapacitor.T"],
}


@pytest.mark.parametrize("example", list(CASES))
def test_fmu_matches_simulate(example: str, tmp_path: Path) -> None:
    model = st.Model.load(MSL_EXAMPLES / f"{example}.toml")
    outputs = CASES[example]
    fmu = model.to_fmu(tmp_path / f"{example}.fmu", outputs=outputs)
    res = fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.001, output=outputs)
    r = model.simulate()
    for name in outputs:
        ref = np.interp(res["time"], r.time, r[name])
        assert np.abs(res[name] - ref).max() < 1e-3 * np.ptp(r[name]), name


def test_parameters_of_the_new_components_sweep() -> None:
    brake = st.Model.load(MSL_EXAMPLES / "EddyCurrentBrake.toml")
    result = st.sweep(
        brake, st.grid({"eddyCurrentTorque.alpha20": [0.0, 3.92e-3]}), ["final(inertia.w)"], progress=False
    )
    assert list(result.table["status"]) == ["ok", "ok"]
    for _, row in result.table.iterrows():
        single = brake.simulate(params={"eddyCurrentTorque.alpha20": row["eddyCurrentTorque.alpha20"]})
        assert row["final(inertia.w)"] == single.metric("final(inertia.w)")
    # the temperature coefficient reaches the torque (through the heated capacitor)
    finals = list(result.table["final(inertia.w)"])
    assert finals[0] != finals[1]
    backlash = st.Model.load(MSL_EXAMPLES / "Backlash.toml")
    swept = st.sweep(
        backlash, st.grid({"elastoBacklash2.d": [0.0, 50.0]}), ["max(elastoBacklash2.w_rel)"], progress=False
    )
    assert list(swept.table["status"]) == ["ok", "ok"]
    undamped, damped = swept.table["max(elastoBacklash2.w_rel)"]
    assert undamped > damped
