"""A faded Brake (docs/fade.md: mu_T, peak_T, mu_table over the heat capacitor's temperature)
exports and runs in an FMU to the results of ``Model.simulate``, its fade tables among the
FMU's parameters."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest

import stiction as st

FADES = {
    "mu_T": {"mu_pos": [[0.0, 0.4]], "mu_T": [[293.15, 1.0], [313.15, 0.5]], "peak_T": [[293.15, 1.2]]},
    "mu_table": {"mu_table": [[0.0, 293.15, 313.15], [0.0, 0.4, 0.2], [200.0, 0.35, 0.15]]},
}


def _stop(fade: dict) -> st.Model:
    m = st.Model("faded")
    m.add("disc", st.Inertia(J=2.0, w=100.0))
    m.add("brake", st.Brake(fn_max=500.0, useHeatPort=True, **fade))
    m.add("press", st.Constant(k=1.0))
    m.add("cap", st.HeatCapacitor(C=1000.0, T={"start": 293.15, "fixed": True}))
    m.connect("disc.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "cap.port")
    m.experiment.update(StopTime=2.0, Interval=1e-3)
    return m


@pytest.mark.parametrize("which", list(FADES))
def test_a_faded_brake_runs_in_an_fmu_as_in_simulate(which: str, tmp_path: Path) -> None:
    model = _stop(FADES[which])
    outputs = ["disc.w", "cap.T", "brake.mu"]
    fmu = model.to_fmu(tmp_path / "faded.fmu", outputs=outputs)
    names = {v.name for v in fmpy.read_model_description(str(fmu)).modelVariables}
    assert any(name.startswith(f"brake.{which}") for name in names)
    res = fmpy.simulate_fmu(str(fmu), stop_time=2.0, output_interval=1e-3, output=outputs)
    r = model.simulate()
    assert r["cap.T"][-1] == pytest.approx(
        293.15 + 0.5 * 2.0 * 100.0**2 / 1000.0, rel=1e-7
    )  # default Tolerance
    for name in outputs:
        ref = np.interp(res["time"], r.time, r[name])
        assert np.abs(res[name] - ref).max() < 1e-3 * np.ptp(r[name]), name
