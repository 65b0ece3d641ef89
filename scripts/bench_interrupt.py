#!/usr/bin/env python3
"""Ctrl-C latency (issue 13): how long after the signal a run, a sweep and the command line
stop. Each case starts a run of seconds (CoupledClutches over 20 000 s; the model compiled by a
short run first, so the signal finds the engine running), interrupts it after `DELAY`, and
measures from the moment the signal was sent to the moment the interrupt
surfaced (`KeyboardInterrupt` or `SimulationCancelled` caught, the CLI process gone). Prints
min / median / max over the trials; the goal is 0.2 s. Asserts nothing.

Run: .venv/bin/python scripts/bench_interrupt.py [--trials N]
"""

from __future__ import annotations

import _thread
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

import stiction as st

MODEL = Path(__file__).resolve().parent.parent / "examples" / "msl" / "CoupledClutches.toml"
LONG = {"StopTime": 20_000.0, "Interval": 1.0}  # about 6 s uninterrupted
DELAY = 0.5


def _interrupted(start: Callable[[], None], send: Callable[[], None], caught: type[BaseException]) -> float:
    """Seconds from `send` (called on a timer thread after DELAY) to `caught` leaving `start`."""
    sent: list[float] = []

    def fire() -> None:
        sent.append(time.perf_counter())
        send()

    timer = threading.Timer(DELAY, fire)
    timer.start()
    try:
        start()
    except caught:
        return time.perf_counter() - sent[0]
    finally:
        timer.cancel()
    raise RuntimeError("the run ended before the signal")


def run_latency(model: st.Model) -> float:
    return _interrupted(lambda: model.simulate(**LONG), _thread.interrupt_main, KeyboardInterrupt)


def sweep_latency(model: st.Model) -> float:
    variants = {"clutch1.fn_max": [10.0, 20.0, 30.0, 40.0], **{k: [v] * 4 for k, v in LONG.items()}}
    return _interrupted(
        lambda: st.sweep(model, variants, ["max(J1.w)"], workers=2, progress=False),
        _thread.interrupt_main,
        KeyboardInterrupt,
    )


def cancel_latency(model: st.Model) -> float:
    sim = st.Simulation(model, **LONG)
    handle = sim.cancel_handle()
    return _interrupted(sim.run, handle.cancel, st.SimulationCancelled)


def cli_latency() -> float:
    """The CLI writing a CSV: SIGINT once it runs; it must exit 130 and leave no file."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "long.csv"
        cmd = [sys.executable, "-m", "stiction", "simulate", str(MODEL), "-o", str(out)]
        cmd += ["--StopTime", "20000", "--Interval", "1"]
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        time.sleep(3.0)  # the interpreter has started and the run is under way
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=60)
        latency = time.perf_counter() - sent
        if proc.returncode != 130 or any(Path(tmp).iterdir()):
            raise RuntimeError(f"exit {proc.returncode}, left {list(Path(tmp).iterdir())}")
        return latency


def main() -> None:
    trials = int(sys.argv[sys.argv.index("--trials") + 1]) if "--trials" in sys.argv else 5
    model = st.Model.load(MODEL)
    model.simulate()  # compiled once, as every case after it reuses
    st.sweep(model, {"clutch1.fn_max": [10.0]}, ["max(J1.w)"], progress=False)
    cases = {
        "Model.simulate, Ctrl-C": lambda: run_latency(model),
        "Simulation.cancel() from a thread": lambda: cancel_latency(model),
        "sweep (2 workers), Ctrl-C": lambda: sweep_latency(model),
        "stiction simulate -o (SIGINT)": cli_latency,
    }
    print(f"load average {os.getloadavg()[0]:.1f}; {trials} trials each; goal 0.2 s")
    print(f"{'case':<36} {'min ms':>8} {'median ms':>10} {'max ms':>8}")
    for name, case in cases.items():
        ms = [1e3 * case() for _ in range(trials)]
        print(f"{name:<36} {min(ms):>8.1f} {statistics.median(ms):>10.1f} {max(ms):>8.1f}")
    signal.signal(signal.SIGINT, signal.default_int_handler)


if __name__ == "__main__":
    main()
