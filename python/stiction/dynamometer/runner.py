"""Running a schedule: one ``Simulation`` of the rigged model, advanced and re-driven stop by
stop, its thermal (and wear) state carried from each stop to the next.

A stop: the brake released (``f_normalized = 0``); the inertia set to the stop's initial speed
(``Simulation.reinit``: the dyno's motor spins it up in no time, its energy counted as work
supplied); cooling at that speed, brake released, until the brake temperature falls to the IBT
(``advance_until``: the exact instant) or for the fixed interval; then the pressure applied at
one event and held, the run advanced to the exact instants the speed passes 10 %, 15 %, … 80 %
of the speed drop (samples) and reaches the final speed (a stop to standstill ends at the
brake's stick event). A target deceleration is held by a sampled controller (control.py),
starting from the clamp force ``J·alpha/(mu·cgeo)`` with the previous stop's mean mu
(``mu_nominal`` for the first). A drag: the inertia at the speed, coupled (a Clutch, locked) to
the dyno's motor (a Speed source following a Constant exactly) that holds it while the
pressure is held for the duration; the samples are at 10 %, 15 %, … 80 % of the duration.
"""

from __future__ import annotations

import math
import time
from typing import Any

from stiction import _deps
from stiction.dynamometer.control import CONTROL_COLUMNS, controlled_stop, controller_limit
from stiction.dynamometer.rig import DYNO_COUPLING, DYNO_SPEED, ZERO_C, Rigged
from stiction.dynamometer.schedule import LEVELS, Schedule, ScheduleError, Section
from stiction.errors import WearLimitError
from stiction.run.simulation import Simulation

__all__ = ["run_schedule"]


