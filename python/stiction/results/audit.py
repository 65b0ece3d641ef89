"""The energy audit of a run, element by element (``Result.audit()``).

For every component with flanges and at every result row, the power entering through its
flanges (the reported cut torques times the flange speeds) is compared with what the
component's own equations take: an inertia ``J·w·a``, a spring or damper ``tau·w_rel``, a
friction element or lossy gear its ``lossPower``, an ideal gear nothing. The two sides are
computed independently (the flange torques from the torque balance of each connection), so a
mistake in either shows. A passive element (no source, no prescribed speed) must never
deliver net energy: what it dissipated over the run is not negative. (Its power may dip below
zero for a while where MSL's equations say so: a brake "starting backward" while another
element drives its shaft forward keeps its backward breakaway torque until the hysteresis
relation flips; ``min_dissipation`` shows such a dip.)

One power is judged apart (``withheld``): MSL's OneWayClutch reports no loss while stuck
(``w_rel <= 0``), also while it starts forward and its integrated relative speed drifts a
little below 0. There ``tau·w_rel`` is neither loss nor stored energy; it is the element's
torque times an error of the integrator, so it must stay within the torque times
``slip_bound`` (the event band plus the integrator's error bound on the relative speed), not
within round-off.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from stiction import _deps
from stiction.errors import EnergyWarning

if TYPE_CHECKING:
    import pandas

    from stiction.results.result import Result

__all__ = ["ElementBalance", "EnergyAudit", "warn_if_delivering"]

# Round-off: 1e-9 of the model's largest power. And a stuck element's relative speed stays
# inside the ±1e-10 rad/s event band (the relations switch there), so its held torque may show
# up to 1e-10·tau of power; twice that is allowed per element.
DEFAULT_TOLERANCE = 1e-9
EVENT_BAND = 2e-10


@dataclass(frozen=True)
class ElementBalance:
    """One component's energy balance over the run (powers in W, energies in J)."""

    component: str
    residual: float
    """Largest |power in − power its parts take| over the rows."""
    scale: float
    """Largest power term of the component over the rows."""
    torque: float
    """Largest cut torque at its flanges (N·m)."""
    passive: bool
    """No source law and no constraint doing work (a speed source)."""
    min_dissipation: float
    """Least power dissipated over the rows; negative means it delivered energy."""
    energy_in: float
    """Energy that entered through the flanges (trapezoid rule over the rows)."""
    dissipated: float
    """Energy dissipated (trapezoid rule over the rows).

    Off by order ``Interval**2`` where a power oscillates within an output interval (0.18 % on a
    Gearbox with backlash at ``Interval=0.01``); ``system.dissipatedEnergy`` is integrated with
    the states and exact to solver tolerance. Includes the spring energy an ElastoBacklash
    loses where a contact opens still compressed, which MSL's ``lossPower`` leaves out, and
    ``reset_loss``.
    """
    withheld: float = 0.0
    """Largest |tau·w_rel − lossPower| over the rows: what MSL's loss law leaves out (a
    OneWayClutch while stuck); 0 for every other element."""
    slip_bound: float = 0.0
    """How far its relative speed may be off [rad/s]: the event band plus
    ``2·Tolerance·(1 + largest flange speed)``, the integrator's error bound on a difference
    of two speeds."""
    reset_loss: float = 0.0
    """Kinetic energy its resets removed at state events (MSL's ``reinit`` of a
    MassWithStopAndFriction at a stop), part of ``dissipated``; 0 for most elements."""


