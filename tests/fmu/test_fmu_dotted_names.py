"""An FMU of a model with hierarchical component names (``clutch.c1``, ``J2.shaft``): its
variables carry the dotted names (FMI allows dots in a name), FMPy validates and runs it, and
it gives what ``simulate`` gives, a parameter set by its dotted name acting as in simulate."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.validation import validate_fmu
from paths import EXAMPLES

import stiction as st

RENAMES = {"clutch1": "clutch.c1", "J2": "J2.shaft"}
OUTPUTS = ["J1.w", "J2.shaft.w", "clutch.c1.w_rel", "clutch.c1.mode"]


def rename(name: str) -> str:
    head, dot, rest = name.partition(".")
    return RENAMES[head] + dot + rest if head in RENAMES else name


def dotted() -> st.Model:
    """CoupledClutches with two components renamed into paths."""
    original = st.Model.load(EXAMPLES / "msl" / "CoupledClutches.toml")
    m = st.Model(original.name)
    for name, comp in original.components.items():
        m.add(rename(name), comp)
    for a, b in original.connections:
        m.connect(rename(a), rename(b))
    m.experiment = dict(original.experiment)
    return m


@pytest.mark.parametrize("version", [2, 3], ids=["fmi2", "fmi3"])
def test_an_fmu_of_dotted_names_runs_in_fmpy_as_simulate(tmp_path: Path, version: int) -> None:
    m = dotted()
    fmu = m.to_fmu(tmp_path / "Dotted.fmu", fmi_version=version, outputs=OUTPUTS)
    assert validate_fmu(str(fmu)) == []
    names = {v.name for v in fmpy.read_model_description(fmu).modelVariables}
    assert {"clutch.c1.w_rel", "J2.shaft.w", "clutch.c1.fn_max", "J2.shaft.J"} <= names
    params = {"clutch.c1.fn_max": 30.0, "J2.shaft.J": 2.5}
    out = fmpy.simulate_fmu(
        str(fmu), stop_time=1.5, output_interval=0.01, output=OUTPUTS, start_values=params
    )
    ref = m.simulate(params=params)
    plain = m.simulate()
    for name in OUTPUTS[:-1]:
        expected = np.interp(out["time"], ref.time, ref[name])
        assert np.max(np.abs(out[name] - expected)) <= 1e-6 * max(float(np.ptp(expected)), 1e-12), name
    assert np.max(np.abs(out["J2.shaft.w"] - np.interp(out["time"], plain.time, plain["J2.shaft.w"]))) > 0.1
