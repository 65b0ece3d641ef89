"""The fit tests' models and data: a braked flywheel and CoupledClutches, with known parameters,
and their traces with seeded Gaussian noise."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
from paths import EXAMPLES

import stiction as st

TRUE_MU = [0.3, 0.25, 0.2]
TRUE_PEAK = 1.3


def flywheel(mu: list[float] = TRUE_MU, peak: float = TRUE_PEAK, amplitude: float = 22.0) -> st.Model:
    """A flywheel (J = 0.5) driven by a 1 Hz sine torque against a brake at half its 100 N: it
    sticks at each turn back and breaks away when the drive exceeds peak*mu(0)*fn (amplitude
    22), or never sticks (a strong drive, 60, with a bias)."""
    m = st.Model("flywheel")
    m.add("J", st.Inertia(J=0.5, w=0.0))
    m.add("drive", st.Torque())
    m.add("sine", st.Sine(amplitude=amplitude, f=1.0, offset=0.0 if amplitude < 50 else 40.0))
    table = [[0.0, mu[0]], [1.5, mu[1]], [3.0, mu[2]]]
    m.add("brake", st.Brake(fn_max=100.0, mu_pos=table, peak=peak, extrapolation="HoldLastPoint"))
    m.add("press", st.Constant(k=0.5))
    m.connect("sine.y", "drive.tau")
    m.connect("drive.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment.update(StopTime=2.0, Interval=0.001, Tolerance=1e-8)
    return m


def clutches(mu: Sequence[float] = (0.5, 0.45, 0.4), peak: float = 1.1) -> st.Model:
    """MSL's CoupledClutches with clutch 2 pressed by a pulsing force (0.5 ± 0.3 at 4 Hz from
    0.4 s, for the step of the example), so that it sticks and breaks away four times, and
    with a 3-point table over the slip it reaches (0 … 0.69 rad/s). The plate never opens
    fully: each break-away happens under a clamp force that is still changing, so its instant
    tells peak (standard error 0.55 % at 0.5 % noise; with a plate that opens to 0, 1.2 %)."""
    text = (EXAMPLES / "msl" / "CoupledClutches.toml").read_text()
    text = text.replace('["step1.y", "clutch2.f_normalized"]', '["press2.y", "clutch2.f_normalized"]')
    press = 'press2 = { type = "Sine", amplitude = 0.3, f = 4.0, offset = 0.5, startTime = 0.4 }'
    text = text.replace("step1 = {", press + "\nstep1 = {")
    m = st.Model.loads(text, EXAMPLES / "msl")
    m.set("clutch2.mu_pos", [[0.0, mu[0]], [0.3, mu[1]], [0.6, mu[2]]])
    m.set("clutch2.peak", peak)
    m.set("clutch2.extrapolation", "HoldLastPoint")
    m.experiment.update(Tolerance=1e-8)
    return m


def trace(model: st.Model, names: dict[str, str], noise: float, seed: int) -> pd.DataFrame:
    """The model's run as measured: each variable with Gaussian noise of ``noise`` times its
    largest magnitude, on the output grid (no event rows)."""
    result = model.simulate()
    time = result.time
    step = float(model.experiment["Interval"])
    keep = np.abs(time / step - np.round(time / step)) < 1e-6  # an event's rows are not samples
    keep &= np.concatenate([[True], np.diff(time) > 0])
    rng = np.random.default_rng(seed)
    frame = {"time": time[keep]}
    for variable, column in names.items():
        y = result[variable][keep]
        frame[column] = y + noise * np.max(np.abs(y)) * rng.standard_normal(len(y))
    return pd.DataFrame(frame)
