"""A vehicle launch: engine, clutch, gearbox, drive shaft, wheel with a brake and road load.

The tutorial (docs/tutorial.md) builds this model step by step; the documentation build runs
this file, so the tutorial cannot go stale. Run it with ``python examples/vehicle_launch.py``.
"""

from __future__ import annotations

import stiction as st


def build() -> st.Model:
    """The drivetrain, engine to road."""
    m = st.Model("vehicle_launch")
    # Engine: 0.2 kg·m² idling at 150 rad/s (about 1430 rpm); 150 N·m until the driver lifts
    # off at 2.5 s (the throttle steps to 0).
    m.add("engine", st.Inertia(J=0.2, w=150.0))
    m.add("torque", st.Torque())
    m.add("throttle", st.Step(offset=150.0, height=-150.0, startTime=2.5))
    m.connect("throttle.y", "torque.tau")
    m.connect("torque.flange", "engine.flange_a")
    # Clutch: pressed closed by a ramp from 0.1 s to 0.6 s; 400 N·m at full force.
    m.add("clutch", st.Clutch(fn_max=4000.0, mu_pos=[[0.0, 0.4]], cgeo=0.25, peak=1.1))
    m.add("pedal", st.Ramp(height=1.0, duration=0.5, startTime=0.1))
    m.connect("engine.flange_b", "clutch.flange_a")
    m.connect("pedal.y", "clutch.f_normalized")
    # Gearbox in first gear (ratio 3.5 × final drive 4.0) with its input inertia.
    m.add("gearbox_in", st.Inertia(J=0.02))
    m.add("gearbox", st.IdealGear(ratio=14.0))
    m.connect("clutch.flange_b", "gearbox_in.flange_a")
    m.connect("gearbox_in.flange_b", "gearbox.flange_a")
    # Drive shaft: torsionally compliant and damped; at rest relative to the wheel at the start.
    m.add("shaft", st.SpringDamper(c=8000.0, d=40.0, w_rel=0.0))  # not twisting at the start
    m.connect("gearbox.flange_b", "shaft.flange_a")
    # Wheel with the vehicle's mass: 1500 kg at a 0.3 m rolling radius is m·r² = 135 kg·m².
    # The vehicle starts at rest: w = 0 is fixed (a bare number), so the clutch starts slipping.
    m.add("wheel", st.Inertia(J=135.0, w=0.0))
    m.connect("shaft.flange_b", "wheel.flange_a")
    # Wheel brake, pressed fully at 2.5 s, and the aerodynamic road load.
    m.add("brake", st.Brake(fn_max=60000.0, mu_pos=[[0.0, 0.35]], cgeo=0.12))
    m.add("brake_pedal", st.Step(height=1.0, startTime=2.5))
    m.connect("wheel.flange_b", "brake.flange_a")
    m.connect("brake_pedal.y", "brake.f_normalized")
    m.add(
        "drag", st.QuadraticSpeedDependentTorque(tau_nominal=-300.0, w_nominal=100.0, TorqueDirection=False)
    )
    m.connect("drag.flange", "brake.flange_b")
    m.experiment.update(StopTime=5.0, Interval=1e-3)
    return m


def main() -> st.Result:
    """Run the launch and report when the clutch and the brake lock and what they dissipated."""
    r = build().simulate()
    print(r.summary())
    for event in r.events:
        print(event)
    print(f"clutch locks at t = {r.first('clutch.locked'):.3f} s, the brake at {r.lock_times('brake')}")
    print(f"dissipated: clutch {r.energy('clutch') / 1e3:.1f} kJ, brake {r.energy('brake') / 1e3:.1f} kJ")
    return r


if __name__ == "__main__":
    main()
