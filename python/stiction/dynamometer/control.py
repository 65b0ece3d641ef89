"""Closed-loop deceleration control: how the dyno holds a stop's target deceleration.

A dynamometer's digital controller samples at a fixed rate; so does this one, at the rig's
``control_rate`` (100 Hz unless the schedule says otherwise). At each sample instant it takes
the brake's mean torque over the sample just ended from the inertia's momentum,
``tau = J·(w_start − w_end)/dt`` (exact: the brake is the one torque on the dyno's inertia in
a stop), the friction coefficient it measured, ``mu = tau/(cgeo·fn)`` (``fn`` was held over the
sample), and holds for the next sample the clamp force that would give the target with it,
``fn = J·alpha/(mu·cgeo)``, clipped to the limit (``p_max·fn_per_bar``, and never above the
brake's ``fn_max``). The first sample starts from the feed-forward of the previous stop's mean
mu. Each new clamp force is one input event of the ``Simulation`` (``set_input``).

With mu changing at ``dmu/dt`` the deceleration of a sample is off by the change over the
sample before it, ``alpha·(dmu/dt)·dt/mu`` relative: a brake fading 10 %/s at 100 Hz is held to
0.1 %. When the target needs more than the limit, the pressure stays at the limit and the stop
is flagged ``missed`` (any sample between 10 % and 80 % of the speed drop clipped).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from stiction.dynamometer.rig import Rigged
from stiction.dynamometer.schedule import LEVELS, Rig, ScheduleError, Section

if TYPE_CHECKING:
    from stiction.dynamometer.runner import _Run

__all__ = ["CONTROL_COLUMNS", "Controlled", "controlled_stop", "controller_limit"]

#: The report's columns of a schedule with target decelerations (left out of any other's).
CONTROL_COLUMNS = ("decel", "decel_mean", "pressure_max", "missed")


def controller_limit(r: Rigged, rig: Rig) -> float:
    """The highest clamp force the controller applies [N]: ``p_max·fn_per_bar``, at most the
    brake's ``fn_max`` (``f_normalized = 1``)."""
    return r.fn_max if rig.p_max is None else min(rig.p_max * float(rig.fn_per_bar or 0.0), r.fn_max)


@dataclass
class Controlled:
    """What a controlled stop leaves for its row: the clamp force's time mean and peak, the
    mean mu (sliding-distance weighted, exact per sample), the mean deceleration over the
    window [rad/s²], whether the limit held the stop short of its target, and the samples'
    mu and temperatures."""

    fn_mean: float
    fn_peak: float
    mu_mean: float
    decel_mean: float
    missed: bool
    mus: list[float] = field(default_factory=list)
    temperatures: list[float] = field(default_factory=list)


class _Loop:
    """The controller's state over one stop."""

    def __init__(self, run: _Run, s: Section, fn: float) -> None:
        rig, r = run.rig, run.r
        self.run, self.s = run, s
        self.alpha = rig.to_rad_s2(float(s.decel or 0.0))
        self.limit = controller_limit(r, rig)
        self.fn, self.clipped = fn, fn >= self.limit  # the feed-forward, clipped by the runner
        self.fn_peak, self.fn_time = self.fn, 0.0
        self.in_window, self.missed, self.mu_work = False, False, 0.0
        self.t_k, self.w_k = run.sim.time, run.sim.get(run.w)  # the sample's start
        self.w_b = self.w_k  # the last breakpoint of the window integral

    def apply(self) -> None:
        r = self.run.r
        self.run.sim.set_input(r.pressure_input, self.fn / r.fn_max)

    def piece(self, w: float) -> None:
        """Close a piece of constant clamp force at speed ``w``: its share of ``∫mu dphi``."""
        if self.in_window:
            r = self.run.r
            self.mu_work += r.J * (self.w_b * self.w_b - w * w) / (2.0 * r.cgeo * self.fn)
            self.missed |= self.clipped
        self.w_b = w

    def sample_ends(self) -> None:
        """A sample instant: measure mu over the sample, set the next clamp force."""
        run, r = self.run, self.run.r
        t, w = run.sim.time, run.sim.get(run.w)
        self.piece(w)
        dt = t - self.t_k
        self.fn_time += self.fn * dt
        tau = r.J * (self.w_k - w) / dt if dt > 0 else 0.0
        mu = tau / (r.cgeo * self.fn) if self.fn > 0 else 0.0
        want = r.J * self.alpha / (mu * r.cgeo) if mu > 0 else math.inf
        self.clipped = want > self.limit
        self.fn = min(want, self.limit)
        self.fn_peak = max(self.fn_peak, self.fn)
        self.apply()
        self.t_k, self.w_k = t, w


def controlled_stop(run: _Run, s: Section, index: int, w0: float, w1: float, fn0: float) -> Controlled:
    """Run a stop with a target deceleration from ``w0`` to ``w1`` under the sampled
    controller, starting from clamp force ``fn0`` (applied, clipped to the limit); the samples at 10 %, 15 %, … 80 % of the
    speed drop at their exact instants as in a pressure stop."""
    sim, rig = run.sim, run.rig
    loop = _Loop(run, s, fn0)
    t0, dt = sim.time, 1.0 / rig.control_rate
    levels = [w0 - q * (w0 - w1) for q in LEVELS] + [w1]
    mus: list[float] = []
    temperatures: list[float] = []
    window: dict[int, tuple[float, float, float]] = {}
    i, k = 0, 1
    while i < len(levels):
        t_next = min(t0 + k * dt, t0 + rig.max_stop)
        if sim.advance_until(run.w, levels[i], t_next):
            w = sim.get(run.w)
            loop.piece(w)
            if i < len(LEVELS):
                mu, T = run.sample(s, index, LEVELS[i])
                mus.append(mu)
                temperatures.append(T)
                if i in (0, len(LEVELS) - 1):
                    window[i] = (sim.time, w, sim.get(run.phi))
                    loop.in_window = i == 0
            i += 1
            continue
        if t_next >= t0 + rig.max_stop:
            raise ScheduleError(
                f"{run.schedule.source}: {s.where()}: the stop did not slow to {levels[i]:g} rad/s "
                f"within max_stop = {rig.max_stop:g} s"
            )
        loop.sample_ends()
        k += 1
    loop.fn_time += loop.fn * (sim.time - loop.t_k)
    (ta, wa, pa), (tb, wb, pb) = window[0], window[len(LEVELS) - 1]
    span = sim.time - t0
    return Controlled(
        fn_mean=loop.fn_time / span if span > 0 else loop.fn,
        fn_peak=loop.fn_peak,
        mu_mean=loop.mu_work / (pb - pa),
        decel_mean=(wa - wb) / (tb - ta),
        missed=loop.missed,
        mus=mus,
        temperatures=temperatures,
    )
