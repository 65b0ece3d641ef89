"""An FMU refuses a negative friction coefficient set by its host (issue 29), in the engine's
words, as the model file, Python and ``Simulation.set_parameter`` do: FMI 3.0 sets a table
whole and is refused at once; FMI 2.0 sets it element by element (a table passes through
shapes the model refuses), so it is refused at the end of initialization."""

from __future__ import annotations

from pathlib import Path

import pytest
from fmpy.fmi1 import FMICallException
from paths import REPO
from test_fmu_state import Runner

import stiction as st

FLYWHEEL = REPO / "examples" / "braked_flywheel.toml"
NEGATIVE = [[0.0, 0.5], [50.0, 0.3], [100.0, -0.2]]


@pytest.mark.parametrize("version", [2, 3], ids=["fmi2", "fmi3"])
def test_a_negative_coefficient_set_by_the_host_is_refused(tmp_path: Path, version: int) -> None:
    model = st.Model.load(FLYWHEEL)
    model.set("brake.mu_pos", [[0.0, 0.5], [50.0, 0.3], [100.0, 0.2]])
    r = Runner(model.to_fmu(tmp_path / "fly.fmu", fmi_version=version), version)
    cells = [x for row in NEGATIVE for x in row]
    with pytest.raises(FMICallException):
        if version == 3:
            r.slave.setFloat64([r.vr["brake.mu_pos"]], cells)
        else:
            names = [f"brake.mu_pos[{i + 1},{j + 1}]" for i in range(3) for j in range(2)]
            r.slave.setReal([r.vr[n] for n in names], cells)
            r.start(1.0)
    assert "coefficients must be >= 0, got -0.2 in row [100, -0.2]" in r.messages[-1], r.messages
