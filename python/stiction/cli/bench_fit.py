"""``stiction bench --fit`` (issue 33): fit 4 parameters (a 3-point ``mu_pos`` and ``peak``) of a
braked flywheel to a 2 s trace of 2001 samples of its speed with 0.5 % noise, made by the
model itself; print the wall time, the model runs it took, the estimates and the machine's load."""

from __future__ import annotations

import os
import time

import click
import numpy as np

from stiction import _deps
from stiction.model.components import Brake, Constant, Inertia, Sine, Torque
from stiction.model.model import Model

__all__ = ["flywheel", "print_fit"]

TRUTH = {"brake.mu_pos[1,2]": 0.3, "brake.mu_pos[2,2]": 0.25, "brake.mu_pos[3,2]": 0.2, "brake.peak": 1.3}


def flywheel(mu: tuple[float, float, float], peak: float) -> Model:
    """A flywheel (J = 0.5) driven by a 1 Hz sine torque of 22 N.m against a brake at half its
    100 N: it sticks at each turn back and breaks away four times in 2 s."""
    m = Model("flywheel")
    m.add("J", Inertia(J=0.5, w=0.0))
    m.add("drive", Torque())
    m.add("sine", Sine(amplitude=22.0, f=1.0))
    table = [[0.0, mu[0]], [1.5, mu[1]], [3.0, mu[2]]]
    m.add("brake", Brake(fn_max=100.0, mu_pos=table, peak=peak, extrapolation="HoldLastPoint"))
    m.add("press", Constant(k=0.5))
    m.connect("sine.y", "drive.tau")
    m.connect("drive.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment.update(StopTime=2.0, Interval=0.001, Tolerance=1e-8)
    return m


def print_fit(workers: int | None = None, seed: int = 1) -> None:
    """Make the trace, fit from a start 10 % off, print the numbers."""
    from stiction.fitting import fit

    pd = _deps.pandas
    result = flywheel((0.3, 0.25, 0.2), 1.3).simulate()
    t = result.time
    keep = (np.abs(t * 1000 - np.round(t * 1000)) < 1e-6) & np.concatenate([[True], np.diff(t) > 0])
    w = result["J.w"][keep]
    rng = np.random.default_rng(seed)
    data = pd.DataFrame({"time": t[keep], "speed": w + 0.005 * np.abs(w).max() * rng.standard_normal(len(w))})
    start = flywheel((0.33, 0.27, 0.22), 1.2)
    params = {"brake.mu_pos[:, 2]": (0.05, 1.0), "brake.peak": (1.0, 2.0)}
    load = os.getloadavg()[0]
    began = time.perf_counter()
    fitted = fit(start, data, params, outputs={"J.w": "speed"}, workers=workers, progress=False)
    wall = time.perf_counter() - began
    click.echo(
        f"fit: 4 parameters, {len(data)} samples: {wall:.3f} s, {fitted.runs} model runs "
        f"({1000 * wall / max(fitted.runs, 1):.2f} ms a run), {os.cpu_count()} cores, load {load:.2f}"
    )
    for name, value in fitted.estimates.items():
        shown = "not identifiable" if value is None else f"{value:.5f}"
        click.echo(f"  {name:<20} {shown}  (truth {TRUTH[name]})")
