"""Quantities with units where a number is typed: ``"20 kN"``, ``"1500 rpm"``, ``"20 degC"``.

A Real parameter, a start value or a table cell may be text: a number and a unit that pint
reads (``"100 km/h"``, ``"2 kg*m^2"``, ``"20 °C"``, ``"90 deg"``). It is converted once, when
the component is built (``st.Inertia(w="1500 rpm")``, a model file, ``m.set``, a sweep's
overrides), to the unit the catalogue declares for the parameter (``rad/s``), so the model
holds SI numbers and the engine never sees a unit. A quantity of another kind is a
``ModelError`` saying what it is and what was wanted ("'20 km/h' is a speed, not a force
[N]"). Angles count: ``"2 Hz"`` is not an angular velocity (write ``"2 rev/s"``), and a
stiffness is per radian.

Display units are MSL's ``displayUnit`` of the SI types: temperatures in degC, angles in deg
(``display_unit``); the numbers stay in SI.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Callable
from typing import Any

from stiction import _deps
from stiction.errors import ModelError

__all__ = [
    "DISPLAY_UNITS",
    "display_unit",
    "from_si",
    "in_display_unit",
    "is_quantity",
    "si_base",
    "to_si",
]

# MSL's displayUnit of the SI types the catalogue uses (Modelica.Units.SI: Temperature and
# ThermodynamicTemperature are shown in degC, Angle in deg); the others declare none.
DISPLAY_UNITS = {"K": "degC", "rad": "deg"}

# A number followed by something that starts like a unit (a letter, °, %, µ): "20 kN",
# "1500rpm", "-5 degC"; "0.9*mu0" and "mu0" are expressions, not quantities.
_QUANTITY = re.compile(
    r"\s*(?P<number>[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(?P<unit>[A-Za-z°%µΩ].*?)?\s*"
)

# Names of kinds of quantity, for messages: a pint unit, and how many radians it holds (so that
# a frequency is not an angular velocity and a torque not a stiffness).
_KINDS = (
    ("a dimensionless number", "dimensionless", 0),
    ("an angle", "rad", 1),
    ("an angular velocity", "rad/s", 1),
    ("an angular acceleration", "rad/s**2", 1),
    ("a frequency", "Hz", 0),
    ("a time", "s", 0),
    ("a force", "N", 0),
    ("a torque or an energy", "N*m", 0),
    ("a rotational stiffness", "N*m/rad", -1),
    ("a rotational damping", "N*m*s/rad", -1),
    ("a moment of inertia", "kg*m**2", 0),
    ("a temperature", "K", 0),
    ("a heat capacity", "J/K", 0),
    ("a thermal conductance", "W/K", 0),
    ("a power", "W", 0),
    ("a speed", "m/s", 0),
    ("an acceleration", "m/s**2", 0),
    ("a length", "m", 0),
    ("a mass", "kg", 0),
    ("a pressure", "Pa", 0),
    ("an area", "m**2", 0),
    ("a volume", "m**3", 0),
)


@functools.cache
def _registry() -> Any:
    """pint's unit registry (a quarter of a second: made on the first quantity), with ``rev``."""
    ureg = _deps.pint.UnitRegistry()
    ureg.define("@alias revolution = rev")
    return ureg


def _pint_text(unit: str) -> str:
    """A Modelica unit string as pint reads it: ``kg.m2`` → ``kg*m**2``, ``1`` → dimensionless."""
    if unit in ("", "1"):
        return "dimensionless"
    parts = []
    for part in re.split(r"(/)", unit):
        if part == "/":
            parts.append("/")
            continue
        factors = [re.sub(r"^([A-Za-z%]+)(-?\d+)$", r"\1**\2", f) for f in part.split(".")]
        parts.append("(" + "*".join(factors) + ")")
    return "".join(parts)


@functools.cache
def _unit(text: str) -> Any:
    """A pint unit of pint text (cached: a sweep converts the same units again and again)."""
    return _registry().parse_units(text)


def _radians(unit: Any) -> float:
    """How many radians a unit holds (rpm: 1, Hz: 0, N.m/rad: -1)."""
    return float(dict(_registry().get_root_units(unit)[1]._units).get("radian", 0))


