"""The vehicle stopping example (examples/vehicle_stop.py and .toml, issue 31): the twins are
one model, and the numbers it reports are what independent computations from the result give."""

from __future__ import annotations

import runpy

import numpy as np
from paths import EXAMPLES

import stiction as st

EXAMPLE = runpy.run_path(str(EXAMPLES / "vehicle_stop.py"))


def test_the_python_model_and_its_toml_twin_run_the_same() -> None:
    r_py = EXAMPLE["build"]().simulate()
    r_toml = st.Model.load(EXAMPLES / "vehicle_stop.toml").simulate()
    assert r_py.names == r_toml.names
    np.testing.assert_array_equal(r_py.data, r_toml.data)


def test_the_reported_stop_closes_its_energy_and_meets_the_definitions() -> None:
    r = EXAMPLE["build"]().simulate()
    stop = EXAMPLE["report"](r)
    v0, m, j, radius = EXAMPLE["V0"], EXAMPLE["M"], EXAMPLE["J"], EXAMPLE["R"]
    t, v = r.time, r["car.v"]
    # the tyre rolls throughout (it never skids at this pressure), so no energy goes there
    assert r["tyre.locked"].min() == 1.0
    assert r.energy("tyre") < 1e-6  # (f times the held slip, ~1e-13 m/s)
    # energy: the brake took ½(m + J/R²)·v0² less the work of rolling resistance and drag,
    # integrated here from the forces and the speed (the trapezoid rule over 1 ms rows)
    step = np.diff(t)
    # PartialForce.f = flange.f, what the car pushes the load with: f·v is the power it takes
    resist = (r["rolling.f"] + r["drag.f"]) * v
    resist_work = float(np.sum(0.5 * (resist[1:] + resist[:-1]) * step))
    kinetic = 0.5 * (m + j / radius**2) * v0**2
    assert abs(stop.brake_energy - (kinetic - resist_work)) < 1e-4 * kinetic
    # ... and the disc holds it at its peak, but for what it gave the air until then:
    # C·(T_peak − T0) + ∫ Q_cooling dt = brake energy
    peak = int(np.argmax(r["disc.T"])) + 1
    q = r["cooling.Q_flow"][:peak]
    cooled = float(np.sum(0.5 * (q[1:] + q[:-1]) * step[: peak - 1]))
    heat = 2760.0 * (stop.peak_disc_temperature - 293.15)
    assert abs(heat + cooled - stop.brake_energy) < 1e-3 * stop.brake_energy
    # the stop: the car at rest where the brake locks the wheel; the distance is ∫ v dt
    assert abs(np.interp(stop.time, t, v)) < 1e-6
    assert abs(stop.distance - float(np.sum(0.5 * (v[1:] + v[:-1]) * step))) < 1e-4
    # MFDD from its definition, by the times the speed crosses 0.8·v0 and 0.1·v0 and the
    # distance between them integrated from the speed, against the report's interpolation
    tb, te = r.first("car.v", lambda x: x <= 0.8 * v0), r.first("car.v", lambda x: x <= 0.1 * v0)
    assert tb is not None and te is not None
    inside = (t > tb) & (t < te)
    grid = np.concatenate(([tb], t[inside], [te]))
    speed = np.interp(grid, t, v)
    covered = float(np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(grid)))
    mfdd = ((0.8 * v0) ** 2 - (0.1 * v0) ** 2) / (2.0 * covered)
    assert abs(stop.mfdd - mfdd) < 2e-3 * mfdd
    # fully developed, the deceleration is the brake's 960 N.m through the rolling wheel plus
    # the road loads: within them of 960·R/(J + m·R²)
    bare = 960.0 * radius / (j + m * radius**2)
    assert bare < stop.mfdd < bare + (47.088 + 76.39) / m