class EnergyAudit:
    """Every element's balance; ``worst`` is the one furthest from closing."""

    def __init__(self, elements: Iterable[ElementBalance], span: float = 1.0) -> None:
        """``span``: the run's length [s], which turns the power tolerances into energies."""
        self.elements = list(elements)
        self.scale = max([1.0, *(e.scale for e in self.elements)])
        self.span = span

    @classmethod
    def from_core(cls, rows: Iterable[Mapping[str, Any]], span: float = 1.0) -> EnergyAudit:
        """From the engine's rows, one mapping of ``ElementBalance``'s fields per element."""
        return cls((ElementBalance(**row) for row in rows), span)

    @property
    def worst(self) -> ElementBalance | None:
        """The element with the largest residual (None for a model without flanges)."""
        return max(self.elements, key=lambda e: e.residual, default=None)

    def allowed(self, element: ElementBalance, tolerance: float = DEFAULT_TOLERANCE) -> float:
        """The power an element's balance may be off by [W]: round-off of the model's largest
        power plus its held torque times the event band."""
        return tolerance * self.scale + EVENT_BAND * element.torque

    def allowed_withheld(self, element: ElementBalance, tolerance: float = DEFAULT_TOLERANCE) -> float:
        """The power an element's loss law may leave out [W]: round-off plus its torque times
        ``slip_bound``."""
        return tolerance * self.scale + element.torque * element.slip_bound

    def delivering(self, tolerance: float = DEFAULT_TOLERANCE) -> list[ElementBalance]:
        """Passive elements that delivered net energy over the run (dissipated less than
        −``allowed`` times the run's length)."""
        return [
            e for e in self.elements if e.passive and e.dissipated < -self.allowed(e, tolerance) * self.span
        ]

    def open(self, tolerance: float = DEFAULT_TOLERANCE) -> list[ElementBalance]:
        """Elements whose balance does not close: residual above ``allowed``, or a withheld
        power above ``allowed_withheld``."""
        return [
            e
            for e in self.elements
            if e.residual > self.allowed(e, tolerance) or e.withheld > self.allowed_withheld(e, tolerance)
        ]

    def ok(self, tolerance: float = DEFAULT_TOLERANCE) -> bool:
        """Every balance closes and no passive element delivers energy."""
        return not self.open(tolerance) and not self.delivering(tolerance)

    def to_pandas(self) -> pandas.DataFrame:
        """One row per component, indexed by name."""
        pd = _deps.pandas

        return pd.DataFrame([vars(e) for e in self.elements]).set_index("component")

    def failures(self, tolerance: float = DEFAULT_TOLERANCE) -> list[str]:
        """One line per element that fails, worst first: a passive element that delivered
        energy, then a balance that does not close; empty when the audit passes."""
        delivering = sorted(self.delivering(tolerance), key=lambda e: e.dissipated)
        unclosed = sorted(self.open(tolerance), key=lambda e: -max(e.residual, e.withheld))
        return [
            *(f"{e.component} delivered {-e.dissipated:.3g} J (a passive element)" for e in delivering),
            *(f"{e.component} is off by {max(e.residual, e.withheld):.3g} W" for e in unclosed),
        ]

    def __str__(self) -> str:
        worst = self.worst
        if worst is None:
            return "energy audit: no component with flanges"
        failures = self.failures()
        if failures:  # name the elements that fail, not the largest residual (issue 29)
            first = failures[0].split(" ", 1)[0]
            return "\n".join([f"energy audit DOES NOT CLOSE: {first} fails", *(f"  {f}" for f in failures)])
        return f"energy audit closes: largest residual {worst.component}, {worst.residual:.3g} W of {self.scale:.3g} W"


def warn_if_delivering(result: Result, suspects: Iterable[str]) -> None:
    """Warn (``EnergyWarning``) for each passive element the energy audit finds delivering
    energy, naming it and the energy. ``suspects`` are the elements whose loss power the engine
    saw below the event band at the end of some step (``RawResult.delivering``): a run without
    any is not audited, so a normal run pays nothing."""
    if not list(suspects):
        return
    audit = result.audit()
    for e in sorted(audit.delivering(), key=lambda e: e.dissipated):
        warnings.warn(
            f"energy audit: {e.component} delivered {-e.dissipated:.3g} J over the run, though it is "
            "a passive element (its balance does not close): the result is not physical; "
            "see Result.audit()",
            EnergyWarning,
            stacklevel=_caller_level(),
        )


def _caller_level() -> int:
    """The ``stacklevel`` of the first frame outside the stiction package (the user's call)."""
    frame, level = sys._getframe(1), 1
    while frame is not None and str(frame.f_globals.get("__name__", "")).startswith("stiction"):
        frame, level = frame.f_back, level + 1  # type: ignore[assignment]
    return level
