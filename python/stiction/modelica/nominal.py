"""Modelica's ``nominal`` of a state variable, which the engine turns into the integrator's
absolute tolerance of the states that variable is made of (Tolerance·nominal, as Dymola's
DASSL scales it): ``w_rel(nominal=1e-4)`` and MSL's ``phi_nominal`` of a compliant element."""

from __future__ import annotations

from typing import Any

from stiction.expressions.lexer import ModelicaError, Pos

__all__ = ["PHI_NOMINAL", "phi_nominal", "positive_nominal", "with_phi_nominal"]

#: PartialCompliantWithRelativeStates' parameter: phi_rel's nominal where it is at least eps.
PHI_NOMINAL = "phi_nominal"
_EPS = 2.220446049250313e-16  # Modelica.Constants.eps


def positive_nominal(value: Any, pos: Pos, where: str) -> float:
    """A ``nominal`` attribute's value: a positive number, else an error placed at ``pos``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
        raise ModelicaError(pos, f"'{where}': nominal must be a positive number, got {value!r}")
    return float(value)


def phi_nominal(value: Any, pos: Pos, where: str) -> float:
    """MSL's ``phi_nominal`` (``min = 0``) as phi_rel's nominal: itself from eps on, else 1."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
        raise ModelicaError(pos, f"'{where}': phi_nominal must be a number >= 0, got {value!r}")
    return float(value) if value >= _EPS else 1.0


def with_phi_nominal(params: dict[str, Any], nominal: float) -> None:
    """Puts ``phi_nominal`` on the component's ``phi_rel`` start value, unless that names its
    own nominal (a modifier of the variable overrides the binding in MSL's declaration)."""
    start = params.get("phi_rel")
    if isinstance(start, dict):
        params["phi_rel"] = {"nominal": nominal, **start}
    elif start is None:
        params["phi_rel"] = {"nominal": nominal}
    else:  # the short form of a fixed start value: a number or an expression
        params["phi_rel"] = {"start": start, "fixed": True, "nominal": nominal}
