#!/usr/bin/env python3
"""Benchmark of issue 11's numbers; prints them, asserts nothing.

1. Importing a generated 1500-component ``.mo`` model (a chain of inertias, clutches and their
   force signals, MSL style with placement annotations).
2. A 100-clutch chain: simulate, then write every variable to CSV, .mat and Parquet; also
   the old per-cell Python CSV writer for comparison, and ``stiction simulate -o`` end to end.

Run: .venv/bin/python scripts/bench_modelica_io.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import stiction as st
from stiction.results.io import csv as csvio


def chain_mo(clutches: int, name: str = "Chain") -> str:
    """An MSL-style model: J0 -clutch1- J1 -clutch2- … each clutch pressed by a Step."""
    lines = [f"model {name}", "  import Modelica.Mechanics.Rotational.Components;"]
    place = " annotation (Placement(transformation(extent={{-10,-10},{10,10}})))"
    lines.append(f"  Components.Inertia J0(J=1, phi(fixed=true, start=0), w(fixed=true, start=10)){place};")
    lines.append(f"  Modelica.Mechanics.Rotational.Sources.ConstantTorque drive(tau_constant=1){place};")
    conns = ["  connect(drive.flange, J0.flange_a);"]
    for k in range(1, clutches + 1):
        lines.append(f"  Components.Clutch clutch{k}(peak=1.1, fn_max=20){place};")
        lines.append(
            f"  Components.Inertia J{k}(J=1, phi(fixed=true, start=0), w(fixed=true, start=0)){place};"
        )
        lines.append(f"  Modelica.Blocks.Sources.Step step{k}(startTime={0.001 * k}){place};")
        conns += [
            f"  connect(J{k - 1}.flange_b, clutch{k}.flange_a) annotation (Line(points={{{{0,0}},{{1,0}}}}));",
            f"  connect(clutch{k}.flange_b, J{k}.flange_a);",
            f"  connect(step{k}.y, clutch{k}.f_normalized);",
        ]
    return (
        "\n".join(
            [
                *lines,
                "equation",
                *conns,
                "  annotation(experiment(StopTime=1, Interval=1e-3));",
                f"end {name};",
            ]
        )
        + "\n"
    )


def timed(func, repeat: int = 3) -> float:
    """Best wall time of ``repeat`` runs."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - t0)
    return best


def cpu(func, repeat: int = 5) -> float:
    """Best CPU time of this process (less disturbed than wall time on a shared machine)."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        func()
        best = min(best, time.process_time() - t0)
    return best


def main() -> None:
    big = chain_mo(500)  # 2 + 3·500 = 1502 components
    model = st.Model.from_modelica(big)
    print(
        f"import {len(model.components)}-component .mo ({len(big) // 1024} KiB): "
        f"{timed(lambda: st.Model.from_modelica(big)) * 1e3:.0f} ms wall, "
        f"{cpu(lambda: st.Model.from_modelica(big)) * 1e3:.0f} ms CPU"
    )
    chain = st.Model.from_modelica(chain_mo(100))
    t0 = time.perf_counter()
    r = chain.simulate()
    sim = time.perf_counter() - t0
    t0 = time.perf_counter()
    data = r.data
    table = time.perf_counter() - t0
    print(
        f"100-clutch chain: {len(r)} rows × {len(r.names)} variables = {data.size / 1e6:.1f} M values; "
        f"simulate {sim * 1e3:.0f} ms, all variables {table * 1e3:.0f} ms"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for ext in (".csv", ".mat", ".parquet"):
            path = Path(tmp) / f"r{ext}"
            seconds = timed(lambda path=path: r.save(path))
            print(f"  write {ext:<8} {seconds * 1e3:7.0f} ms  {path.stat().st_size / 1e6:6.1f} MB")
        old = timed(lambda: csvio.write_csv(Path(tmp) / "old.csv", r.names, data), repeat=1)
        print(f"  old Python per-cell CSV writer: {old * 1e3:.0f} ms")
        big_mo = Path(tmp) / "Big.mo"
        big_mo.write_text(big)
        convert = [sys.executable, "-m", "stiction", "import", str(big_mo), "-o", str(Path(tmp) / "big.toml")]
        print(f"  stiction import Big.mo -o big.toml (fresh process, best of 3): {_process(convert):.2f} s")
        mo = Path(tmp) / "Chain.mo"
        mo.write_text(chain_mo(100))
        cli = [sys.executable, "-m", "stiction", "simulate", str(mo), "-o"]
        for ext in (".csv", ".parquet"):
            seconds = _process([*cli, str(Path(tmp) / f"cli{ext}")])
            print(f"  stiction simulate Chain.mo -o result{ext} (end to end, best of 3): {seconds:.2f} s")
    bare = _process([sys.executable, "-c", "pass"])
    loaded = _process([sys.executable, "-c", "import stiction"])
    print(
        f"import stiction: {(loaded - bare) * 1e3:.0f} ms beyond the interpreter's start ({bare * 1e3:.0f} ms)"
    )


def _process(command: list[str], repeat: int = 3) -> float:
    """Best wall time of a fresh process, bytecode cached as an installed package has it (this
    sandbox sets PYTHONDONTWRITEBYTECODE, which would recompile every module on every start)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    subprocess.run(command, check=True, capture_output=True, env=env)  # writes the bytecode
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True, env=env)
        best = min(best, time.perf_counter() - t0)
    return best


if __name__ == "__main__":
    main()