class _Run:
    """The state of one schedule's run: the simulation, the rig's names, the clocks."""

    def __init__(self, rigged: Rigged, schedule: Schedule) -> None:
        self.r, self.schedule, self.rig = rigged, schedule, schedule.rig
        # StopTime: the longest the schedule can take (chatter is judged against the span); a
        # drag lasts its duration, which may be longer than a stop may
        horizon = 1.0 + sum(
            s.repeat
            * (
                max(self.rig.max_stop, s.duration or 0.0)
                + (s.interval or 0.0)
                + (self.rig.max_cooling if s.IBT is not None else 0.0)
            )
            for s in schedule.sections
        )
        self.sim: Simulation = rigged.model.simulation(StopTime=horizon, Interval=horizon)
        self.sim.set_recording(False)
        names = set(self.sim.values())
        for name in (rigged.temperature, f"{self.rig.brake}.tau", f"{self.rig.brake}.fn"):
            if name not in names:
                raise ScheduleError(
                    f"{schedule.source}: [dyno] (line {self.rig.line}): the run has no variable '{name}'"
                    + (
                        " (set temperature = the brake temperature variable)"
                        if name == rigged.temperature
                        else ""
                    )
                )
        # the brake's own wear state (docs/wear.md), when it keeps one: the report's wear column
        wear, thickness = f"{self.rig.brake}.wearVolume", f"{self.rig.brake}.thickness"
        self.wear = wear if wear in names else None
        self.thickness = thickness if thickness in names else None
        self.T, self.w, self.phi = rigged.temperature, f"{rigged.inertia}.w", f"{rigged.inertia}.phi"
        self.ambient = [self.sim.get(f"{a}.port.T") for a in rigged.ambients]
        self.clock = {"stops": 0.0, "cooling": 0.0}
        self.mu_last = self.rig.mu_nominal
        self.samples: list[dict[str, Any]] = []

    def check_cooling(self) -> None:
        """An IBT the model cannot cool to is refused before the run: no ambient to cool to, or
        an IBT at or below the coldest ambient."""
        for s in self.schedule.sections:
            if s.IBT is None:
                continue
            at = f"{self.schedule.source}: {s.where('IBT')}"
            if not self.ambient:
                raise ScheduleError(
                    f"{at}: IBT = {s.IBT} °C cannot be reached: the model has no cooling path "
                    "(no FixedTemperature ambient for the brake's heat to flow to)"
                )
            if s.IBT + ZERO_C <= min(self.ambient):
                raise ScheduleError(
                    f"{at}: IBT = {s.IBT} °C cannot be reached: it is not above the ambient "
                    f"({min(self.ambient) - ZERO_C:g} °C)"
                )

    def cool(self, s: Section) -> float:
        """Cooling before a stop, at the stop's speed with the brake released; its length [s]."""
        started, t0 = time.perf_counter(), self.sim.time
        if s.IBT is not None and self.sim.get(self.T) > s.IBT + ZERO_C:
            if not self.sim.advance_until(self.T, s.IBT + ZERO_C, t0 + self.rig.max_cooling):
                raise ScheduleError(
                    f"{self.schedule.source}: {s.where('IBT')}: the brake did not cool to IBT = "
                    f"{s.IBT} °C within max_cooling = {self.rig.max_cooling:g} s "
                    f"(it is at {self.sim.get(self.T) - ZERO_C:.1f} °C)"
                )
        elif s.interval:
            self.sim.advance_to(t0 + s.interval)
        self.clock["cooling"] += time.perf_counter() - started
        return self.sim.time - t0

    def clamp(self, s: Section, k: int) -> float:
        """The clamp force of stop ``k`` [N]: from the pressure, or for a target deceleration
        the controller's start, from the previous stop's mean mu (feed-forward), clipped to its
        limit."""
        if s.pressure is not None:
            return s.pressure[k] * float(self.rig.fn_per_bar or 0.0)
        alpha = self.rig.to_rad_s2(float(s.decel or 0.0))
        return min(self.r.J * alpha / (self.mu_last * self.r.cgeo), controller_limit(self.r, self.rig))

    def mu_now(self) -> float:
        """The friction coefficient as a dyno measures it: torque / (cgeo · clamp force)."""
        fn = self.sim.get(f"{self.rig.brake}.fn")
        return abs(self.sim.get(f"{self.rig.brake}.tau")) / (self.r.cgeo * fn) if fn > 0 else math.nan

    def reach(self, s: Section, w: float, t_max: float) -> None:
        if not self.sim.advance_until(self.w, w, t_max):
            raise ScheduleError(
                f"{self.schedule.source}: {s.where()}: the stop did not slow to {w:g} rad/s within "
                f"max_stop = {self.rig.max_stop:g} s (too little pressure?)"
            )

    def sample(self, s: Section, index: int, q: float) -> tuple[float, float]:
        """mu and temperature now, kept as the sample at fraction ``q`` of the stop."""
        mu, T = self.mu_now(), self.sim.get(self.T)
        self.samples.append(
            {
                "index": index,
                "section": s.name,
                "fraction": q,
                "w": self.sim.get(self.w),
                "mu": mu,
                "T": T - ZERO_C,
            }
        )
        return mu, T

    def press(self, s: Section, k: int, w0: float) -> tuple[float, float, float, float]:
        """Release, spin up to ``w0``, cool, (for a drag: couple the motor), press: the clamp
        force, the cooling time, the start's temperature and wear."""
        sim, r = self.sim, self.r
        sim.set_input(r.pressure_input, 0.0)
        if r.motor:
            sim.set_input(f"{DYNO_COUPLING}.f_normalized", 0.0)
            sim.set_parameter(f"{DYNO_SPEED}.k", w0)  # the motor runs at the stop's speed
        sim.reinit(self.w, w0)
        cooling = self.cool(s)
        if s.kind == "drags":  # coupled at equal speeds: the coupling locks at once
            sim.set_input(f"{DYNO_COUPLING}.f_normalized", 1.0)
        fn = self.clamp(s, k)
        T0, wear0 = sim.get(self.T), sim.get(self.wear) if self.wear else 0.0
        sim.set_input(r.pressure_input, fn / r.fn_max)
        return fn, cooling, T0, wear0

    def stop(self, s: Section, k: int, index: int) -> dict[str, Any]:
        """One stop (or drag) and its row of the report."""
        rig, sim = self.rig, self.sim
        w0, w1 = rig.to_rad_s(s.v_initial), rig.to_rad_s(s.v_final)
        fn, cooling, T0, wear0 = self.press(s, k, w0)
        if s.decel is not None and s.kind == "stops":
            return self.controlled(s, k, index, (w0, w1), (fn, cooling, T0, wear0))
        started, t0 = time.perf_counter(), sim.time
        mus, peak, window = [], T0, {}
        lost0 = sim.get("system.dissipatedEnergy")
        for q in LEVELS:
            if s.kind == "drags":
                sim.advance_to(t0 + q * (s.duration or 0.0))
            else:
                self.reach(s, w0 - q * (w0 - w1), t0 + rig.max_stop)
            mu, T = self.sample(s, index, q)
            mus.append(mu)
            peak = max(peak, T)
            if q in (LEVELS[0], LEVELS[-1]):
                window[q] = (sim.get(self.w), sim.get(self.phi), sim.get("system.dissipatedEnergy"), sim.time)
        if s.kind == "drags":
            sim.advance_to(t0 + (s.duration or 0.0))
        else:
            self.reach(s, w1, t0 + rig.max_stop)
        T1 = sim.get(self.T)
        (wa, pa, ea, ta), (wb, pb, eb, tb) = window[LEVELS[0]], window[LEVELS[-1]]
        # the torque's work over the window: from the inertia in a stop, the dissipation in a drag
        work = eb - ea if s.kind == "drags" else self.r.J * (wa * wa - wb * wb) / 2
        mu_mean = work / (self.r.cgeo * fn * (pb - pa))
        self.mu_last = mu_mean
        energy = (
            sim.get("system.dissipatedEnergy") - lost0
            if s.kind == "drags"
            else self.r.J * (w0 * w0 - w1 * w1) / 2
        )
        sim.set_input(self.r.pressure_input, 0.0)
        self.clock["stops"] += time.perf_counter() - started
        row = self.row(s, k, index, fn, (T0, peak, T1, wear0), (mu_mean, mus), (energy, cooling, t0))
        # the control columns (kept only in a schedule with target decelerations)
        row["decel_mean"] = rig.from_rad_s2((wa - wb) / (tb - ta)) if s.kind == "stops" else math.nan
        row["pressure_max"], row["missed"] = row["pressure"], False
        return row

    def controlled(
        self, s: Section, k: int, index: int, speeds: tuple[float, float], start: tuple[float, ...]
    ) -> dict[str, Any]:
        """A stop with a target deceleration, under the sampled controller (control.py)."""
        (w0, w1), (fn, cooling, T0, wear0) = speeds, start
        started, t0 = time.perf_counter(), self.sim.time
        c = controlled_stop(self, s, index, w0, w1, fn)
        T1 = self.sim.get(self.T)
        self.mu_last = c.mu_mean
        self.sim.set_input(self.r.pressure_input, 0.0)
        self.clock["stops"] += time.perf_counter() - started
        energy = self.r.J * (w0 * w0 - w1 * w1) / 2
        peak = max([T0, *c.temperatures])
        row = self.row(
            s, k, index, c.fn_mean, (T0, peak, T1, wear0), (c.mu_mean, c.mus), (energy, cooling, t0)
        )
        per_bar = self.rig.fn_per_bar
        row["decel"] = s.decel
        row["pressure_max"] = c.fn_peak / per_bar if per_bar else math.nan
        row["decel_mean"] = self.rig.from_rad_s2(c.decel_mean)
        row["missed"] = c.missed
        return row

    def row(
        self,
        s: Section,
        k: int,
        index: int,
        fn: float,
        temps: tuple[float, float, float, float],
        mu: tuple[float, list[float]],
        times: tuple[float, float, float],
    ) -> dict[str, Any]:
        """A stop's row of the report."""
        rig, sim = self.rig, self.sim
        (T0, peak, T1, wear0), (mu_mean, mus), (energy, cooling, t0) = temps, mu, times
        row = {
            "index": index,
            "section": s.name,
            "kind": s.kind,
            "stop": k + 1,
            "v_initial": s.v_initial,
            "v_final": s.v_final,
            "pressure": fn / rig.fn_per_bar if rig.fn_per_bar else math.nan,
            "fn": fn,
            "T_initial": T0 - ZERO_C,
            "T_peak": max(peak, T1) - ZERO_C,
            "T_final": T1 - ZERO_C,
            "mu_mean": mu_mean,
            "mu_min": min(mus),
            "mu_max": max(mus),
            "time": sim.time - t0,
            "energy": energy,
            "cooling_time": cooling,
            "t_start": t0,
        }
        if self.wear:
            row["wear"] = sim.get(self.wear) - wear0
        if self.thickness:
            row["thickness"] = sim.get(self.thickness)
        return row


