"""A pause within round-off of a time event works (issue 29): advancing in steps of
``t += 0.01`` reaches 0.09999999999999999, a hair before a Ramp's start at 0.1, and a
parameter or input set there raised ``IntegratorError … Stop time is at the current state
time``. Such a pause is taken at the time event, the event handled, as a pause exactly there
is; the run is the same as one that paused at 0.1."""

from __future__ import annotations

import numpy as np

import stiction as st


def _ramped() -> st.Model:
    m = st.Model("ramp_pause")
    m.add("J", st.Inertia(J=1.0, phi=0.0, w=10.0))
    m.add("brake", st.Brake(fn_max=5.0))
    m.add("press", st.Ramp(height=1.0, duration=0.2, startTime=0.1))
    m.connect("J.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    return m


def _stepped(times: list[float]) -> st.Result:
    sim = _ramped().simulation(StopTime=0.5)
    for t in times:
        sim.advance_to(t)
        sim.set_parameter("brake.fn_max", 5.0 + round(t, 6))
    sim.run()
    return sim.result()


def test_setting_a_parameter_a_hair_before_a_time_event_works() -> None:
    t, times = 0.0, []
    while t < 0.3:
        t += 0.01
        times.append(t)
    assert 0.09999999999999999 in times  # the case
    r = _stepped(times)
    exact = _stepped([0.1 if t == 0.09999999999999999 else t for t in times])  # paused at 0.1
    assert np.array_equal(r.time, exact.time)
    assert np.array_equal(r["J.w"], exact["J.w"])


def test_the_pause_lands_on_the_time_event_and_at_stop_time() -> None:
    sim = _ramped().simulation(StopTime=0.5)
    sim.advance_to(0.09999999999999999)
    assert sim.time == 0.1  # the time event, handled
    sim.set_parameter("brake.fn_max", 6.0)
    sim.advance_to(0.49999999999999994)  # a hair before StopTime: the end
    sim.set_parameter("brake.fn_max", 7.0)
    r = sim.result()
    assert r.time[-1] == 0.5
