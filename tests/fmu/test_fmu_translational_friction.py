"""The translational friction family in FMUs and sweeps: MSL's Translational Brake and PreLoad
examples export and run in FMPy to the results of ``Model.simulate``, and a sweep of the brake's
normal force gives the closed-form stopping distances."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from paths import EXAMPLES

import stiction as st

DIR = EXAMPLES / "msl-translational"
CASES = {
    "Brake": (2.0, ["mass1.s", "mass1.v", "mass2.v"]),
    "PreLoad": (100.0, ["spool.s", "innerContactA.s_rel"]),
}


@pytest.mark.parametrize("example", list(CASES))
def test_fmu_matches_simulate(example: str, tmp_path: Path) -> None:
    model = st.Model.load(DIR / f"{example}.toml")
    stop, outputs = CASES[example]
    fmu = model.to_fmu(tmp_path / f"{example}.fmu", outputs=outputs)
    res = fmpy.simulate_fmu(str(fmu), stop_time=stop, output_interval=stop / 1000, output=outputs)
    r = model.simulate()
    for name in outputs:
        ref = np.interp(res["time"], r.time, r[name])
        assert np.abs(res[name] - ref).max() < 1e-3 * np.ptp(r[name]), name


def test_a_sweep_of_the_normal_force_gives_the_closed_form_stopping_distances() -> None:
    """Braked from 0.1 s on with f = mu·fn_max·2 (mu 0.5, step height 2) the 1 kg mass at 1 m/s
    stops after 0.1 + 1/(2·fn_max) m."""
    model = st.Model.load(DIR / "Brake.toml")
    values = [0.75, 1.0, 2.0, 4.0]
    result = st.sweep(model, st.grid({"brake.fn_max": values}), ["final(mass1.s)"], progress=False)
    assert list(result.table["status"]) == ["ok"] * len(values)
    got = np.array(result.table["final(mass1.s)"])
    want = 0.1 + 1.0 / (2.0 * np.array(result.table["brake.fn_max"]))
    np.testing.assert_allclose(got, want, rtol=1e-8)