def run_schedule(
    rigged: Rigged, schedule: Schedule, progress: bool = True
) -> tuple[Any, Any, dict[str, float], dict[str, Any] | None]:
    """Run every stop of ``schedule`` on ``rigged``: the per-stop table, the samples, the
    wall-clock split (``stops``, ``cooling``, ``setup``) in s, and ``None`` — or, when the pad
    wore down to its ``thickness_min`` in a stop, which stop that was (the run ends there, the
    table holds the stops done before it)."""
    started = time.perf_counter()
    run = _Run(rigged, schedule)
    run.check_cooling()
    setup = time.perf_counter() - started
    bar = _deps.tqdm_auto.tqdm(total=schedule.stops, desc="dyno", unit="stop", disable=not progress)
    rows: list[dict[str, Any]] = []
    worn_out: dict[str, Any] | None = None
    try:
        for s in schedule.sections:
            for k in range(s.repeat):
                try:
                    rows.append(run.stop(s, k, len(rows) + 1))
                except WearLimitError as exc:
                    worn_out = {"index": len(rows) + 1, "section": s.name, "stop": k + 1, "message": str(exc)}
                    break
                bar.update(1)
            if worn_out:
                break
    finally:
        bar.close()
    pd = _deps.pandas
    table = pd.DataFrame(rows, columns=None if rows else ["index", "section", "kind"])
    if any(s.decel is not None and s.kind == "stops" for s in schedule.sections):
        table["decel"] = table["decel"].astype(float) if "decel" in table else math.nan
        # no stop ended (the pad wore out in the first): the columns, empty
        table["missed"] = table["missed"].astype(bool) if "missed" in table else False
    else:  # a pressure-only schedule's table is as it was before the controller
        table = table.drop(columns=[c for c in CONTROL_COLUMNS if c in table])
    table["section"] = table["section"].astype("string")
    table["kind"] = table["kind"].astype("string")
    # the samples of the stop the pad wore out in are kept: they show how far it got
    samples = pd.DataFrame(run.samples, columns=None if run.samples else ["index", "section"])
    samples["section"] = samples["section"].astype("string")
    return table, samples, {"setup": setup, **run.clock}, worn_out
