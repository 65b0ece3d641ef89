"""Generated drivetrains of any size, for benchmarks and tests (issue 10).

- :func:`chain_toml`: N+1 inertias joined by N clutches that engage one after another
  (``spacing`` seconds apart), the first driven by a constant torque. Simulated time, steps and
  events all grow with N.
- :func:`ladder_toml`: N inertias, neighbours joined alternately by a clutch and a
  spring-damper, a brake to the housing on every fourth inertia, a constant torque on the first;
  the clutches engage one after another within the first 0.5 s, the brakes close at 0.8 s,
  1.5 s simulated. Each clutch engages at its own instant by default, so its time events (N/2)
  and steps grow with N and its cost is at least quadratic; with ``waves`` the clutches engage
  in that many groups, one group after another, and its steps hardly grow with N.

Both return model-file text (``Model.loads`` reads it).
"""

from __future__ import annotations

import math

__all__ = ["chain_toml", "ladder_toml"]


def _toml(name: str, comps: list[str], conns: list[str], stop: float, interval: float) -> str:
    lines = [f'name = "{name}"', "connect = ["]
    lines += [f'  ["{a}", "{b}"],' for a, b in (c.split() for c in conns)]
    lines += ["]", "", "[experiment]", "StartTime = 0.0", f"StopTime = {stop!r}"]
    lines += [f"Interval = {interval!r}", "Tolerance = 1e-6", "", "[components]"]
    return "\n".join(lines + comps) + "\n"


def chain_toml(n: int, spacing: float = 0.05, interval: float | None = None) -> str:
    """J0 -clutch1- J1 -clutch2- … Jn; clutch k closes at ``spacing·k``."""
    stop = spacing * (n + 2)
    comps = [
        'J0 = { type = "Inertia", J = 1.0, phi = 0.0, w = 10.0 }',
        'drive = { type = "ConstantTorque", tau_constant = 1.0 }',
    ]
    conns = ["drive.flange J0.flange_a"]
    for k in range(1, n + 1):
        comps += [
            f'clutch{k} = {{ type = "Clutch", peak = 1.1, fn_max = 20.0 }}',
            f'J{k} = {{ type = "Inertia", J = 1.0, phi = 0.0, w = 0.0 }}',
            f'step{k} = {{ type = "Step", startTime = {spacing * k!r} }}',
        ]
        conns += [
            f"J{k - 1}.flange_b clutch{k}.flange_a",
            f"clutch{k}.flange_b J{k}.flange_a",
            f"step{k}.y clutch{k}.f_normalized",
        ]
    return _toml(f"Chain{n}", comps, conns, stop, interval or stop / 500)


def _engagement(t: float, waves: int | None) -> float:
    """``t``, or the end of the slot of ``0.5/waves`` s it falls in."""
    if waves is None:
        return t
    slot = min(waves, max(1, math.ceil(t * waves / 0.5 - 1e-9)))
    return 0.5 * slot / waves


def ladder_toml(n: int, interval: float = 1.5e-3, waves: int | None = None) -> str:
    """N inertias; links alternate clutch / spring-damper; a brake on every fourth inertia.

    Clutch k engages at ``0.5·k/(n-1)`` s; with ``waves``, at the end of the ``0.5/waves`` s
    slot that instant falls in (the same ``waves`` instants for any N)."""
    comps = [
        'drive = { type = "ConstantTorque", tau_constant = 10.0 }',
        'brakeStep = { type = "Step", startTime = 0.8 }',
    ]
    conns = ["drive.flange J0.flange_a"]
    links = max(n - 1, 1)
    for k in range(n):
        w = 10.0 if k == 0 else 0.0
        comps.append(f'J{k} = {{ type = "Inertia", J = 1.0, phi = 0.0, w = {w} }}')
        if k % 4 == 3:
            comps.append(f'brake{k} = {{ type = "Brake", fn_max = 50.0 }}')
            conns += [f"J{k}.flange_b brake{k}.flange_a", f"brakeStep.y brake{k}.f_normalized"]
        if k == 0:
            continue
        if k % 2 == 1:
            t_on = _engagement(0.5 * k / links, waves)
            comps.append(f'clutch{k} = {{ type = "Clutch", peak = 1.1, fn_max = 20.0 }}')
            comps.append(f'step{k} = {{ type = "Step", startTime = {t_on!r} }}')
            conns += [
                f"J{k - 1}.flange_b clutch{k}.flange_a",
                f"clutch{k}.flange_b J{k}.flange_a",
                f"step{k}.y clutch{k}.f_normalized",
            ]
        else:
            comps.append(f'sd{k} = {{ type = "SpringDamper", c = 1000.0, d = 10.0 }}')
            conns += [f"J{k - 1}.flange_b sd{k}.flange_a", f"sd{k}.flange_b J{k}.flange_a"]
    return _toml(f"Ladder{n}", comps, conns, 1.5, interval)
