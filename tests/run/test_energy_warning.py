"""A run whose energy balance does not close warns without being asked (issue 29).

The engine notes, at the end of every step, each switching element whose loss power went
below the event band (a stuck element's slip stays within ±1e-10 rad/s, so its held torque
shows at most about 1e-10·tau of power); only such a run is audited when its ``Result`` is
made, and a passive element the audit finds delivering energy is an ``st.EnergyWarning``
naming it and the energy. The command line prints it as ``warning: …`` on stderr.

The case: a LossyGear whose table, continued linearly past its last row as MSL does, reaches
an efficiency above 1 at the speeds of the run — the gear makes energy.
"""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest
from paths import REPO

import stiction as st


def _gaining_gear() -> st.Model:
    m = st.Model("gear_gain")
    m.add("J1", st.Inertia(J=1.0, phi=0.0, w=10.0))
    # 0.9 at rest, 0.95 at 1 rad/s: 1.4 at 10 rad/s
    m.add("gear", st.LossyGear(ratio=1.0, lossTable=[[0, 0.9, 0.9, 0, 0], [1, 0.95, 0.95, 0, 0]]))
    m.add("J2", st.Inertia(J=1.0))
    m.add("load", st.ConstantTorque(tau_constant=-5.0))
    m.add("motor", st.ConstantTorque(tau_constant=20.0))
    m.connect("motor.flange", "J1.flange_a")
    m.connect("J1.flange_b", "gear.flange_a")
    m.connect("gear.flange_b", "J2.flange_a")
    m.connect("J2.flange_b", "load.flange")
    return m


def test_a_passive_element_delivering_energy_warns_naming_it() -> None:
    with pytest.warns(
        st.EnergyWarning, match=r"^energy audit: gear delivered [0-9.]+ J over the run"
    ) as caught:
        r = _gaining_gear().simulate(StopTime=1.0)
    assert len(caught) == 1
    assert caught[0].filename == __file__  # points at the user's call, not inside stiction
    assert issubclass(st.EnergyWarning, UserWarning)
    delivered = r.audit().delivering()
    assert [e.component for e in delivered] == ["gear"]
    assert f"{-delivered[0].dissipated:.3g} J" in str(caught[0].message)


@pytest.mark.parametrize("example", ["CoupledClutches", "HeatLosses", "LossyGearDemo2", "OneWayClutch"])
def test_a_normal_run_neither_warns_nor_is_audited(example: str) -> None:
    m = st.Model.load(REPO / "examples" / "msl" / f"{example}.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error", st.EnergyWarning)
        r = m.simulate()
    assert r._source.delivering == []  # nothing to audit: the run pays nothing for the check


def test_the_command_line_prints_the_warning(tmp_path: Path) -> None:
    model = tmp_path / "gear.toml"
    _gaining_gear().save(model)
    proc = subprocess.run(
        [sys.executable, "-m", "stiction", "simulate", str(model), "--StopTime", "1"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.startswith("warning: ")]
    assert len(lines) == 1 and "gear delivered" in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr and "EnergyWarning" not in proc.stderr
