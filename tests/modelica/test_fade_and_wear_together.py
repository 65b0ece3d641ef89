"""A Brake with both of stiction's extensions, fade (a Stiction.Components class) and wear (a
``__stiction_wear`` annotation), leaves and comes back through Modelica with both, and
``Model.load`` reads a ``.mo`` file as Modelica."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from paths import MSL_EXAMPLES

import stiction as st


def faded_worn_brake() -> st.Model:
    """A flywheel at 100 rad/s stopped by a Brake whose mu halves from 300 K to 600 K, with
    energy wear, heating a 500 J/K disc."""
    m = st.Model("faded_worn")
    m.add("J", st.Inertia(J=1.0, w=100.0))
    brake = st.Brake(
        fn_max=1000.0,
        mu_pos=[[0.0, 0.4]],
        useHeatPort=True,
        mu_T=[[300.0, 1.0], [600.0, 0.5]],
        wear=st.wear.Energy(alpha=1e-13),
    )
    m.add("brake", brake)
    m.add("disc", st.HeatCapacitor(C=500.0, T=300.0))
    m.add("press", st.Constant(k=1.0))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "disc.port")
    m.experiment.update(StopTime=2.0, Tolerance=1e-10)
    return m


def test_fade_and_wear_round_trip_through_modelica(tmp_path: Path) -> None:
    model = faded_worn_brake()
    before = model.simulate()
    # the wear is alpha times the kinetic energy the brake took, the disc heated by all of it
    assert abs(before["brake.wearVolume"][-1] / (1e-13 * 0.5 * 100.0**2) - 1) < 1e-7
    assert abs(before["disc.T"][-1] - 310.0) < 1e-6
    path = tmp_path / "faded_worn.mo"
    model.to_modelica(path)
    text = path.read_text()
    assert "Stiction.Components.Brake brake(" in text and "__stiction_wear(" in text
    after = st.Model.load(path).simulate()
    for name in ("J.w", "brake.mu", "disc.T", "brake.wearVolume"):
        assert np.array_equal(after[name], before[name]), name


def test_model_load_reads_a_modelica_file_as_from_modelica() -> None:
    path = MSL_EXAMPLES / "Friction.mo"
    loaded, read = st.Model.load(path).simulate(), st.Model.from_modelica(path).simulate()
    assert np.array_equal(loaded["inertia1.w"], read["inertia1.w"])
