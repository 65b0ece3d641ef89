"""Trust under long runs and bad starts: chattering is told from many legitimate events, user
limits stop a run and say so, and a start the element's own logic forbids is refused."""

from __future__ import annotations

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

MSL = MSL_EXAMPLES


@pytest.mark.slow
def test_a_long_run_with_many_legitimate_events_completes_and_events_grow_linearly():
    model = st.Model.load(MSL / "CoupledClutches.toml")
    r = model.simulate(StopTime=20_000.0, Interval=1.0)
    times = np.array([e.time for e in r.events])
    assert r.time[-1] == 20_000.0
    assert len(times) > 50_000  # more than the old total cap, about four per second
    halves = (times < 10_000).sum(), (times >= 10_000).sum()
    assert abs(halves[0] - halves[1]) < 0.01 * len(times), halves


def test_user_limits_stop_the_run_and_say_which():
    model = st.Model.load(MSL / "CoupledClutches.toml")
    with pytest.raises(st.LimitExceededError, match="max_events = 5"):
        model.simulate(params={"max_events": 5})
    with pytest.raises(st.LimitExceededError, match="max_steps = 10"):
        model.simulate(params={"max_steps": 10})
    with pytest.raises(st.LimitExceededError, match="timeout"):
        model.simulate(StopTime=5000.0, Interval=1.0, params={"timeout": 0.05})
    with pytest.raises(st.ModelError, match="max_events must be a positive whole number"):
        model.simulate(params={"max_events": 2.5})


def test_a_one_way_clutch_started_backward_is_refused_before_the_run():
    text = (MSL / "OneWayClutch.toml").read_text()
    backward = text.replace(
        'inertiaOut = { type = "Inertia", J = 1.0, phi = 0.0, w = 0.0 }',
        'inertiaOut = { type = "Inertia", J = 1.0, phi = 0.0, w = -2.0 }',
    )
    assert backward != text
    model = st.Model.loads(backward)
    for run in (model.check, model.simulate):
        with pytest.raises(st.ModelError, match=r"oneWayClutch.*w_rel starts at -1\.5"):
            run()
    st.Model.loads(text).check()  # the example's own start is fine


@pytest.fixture
def ctrl_c_acts():
    """Ctrl-C raises KeyboardInterrupt here even when the test process was started with SIGINT
    ignored (as a background job is, e.g. under nohup), which Python would otherwise keep."""
    import signal

    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def test_ctrl_c_interrupts_a_long_run_promptly(ctrl_c_acts):
    import _thread
    import threading
    import time

    model = st.Model.load(MSL / "CoupledClutches.toml")
    model.simulate()  # the first run's imports happen before the interrupt, not during it
    timer = threading.Timer(0.3, _thread.interrupt_main)
    started = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        model.simulate(StopTime=20_000.0, Interval=1.0)  # about 6 s uninterrupted
    latency = time.perf_counter() - started - 0.3
    timer.cancel()
    assert latency < 1.0, f"stopped {latency:.3f} s after the signal"


def test_ctrl_c_interrupts_a_sweep_inside_its_runs(ctrl_c_acts):
    """The signal reaches the runs under way (each about 6 s long), not only the gaps
    between batches."""
    import _thread
    import threading
    import time

    model = st.Model.load(MSL / "CoupledClutches.toml")
    # a short sweep first: the interrupt must land in the runs, not in the first import of
    # pandas a sweep makes (a module half imported stays broken for the rest of the process)
    st.sweep(model, {"clutch1.fn_max": [10.0, 20.0]}, ["max(J1.w)"], workers=2, progress=False)
    variants = {"clutch1.fn_max": [10.0, 20.0, 30.0, 40.0], "StopTime": [20_000.0] * 4, "Interval": [1.0] * 4}
    timer = threading.Timer(0.3, _thread.interrupt_main)
    started = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        st.sweep(model, variants, ["max(J1.w)"], workers=2, progress=False)
    latency = time.perf_counter() - started - 0.3
    timer.cancel()
    assert latency < 1.0, f"stopped {latency:.3f} s after the signal"


@pytest.mark.slow
def test_ctrl_c_stops_the_command_line_with_status_130_and_no_result_file(tmp_path, ctrl_c_acts):
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "long.csv"
    cmd = [sys.executable, "-m", "stiction", "simulate", str(MSL / "CoupledClutches.toml")]
    cmd += ["--StopTime", "20000", "--Interval", "1", "-o", str(out)]
    # a child inherits an ignored SIGINT: the fixture above makes it the default again first
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=os.environ.copy())
    time.sleep(2.0)  # the interpreter starts, the run is under way (about 6 s in all)
    sent = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=30)
    latency = time.perf_counter() - sent
    assert proc.returncode == 130, err.decode()
    assert latency < 2.0, latency
    assert not out.exists() and not list(tmp_path.iterdir())


@pytest.mark.parametrize("start_time", [3e-69, 1e-12])
def test_a_switch_a_hair_after_the_start_acts_from_the_start(start_time):
    """A Step at 1e-12 s is merged into the start (no event that close to it): its new value
    holds from t = 0, so the released clutch never drives J3 (before: it drove J3 for the whole
    first integrator step, 1.7e-4 s, found by the property tests)."""
    m = st.Model("release")
    m.add("J0", st.Inertia(J=1.0, phi=0.0, w=1.0))
    m.add("J3", st.Inertia(J=1.0, phi={"start": 0.0, "fixed": True}, w=0.0))
    m.add("c3", st.Clutch(fn_max=1.0))
    m.add("f3", st.Step(height=-1.0, offset=1.0, startTime=start_time))
    m.connect("J0.flange_b", "c3.flange_a")
    m.connect("c3.flange_b", "J3.flange_a")
    m.connect("f3.y", "c3.f_normalized")
    m.experiment.update(StopTime=0.1, Interval=1e-3)
    r = m.simulate()
    assert r["f3.y"][0] == 0.0 and r["c3.free"][0] == 1.0
    assert np.all(r["J3.w"] == 0.0) and np.all(r["J0.w"] == 1.0)


def test_a_switch_a_hair_before_the_stop_time_does_not_act_early():
    """Found by the property tests: a Step at StopTime - 1e-16 is merged into StopTime (no
    event of its own). It released a locked brake in a state event 1e-10 s before it, with
    the brake's left row already showing no static limit; now nothing happens before the end."""
    text = """
name = "ReleasedAtTheEnd"
connect = [["drive.flange", "J.flange_a"], ["J.flange_b", "brake.flange_a"], ["press.y", "brake.f_normalized"]]
[experiment]
StopTime = 1.0
[components]
J = { type = "Inertia", J = 1.0, w = { start = 0.0, fixed = true } }
drive = { type = "ConstantTorque", tau_constant = 1.0 }
brake = { type = "Brake", fn_max = 10.0 }
press = { type = "Step", height = -1.0, offset = 1.0, startTime = 0.9999999999999999 }
"""
    r = st.Model.loads(text).simulate()
    assert [e.cause for e in r.events if e.cause != "initialization"] == []
    assert (r["brake.locked"] == 1.0).all() and (r["brake.tau0_max"] > 0).all()
