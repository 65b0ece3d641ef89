"""A quarter car braking from 100 km/h: stopping distance, time, MFDD, disc temperature.

The twin of examples/vehicle_stop.toml, built in Python: one wheel with its disc brake (its
heat port into the disc's heat capacity), the tyre as a ``SlipWheel`` (stiction's own tyre
contact: it rolls while its contact sticks and would skid if the brake locked it), 400 kg of
car as a ``Translational.Mass``, rolling resistance (``Translational.RollingResistance``: it
vanishes at rest) and aerodynamic drag. The brake pressure
ramps to full in 0.3 s. Run it with ``python examples/vehicle_stop.py``; the documentation
build runs it into the gallery.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import stiction as st

V0 = 100.0 / 3.6  # [m/s]
R = 0.3  # wheel radius [m]
M = 400.0  # the car's share [kg]
J = 1.2  # wheel, hub and disc [kg.m2]
G = 9.81


def build() -> st.Model:
    """The quarter car, pedal to road (the same model as vehicle_stop.toml)."""
    tr = st.translational
    m = st.Model("vehicle_stop")
    m.add("pedal", st.Ramp(height=1.0, duration=0.3, startTime=0.1))
    # disc brake: pads with mu 0.4 at an effective radius of 0.12 m, 20 kN clamp: 960 N.m
    m.add("brake", st.Brake(fn_max=20000.0, cgeo=0.12, mu_pos=[[0.0, 0.4]], useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=2760.0, T="20 degC"))  # 6 kg of cast iron
    m.add("cooling", st.ThermalConductor(G=5.0))
    m.add("ambient", st.FixedTemperature(T="20 degC"))
    m.add("wheel", st.Inertia(J=J, w=V0 / R))
    m.add("tyre", st.SlipWheel(radius=R, mu_pos=[[0.0, 0.9]], peak=1.1, fNConstant=M * G))
    m.add("car", tr.Mass(m=M, s=0.0, v="100 km/h"))
    # rolling resistance 0.012·m·g against the motion, vanishing at rest (MSL's regularization)
    m.add("rolling", tr.RollingResistance(fWeight=M * G, CrConstant=0.012))
    # ½·rho·cw·A·v² with rho = 1.2 kg/m3, cw·A = 0.66 m2, a quarter of it on this wheel
    drag = -0.5 * 1.2 * 0.66 / 4 * V0**2
    m.add("drag", tr.QuadraticSpeedDependentForce(f_nominal=drag, v_nominal=V0, ForceDirection=False))
    for a, b in [
        ("pedal.y", "brake.f_normalized"),
        ("brake.flange_b", "wheel.flange_a"),
        ("brake.heatPort", "disc.port"),
        ("disc.port", "cooling.port_a"),
        ("cooling.port_b", "ambient.port"),
        ("wheel.flange_b", "tyre.flangeR"),
        ("tyre.flangeT", "car.flange_a"),
        ("car.flange_b", "rolling.flange"),
        ("car.flange_b", "drag.flange"),
    ]:
        m.connect(a, b)
    m.experiment.update(StopTime=6.0, Interval=1e-3)
    return m


@dataclass(frozen=True)
class Stop:
    """What a brake test reports."""

    distance: float  # [m] from the pedal's first touch (t = 0 here, v = v0) to rest
    time: float  # [s] to rest
    mfdd: float  # [m/s2] mean fully developed deceleration (ECE R13)
    peak_disc_temperature: float  # [K]
    brake_energy: float  # [J]


def mfdd(t: np.ndarray, v: np.ndarray, s: np.ndarray, v0: float) -> float:
    """ECE R13's mean fully developed deceleration: (v_b² − v_e²)/(2·(s_e − s_b)) between
    v_b = 0.8·v0 and v_e = 0.1·v0 (the speed falling; s at those speeds interpolated)."""
    falling = np.flatnonzero(np.diff(t) > 0)  # the rows of a monotonic time (event rows twice)
    t, v, s = t[falling], v[falling], s[falling]
    vb, ve = 0.8 * v0, 0.1 * v0
    sb, se = (float(np.interp(-x, -v, s)) for x in (vb, ve))  # v decreasing: interpolate in −v
    return (vb**2 - ve**2) / (2.0 * (se - sb))


def report(r: st.Result) -> Stop:
    """The brake test's numbers from a result."""
    t_stop = r.first("brake.locked")  # the wheel stops, the car with it (the tyre rolls)
    assert t_stop is not None, "the car does not stop"
    return Stop(
        distance=float(np.interp(t_stop, r.time, r["car.s"])),
        time=t_stop,
        mfdd=mfdd(r.time, r["car.v"], r["car.s"], V0),
        peak_disc_temperature=float(np.max(r["disc.T"])),
        brake_energy=r.energy("brake"),
    )


def main() -> st.Result:
    """Brake from 100 km/h; print the report; plot speed and distance."""
    r = build().simulate()
    stop = report(r)
    print(f"stopping distance  {stop.distance:.2f} m")
    print(f"stopping time      {stop.time:.3f} s")
    print(f"MFDD               {stop.mfdd:.3f} m/s2")
    print(f"peak disc temp.    {stop.peak_disc_temperature - 273.15:.1f} degC")
    print(f"brake energy       {stop.brake_energy / 1e3:.1f} kJ")
    print(f"tyre locked        {'never' if r['tyre.locked'].min() > 0.5 else 'yes'}")
    return r


if __name__ == "__main__":
    result = main()
    result.plot("car.v", "car.s", "disc.T", path="vehicle_stop.png")
