"""Derived variables (``Model.variable``, ``[variables]``) as FMU outputs: the runtime reads
them from the core like any other variable, so FMPy (an independent importer) gets the values
``r[name]`` of the same model run in stiction at every communication point, FMI 2.0 and 3.0."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.validation import validate_fmu
from paths import MSL_EXAMPLES

import stiction as st

OUTPUTS = ["slip", "heat", "J1.w"]


@pytest.mark.parametrize("version", [2, 3])
def test_derived_variables_are_fmu_outputs_with_the_result_values(tmp_path: Path, version: int) -> None:
    m = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    m.parameters["k"] = 3.0
    m.variable("slip", "J1.w - J2.w")
    m.variable("heat", "k * clutch1.tau * der(clutch1.phi_rel)")
    fmu = m.to_fmu(tmp_path / f"cc{version}.fmu", fmi_version=version, outputs=OUTPUTS)
    assert validate_fmu(str(fmu)) == []
    described = {v.name: v for v in fmpy.read_model_description(fmu).modelVariables}
    assert described["slip"].causality == "output" and described["heat"].causality == "output"
    h = 0.01
    run = fmpy.simulate_fmu(fmu, stop_time=1.5, output_interval=h, output=OUTPUTS)
    r = m.simulate(StopTime=1.5)
    assert np.ptp(r["heat"]) > 1.0  # the clutch slips and locks within the run
    for t, *values in run[["time", *OUTPUTS]].tolist():
        row = np.flatnonzero(np.abs(r.time - t) <= 1e-12)[-1]  # the last row at that instant
        for name, value in zip(OUTPUTS, values, strict=True):
            assert value == r[name][row], (t, name)
