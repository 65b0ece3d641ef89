"""A brake dyno trace with fade, and the mu map over speed and temperature fitted to it.

docs/fit.md, worked example 2. The rig: a 40 kg.m2 dyno inertia that the dyno's motor spins up
to about 121 rad/s (2400 N.m for 2 s, and the ramps), then the brake stops it at 80 bar, five
times in a row with no pause to cool, so the disc (2500 J/K, 20 W/K to the air) heats from 20 to
about 525 degC, past the pads' fade onset. The brake's mu is a speed curve (``mu_pos``, 0, 60,
120 rad/s) times a fade factor over the disc temperature (``mu_T``, 20, 200, 350, 450 degC, the
20 degC row the reference, 1). ``fn_max`` is the clamp force per bar (255 N/bar), so the logged
line pressure in bar drives ``brake.f_normalized`` as it is.

The dyno logs the inertia's speed, the disc temperature (a thermocouple, in K), the line
pressure and the motor torque every 20 ms; the speed and temperature here carry Gaussian noise
of 0.5 % of their largest value, the logged commands none. Run ``python
examples/fit/brake_dyno_fade.py``: it makes the trace with the true map and fits the map back.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

import stiction as st

DT = 0.02  # the log's sample interval [s]
TRUE_MU = [[0.0, 0.42], [60.0, 0.40], [120.0, 0.37]]  # mu over slip speed [rad/s]
TRUE_FADE = [[293.15, 1.0], [473.15, 0.92], [623.15, 0.70], [723.15, 0.50]]  # factor over T [K]


def schedule(stops: int, w0: float = 120.0, J: float = 40.0, motor: float = 2400.0, bar: float = 80.0):
    """The dyno's commands as TimeTable rows (time, value): the motor spins the inertia up
    from rest to ``w0`` with the brake released, then the pressure is held for 5.5 s (to
    standstill) and released; every change is a ramp over one sample, so that the log,
    sampled every DT, replays the commands exactly. Returns (pressure, motor, end time)."""
    pressure, torque, t = [[0.0, 0.0]], [[0.0, 0.0]], 0.2
    spin = round(w0 * J / motor / DT) * DT
    for _ in range(stops):
        torque += [[t, 0.0], [t + DT, motor], [t + DT + spin, motor], [t + 2 * DT + spin, 0.0]]
        t += 2 * DT + spin + 0.2
        pressure += [[t, 0.0], [t + DT, bar], [t + DT + 5.5, bar], [t + 2 * DT + 5.5, 0.0]]
        t += 2 * DT + 5.5 + 0.2
    return pressure, torque, round(t / DT) * DT


def rig(mu_pos: list, mu_T: list, stops: int = 5) -> st.Model:
    """The dyno with the brake of friction ``mu_pos`` times ``mu_T``, running ``stops`` stops."""
    pressure, torque, end = schedule(stops)
    m = st.Model("brake_dyno")
    m.add("J", st.Inertia(J=40.0, w=0.0))
    m.add("motor", st.Torque())
    m.add("motor_cmd", st.TimeTable(table=torque, extrapolation="HoldLastPoint"))
    m.add("press", st.TimeTable(table=pressure, extrapolation="HoldLastPoint"))
    brake = st.Brake(
        fn_max=255.0,  # N per bar: the pressure in bar is f_normalized
        cgeo=0.26,
        mu_pos=mu_pos,
        mu_T=mu_T,
        peak=1.1,
        useHeatPort=True,
        extrapolation="HoldLastPoint",
    )
    m.add("brake", brake)
    m.add("disc", st.HeatCapacitor(C=2500.0, T=293.15))
    m.add("cooling", st.ThermalConductor(G=20.0))
    m.add("ambient", st.FixedTemperature(T=293.15))
    m.connect("motor_cmd.y", "motor.tau")
    m.connect("motor.flange", "J.flange_a")
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.connect("brake.heatPort", "disc.port")
    m.connect("disc.port", "cooling.port_a")
    m.connect("cooling.port_b", "ambient.port")
    m.experiment.update(StopTime=end, Interval=DT, Tolerance=1e-8)
    return m


def measure(model: st.Model, noise: float = 0.005, seed: int = 1) -> pd.DataFrame:
    """The dyno's log of a run of ``model``: time, speed [rad/s] and temperature [K] with
    Gaussian noise of ``noise`` times their largest value, pressure [bar] and motor [N.m]."""
    r = model.simulate()
    on_grid = np.abs(r.time / DT - np.round(r.time / DT)) < 1e-6  # an event's rows are no samples
    on_grid &= np.concatenate([[True], np.diff(r.time) > 0])
    rng = np.random.default_rng(seed)
    log = {"time": r.time[on_grid]}
    for column, name in (("speed", "J.w"), ("temperature", "disc.T")):
        y = r[name][on_grid]
        log[column] = y + noise * np.max(np.abs(y)) * rng.standard_normal(len(y))
    log["pressure"] = r["press.y"][on_grid]
    log["motor"] = r["motor_cmd.y"][on_grid]
    return pd.DataFrame(log)


#: what is fitted: the three speed points and the fade factors above the 20 degC reference
PARAMS = {"brake.mu_pos[:, 2]": (0.05, 1.0), "brake.mu_T[2:end, 2]": (0.1, 1.5)}
OUTPUTS = {"J.w": "speed", "disc.T": "temperature"}
INPUTS = {"brake.f_normalized": "pressure", "motor.tau": "motor"}


def fit_map(data: pd.DataFrame, stops: int = 5, params: dict | None = None) -> st.FitResult:
    """The map fitted to ``data`` from a flat start (mu 0.35, every factor 0.8)."""
    start = rig(
        [[0.0, 0.35], [60.0, 0.35], [120.0, 0.35]],
        [[293.15, 1.0], [473.15, 0.8], [623.15, 0.8], [723.15, 0.8]],
        stops,
    )
    return st.fit(start, data, params or PARAMS, outputs=OUTPUTS, inputs=INPUTS, progress=False)


def main() -> st.FitResult:
    """Make the trace with the true map, fit it back, print the report."""
    data = measure(rig(TRUE_MU, TRUE_FADE))
    fit = fit_map(data)
    print(fit.report())
    return fit


if __name__ == "__main__":
    main()
