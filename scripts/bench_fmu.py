#!/usr/bin/env python3
"""Benchmark of issue 12's numbers (FMU export); prints them, asserts nothing.

In the C host of tests/fmi/harness.c (no Python in that process):
1. the braked flywheel (brake force a model input) in doSteps of 1 ms over 5 s, brake off
   (nothing happens) and brake on (braked to rest: a slip and a stick event);
2. CoupledClutches over its 1.5 s in doSteps of 0.5 ms, against the in-process run;
3. resident memory before and after 10 000 reset/initialize and 10 000 instantiate/free cycles.
Then FMPy's end-to-end time for the same runs (its own Python loop dominates), the cost of
saving and restoring an FMU state (a restore replays the run to the saved time) and the FMU
size.

Run: .venv/bin/python scripts/bench_fmu.py
"""

from __future__ import annotations

import subprocess
import tempfile
import time
from pathlib import Path

import fmpy
from fmpy.fmi2 import FMU2Slave

import stiction as st

ROOT = Path(__file__).resolve().parents[1]


def flywheel() -> st.Model:
    m = st.Model.load(ROOT / "examples" / "braked_flywheel.toml")
    del m.components["press"]
    m.connections = [c for c in m.connections if "press.y" not in c]
    return m.input("brake.f_normalized", start=0.0)


def harness(exe: Path, fmu: Path, out: str, stop: float, h: float, cycles: int, brake: str = "") -> dict:
    md = fmpy.read_model_description(fmu)
    unzipped = Path(fmpy.extract(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    args = [exe, unzipped, next((unzipped / "binaries").rglob("*.so")), md.guid, vr[out], stop, h, cycles]
    if brake:
        args += [vr["brake.f_normalized"], brake]
    run = subprocess.run([str(a) for a in args], check=True, capture_output=True, text=True)
    return {k: float(v) for k, v in (line.split() for line in run.stdout.splitlines())}


def main() -> None:
    tmp = Path(tempfile.mkdtemp())
    exe = tmp / "harness"
    subprocess.run(["cc", "-O2", "-o", exe, ROOT / "tests" / "fmi" / "harness.c", "-ldl"], check=True)
    fly = flywheel().to_fmu(tmp / "Flywheel.fmu")
    clutches = st.Model.load(ROOT / "examples" / "msl" / "CoupledClutches.toml")
    cc = clutches.to_fmu(tmp / "CoupledClutches.fmu")
    for label, brake in (("brake off", "0"), ("brake on", "1")):
        r = harness(exe, fly, "flywheel.w", 5.0, 0.001, 0, brake)
        print(f"flywheel, {label}: {r['seconds'] / r['steps'] * 1e6:.2f} µs per 1 ms doStep")
    r = harness(exe, cc, "J1.w", 1.5, 0.0005, 10_000)
    wall = min(clutches.simulate().stats["wall_ms"] for _ in range(5))
    print(f"CoupledClutches, 3000 doSteps of 0.5 ms: {r['seconds'] * 1e3:.2f} ms; in process: {wall:.2f} ms")
    print(
        f"10 000 resets + 10 000 instantiate/free: RSS {r['rss_before_kb']:.0f} → {r['rss_after_kb']:.0f} kB"
    )
    for fmu, stop, h in ((fly, 5.0, 0.001), (cc, 1.5, 0.0005)):
        t = time.perf_counter()
        fmpy.simulate_fmu(str(fmu), stop_time=stop, output_interval=h)
        print(f"FMPy end to end, {fmu.stem}: {time.perf_counter() - t:.2f} s")
    state_costs(cc)
    print(f"FMU size: {cc.stat().st_size / 1e3:.0f} kB (CoupledClutches, zipped)")


def state_costs(fmu: Path) -> None:
    """getFMUstate and setFMUstate (a replay from the start) of CoupledClutches, through FMPy."""
    md = fmpy.read_model_description(fmu)
    slave = FMU2Slave(
        guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.coSimulation.modelIdentifier
    )
    slave.instantiate()
    slave.setupExperiment(startTime=0.0, stopTime=1.5)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    t = 0.0
    for saved_at in (0.375, 0.75, 1.5):
        while t < saved_at - 1e-12:
            slave.doStep(t, 0.0005)
            t += 0.0005
        start = time.perf_counter()
        state = slave.getFMUstate()
        got = time.perf_counter() - start
        start = time.perf_counter()
        slave.setFMUstate(state)
        restored = time.perf_counter() - start
        print(
            f"CoupledClutches state at {saved_at} s: getFMUstate {got * 1e6:.0f} µs, "
            f"setFMUstate {restored * 1e3:.2f} ms (replays the run to {saved_at} s)"
        )
        slave.freeFMUstate(state)
    slave.terminate()
    slave.freeInstance()


if __name__ == "__main__":
    main()