def _kind(unit: Any, modelica: str | None = None) -> str:
    """``a force`` for N, kN, lbf …; the dimension for a unit of no kind named here."""
    radians = _radians(unit)
    for name, text, rad in _KINDS:
        known = _unit(text)
        if known.dimensionality == unit.dimensionality and rad == radians:
            return name
    if modelica:
        return f"a quantity in {modelica}"
    return f"of dimension {unit.dimensionality}" + (f" x rad^{radians:g}" if radians else "")


def is_quantity(text: str) -> bool:
    """Whether text reads as a number with a unit (``"20 kN"``), not an expression (``"0.9*mu0"``)."""
    found = _QUANTITY.fullmatch(text)
    return bool(found and found.group("unit"))


def to_si(text: str, unit: str, where: str) -> float:
    """The number ``text`` (``"20 kN"``) is in ``unit``, a Modelica unit string (``N``).

    A bare number (``"20"``) is taken as it is, as everywhere in a model. Raises ModelError
    starting with ``where`` for text that is no quantity, a unit pint does not know, or a
    quantity of the wrong kind.
    """
    found = _QUANTITY.fullmatch(text)
    if not found:
        raise ModelError(
            f"{where}: {text!r} is not a number with a unit such as '20 kN' or '1500 rpm' "
            '(an expression over top-level parameters is written { expr = "…" }, st.expr in Python)'
        )
    number = float(found.group("number"))
    if not found.group("unit"):
        return number
    try:
        given = _unit(found.group("unit"))
    except Exception as exc:  # noqa: BLE001  # pint's parser raises many kinds (AssertionError: "kg*")
        raise ModelError(f"{where}: {text!r}: {_why(exc, found.group('unit'))}") from None
    wanted = _unit(_pint_text(unit))
    if given.dimensionality != wanted.dimensionality or _radians(given) != _radians(wanted):
        raise ModelError(f"{where}: {text!r} is {_kind(given)}, not {_kind(wanted, unit)} [{unit}]")
    value = float(_registry().Quantity(number, given).to(wanted).magnitude)
    if not math.isfinite(value):
        raise ModelError(f"{where}: {text!r} is not a finite number")
    return value


def si_base(text: str, where: str) -> float:
    """A quantity where no unit is declared (a top-level parameter) in SI base units:
    ``"1500 rpm"`` → 157.08 (rad/s), ``"20 degC"`` → 293.15 (K), ``"20 kN"`` → 20000 (N)."""
    found = _QUANTITY.fullmatch(text)
    if not found or not found.group("unit"):
        return to_si(text, "1", where)  # a bare number, or the message for no quantity
    try:
        given = _unit(found.group("unit"))
    except Exception as exc:  # noqa: BLE001  # as in to_si
        raise ModelError(f"{where}: {text!r}: {_why(exc, found.group('unit'))}") from None
    quantity = _registry().Quantity(float(found.group("number")), given)
    return float(quantity.to_base_units().magnitude)


def from_si(value: float, unit: str, target: str) -> float:
    """``value`` in ``unit`` (Modelica, ``K``) expressed in ``target`` (``degC``)."""
    quantity = _registry().Quantity(value, _unit(_pint_text(unit)))
    return float(quantity.to(_unit(_pint_text(target))).magnitude)


def display_unit(unit: str) -> str | None:
    """MSL's display unit of a quantity in ``unit`` (``K`` → ``degC``, ``rad`` → ``deg``), or None."""
    return DISPLAY_UNITS.get(unit)


# the conversions to the display units, on numbers or NumPy arrays alike (no pint: a plot of
# a result needs none)
_TO_DISPLAY: dict[str, Callable[[Any], Any]] = {
    "K": lambda v: v - 273.15,
    "rad": lambda v: v * (180.0 / math.pi),
}


def in_display_unit(value: Any, unit: str) -> tuple[Any, str]:
    """``value`` (a number or an array in ``unit``) in MSL's display unit, with that unit:
    ``(293.15, "K")`` → ``(20.0, "degC")``; values of units without one are returned as they are."""
    shown = DISPLAY_UNITS.get(unit)
    return (_TO_DISPLAY[unit](value), shown) if shown else (value, unit)


def _why(exc: Exception, unit: str) -> str:
    if isinstance(exc, _deps.pint.errors.UndefinedUnitError):
        names = ", ".join(repr(n) for n in exc.unit_names) if exc.unit_names else repr(unit)
        return f"{names} is not a unit pint knows"
    return f"{unit!r} is not a unit pint reads"
