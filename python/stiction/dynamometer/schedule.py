"""A dynamometer schedule file (TOML): the rig (``[dyno]``) and its sections (``[[section]]``).

Every value is checked when the file is read, and a refusal names the section and the line of
the file it stands on (``tomllib`` keeps no positions: a small scan of the text finds them).
Speeds are vehicle speeds in km/h when the rig gives a rolling radius ``r_dyn`` (or
``speed_unit = "km/h"``), else the inertia's speeds in rad/s; temperatures are in °C,
pressures in bar, times in s.
"""

from __future__ import annotations

import math
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from stiction.errors import ModelError

__all__ = ["LEVELS", "Rig", "Schedule", "ScheduleError", "Section", "load_schedule", "loads_schedule"]

#: The fractions of a stop's speed drop where mu and temperature are sampled; the mean mu is
#: taken between the first (10 %) and the last (80 %).
LEVELS = tuple(round(0.10 + 0.05 * k, 2) for k in range(15))

RIG_KEYS = {
    "brake": "the Brake component of the model",
    "inertia": "an Inertia of the model the brake stops",
    "flange": "the flange the dyno's own inertia is joined to (with J or mass/axle_share/r_dyn)",
    "J": "the dyno's inertia [kg·m²]",
    "mass": "vehicle mass [kg] (J = mass·axle_share·r_dyn²)",
    "axle_share": "the share of the mass this brake stops (per brake)",
    "r_dyn": "dynamic rolling radius [m]",
    "speed_unit": '"km/h" (vehicle speed, needs r_dyn) or "rad/s"',
    "temperature": "the brake temperature variable (default: <brake>.heatPort.T)",
    "fn_per_bar": "clamp force per bar of line pressure [N/bar]",
    "mu_nominal": "the friction coefficient a target deceleration's first stop starts with",
    "control_rate": "the deceleration controller's sample rate [Hz] (100)",
    "p_max": "the highest line pressure the controller applies [bar] (default: the brake's fn_max)",
    "max_cooling": "the longest cooling before a stop [s]",
    "max_stop": "the longest stop [s]",
}
SECTION_KEYS = {
    "name": "the section's name",
    "kind": '"stops" or "drags"',
    "repeat": "how many stops (or drags)",
    "v_initial": "speed at the start of a stop (the held speed of a drag)",
    "v_final": "speed at the end of a stop (0: to standstill)",
    "pressure": "line pressure [bar], or a list of them (one per stop)",
    "decel": "target deceleration [m/s² with km/h, rad/s² with rad/s]",
    "IBT": "initial brake temperature to cool down to before each stop [°C]",
    "interval": "fixed cooling time before each stop [s]",
    "duration": "length of a drag [s]",
}


class ScheduleError(ModelError):
    """A schedule that cannot be run, naming the section and the line of the file."""


@dataclass(frozen=True)
class Rig:
    """The ``[dyno]`` table: which brake, which inertia and how pressure reaches the brake."""

    brake: str
    inertia: str | None = None
    flange: str | None = None
    J: float | None = None
    r_dyn: float | None = None
    speed_unit: str = "rad/s"
    temperature: str | None = None
    fn_per_bar: float | None = None
    mu_nominal: float = 0.4
    control_rate: float = 100.0
    p_max: float | None = None
    max_cooling: float = 3600.0
    max_stop: float = 120.0
    line: int = 0

    def to_rad_s(self, v: float) -> float:
        """A schedule speed in rad/s of the inertia."""
        return v / 3.6 / self.r_dyn if self.speed_unit == "km/h" and self.r_dyn else v

    def to_rad_s2(self, a: float) -> float:
        """A schedule deceleration in rad/s² of the inertia."""
        return a / self.r_dyn if self.speed_unit == "km/h" and self.r_dyn else a

    def from_rad_s2(self, alpha: float) -> float:
        """An inertia's deceleration [rad/s²] in the schedule's unit."""
        return alpha * self.r_dyn if self.speed_unit == "km/h" and self.r_dyn else alpha


@dataclass(frozen=True)
class Section:
    """One ``[[section]]``: ``repeat`` stops (or drags) alike. Speeds in schedule units."""

    name: str
    kind: str
    repeat: int
    v_initial: float
    v_final: float
    pressure: tuple[float, ...] | None  # [bar], one per stop
    decel: float | None
    IBT: float | None  # °C
    interval: float | None
    duration: float | None
    line: int
    lines: dict[str, int] = field(default_factory=dict)

    def where(self, key: str | None = None) -> str:
        """``section 'fade' (line 40)``, or the line of one of its keys."""
        line = self.lines.get(key, self.line) if key else self.line
        return f"section '{self.name}' (line {line})"


@dataclass(frozen=True)
class Schedule:
    """A rig and its sections, as read from a schedule file."""

    rig: Rig
    sections: list[Section]
    source: str = "schedule"

    @property
    def stops(self) -> int:
        """How many stops and drags the schedule runs."""
        return sum(s.repeat for s in self.sections)


_HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z_][\w.-]*)\s*\]\]?")
_KEY = re.compile(r'^\s*("?)([A-Za-z_][\w-]*)\1\s*=')


def _positions(text: str) -> tuple[dict[str, int], list[dict[str, int]]]:
    """Line numbers (1-based) of the ``[dyno]`` keys and of each ``[[section]]``'s keys (its
    header under ``""``)."""
    rig: dict[str, int] = {}
    sections: list[dict[str, int]] = []
    current: dict[str, int] | None = None
    for number, line in enumerate(text.splitlines(), start=1):
        if header := _HEADER.match(line):
            if header.group(2) == "dyno" and header.group(1) == "[":
                rig[""] = number
                current = rig
            elif header.group(2) == "section" and header.group(1) == "[[":
                sections.append({"": number})
                current = sections[-1]
            else:
                current = None
            continue
        if current is not None and (key := _KEY.match(line)):
            current.setdefault(key.group(2), number)
    return rig, sections


def _number(value: Any, where: str, key: str, *, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ScheduleError(f"{where}: {key} = {value!r} is not a finite number")
    if value < 0 or (positive and value == 0):
        raise ScheduleError(f"{where}: {key} = {value} must be {'positive' if positive else '≥ 0'}")
    return float(value)


def _unknown(table: dict[str, Any], known: dict[str, str], where: Any) -> None:
    for key in table:
        if key not in known:
            near = [k for k in known if k.lower() == key.lower() or k.lower().startswith(key.lower()[:3])]
            hint = f" (did you mean {', '.join(near)}?)" if near else f"; known keys: {', '.join(known)}"
            raise ScheduleError(f"{where(key)}: unknown key '{key}'{hint}")


def _rig(table: Any, lines: dict[str, int], source: str) -> Rig:
    at = lambda key=None: f"{source}: [dyno] (line {lines.get(key or '', lines.get('', 0))})"
    if not isinstance(table, dict):
        raise ScheduleError(f"{source}: a [dyno] table naming the brake is missing")
    _unknown(table, RIG_KEYS, at)
    if not isinstance(table.get("brake"), str):
        raise ScheduleError(f"{at('brake')}: brake = the name of the model's Brake is missing")
    values = {
        k: _number(table[k], at(k), k, positive=True)
        for k in RIG_KEYS
        if k in table
        and k
        in (
            "J",
            "mass",
            "axle_share",
            "r_dyn",
            "fn_per_bar",
            "mu_nominal",
            "control_rate",
            "p_max",
            "max_cooling",
            "max_stop",
        )
    }
    if "p_max" in values and "fn_per_bar" not in values:
        raise ScheduleError(f"{at('p_max')}: p_max [bar] needs fn_per_bar (the clamp force per bar)")
    J = values.pop("J", None)
    mass, share = values.pop("mass", None), values.pop("axle_share", None)
    r_dyn = values.get("r_dyn")
    if mass is not None or share is not None:
        if mass is None or share is None or r_dyn is None or J is not None:
            raise ScheduleError(
                f"{at('mass')}: the inertia from the vehicle needs mass, axle_share and r_dyn (and no J)"
            )
        J = mass * share * r_dyn**2
    if ("inertia" in table) == ("flange" in table):
        raise ScheduleError(f"{at()}: name either the model's inertia or a flange for the dyno's own inertia")
    if "flange" in table and J is None:
        raise ScheduleError(f"{at('flange')}: the dyno's own inertia needs J (or mass, axle_share, r_dyn)")
    if "inertia" in table and J is not None:
        raise ScheduleError(f"{at('J')}: J is the model's inertia's when 'inertia' names it")
    unit = table.get("speed_unit", "km/h" if r_dyn else "rad/s")
    if unit not in ("km/h", "rad/s") or (unit == "km/h" and r_dyn is None):
        raise ScheduleError(f'{at("speed_unit")}: speed_unit = {unit!r}: "rad/s", or "km/h" with r_dyn')
    for key in ("inertia", "flange", "temperature"):
        if key in table and not isinstance(table[key], str):
            raise ScheduleError(f"{at(key)}: {key} must be a name, got {table[key]!r}")
    return Rig(
        brake=table["brake"],
        inertia=table.get("inertia"),
        flange=table.get("flange"),
        J=J,
        speed_unit=unit,
        temperature=table.get("temperature"),
        line=lines.get("", 0),
        **values,
    )


def _section(table: Any, lines: dict[str, int], k: int, source: str) -> Section:
    name = table.get("name", f"#{k + 1}") if isinstance(table, dict) else f"#{k + 1}"
    at = lambda key=None: f"{source}: section '{name}' (line {lines.get(key or '', lines[''])})"
    _unknown(table, SECTION_KEYS, at)
    kind = table.get("kind", "stops")
    if kind not in ("stops", "drags"):
        raise ScheduleError(f'{at("kind")}: kind = {kind!r}: "stops" or "drags"')
    repeat = table.get("repeat", 1)
    if isinstance(repeat, bool) or not isinstance(repeat, int) or repeat < 1:
        raise ScheduleError(f"{at('repeat')}: repeat = {repeat!r} must be a whole number ≥ 1")
    if "v_initial" not in table:
        raise ScheduleError(f"{at()}: v_initial is missing")
    for key in ("v_initial", "v_final"):
        if key in table and isinstance(table[key], (int, float)) and table[key] < 0:
            raise ScheduleError(f"{at(key)}: {key} = {table[key]}: a negative speed (the dyno turns one way)")
    v0 = _number(table["v_initial"], at("v_initial"), "v_initial", positive=True)
    v1 = _number(table.get("v_final", 0.0), at("v_final"), "v_final")
    if kind == "stops" and v1 >= v0:
        raise ScheduleError(
            f"{at('v_final')}: v_final = {v1} is not below v_initial = {v0}: a stop slows down"
        )
    pressures = table.get("pressure")
    if isinstance(pressures, list):  # one pressure per stop: a pressure-sensitivity section
        if "repeat" in table and len(pressures) != repeat:
            raise ScheduleError(f"{at('pressure')}: {len(pressures)} pressures for repeat = {repeat}")
        repeat = len(pressures)
        table = {**table, "pressure": pressures[0] if pressures else None}
        pressures = tuple(_number(p, at("pressure"), "pressure", positive=True) for p in pressures)
    nums = {
        k: _number(table[k], at(k), k, positive=k != "interval")
        for k in ("pressure", "decel", "interval", "duration")
        if k in table
    }
    if "pressure" in nums and not isinstance(pressures, tuple):
        pressures = (nums["pressure"],) * repeat
    if ("pressure" in nums) == ("decel" in nums):
        raise ScheduleError(f"{at()}: give either pressure [bar] or decel")
    if kind == "drags" and ("duration" not in nums or "pressure" not in nums):
        raise ScheduleError(f"{at()}: a drag needs pressure and duration")
    if "IBT" in table and "interval" in nums:
        raise ScheduleError(f"{at('IBT')}: give either IBT (cool down to it) or interval (a fixed time)")
    ibt = None
    if "IBT" in table:
        value = table["IBT"]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value <= -273.15:
            raise ScheduleError(f"{at('IBT')}: IBT = {value!r} °C is not a temperature")
        ibt = float(value)
    return Section(
        name=str(name),
        kind=kind,
        repeat=repeat,
        v_initial=v0,
        v_final=v1 if kind == "stops" else v0,
        pressure=pressures if "pressure" in nums else None,
        decel=nums.get("decel"),
        IBT=ibt,
        interval=nums.get("interval"),
        duration=nums.get("duration"),
        line=lines[""],
        lines=dict(lines),
    )


def loads_schedule(text: str, source: str = "schedule") -> Schedule:
    """A schedule from TOML text; ``ScheduleError`` naming section and line if it is wrong."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScheduleError(f"{source}: not valid TOML: {exc}") from None
    rig_lines, section_lines = _positions(text)
    for key in data:
        if key not in ("dyno", "section", "name", "description"):
            keys = (_KEY.match(t) for t in text.splitlines())
            line = next((n for n, m in enumerate(keys, 1) if m and m.group(2) == key), 0)
            raise ScheduleError(
                f"{source}: line {line}: unknown top-level key '{key}' "
                "(a schedule has name, description, [dyno] and [[section]]s)"
            )
    rig = _rig(data.get("dyno"), rig_lines, source)
    tables = data.get("section", [])
    if not isinstance(tables, list) or not tables or len(tables) != len(section_lines):
        raise ScheduleError(f"{source}: write the sections as [[section]] tables, at least one")
    sections = [_section(t, lines, k, source) for k, (t, lines) in enumerate(zip(tables, section_lines))]
    for s in sections:
        if s.pressure is not None and rig.fn_per_bar is None:
            raise ScheduleError(f"{source}: {s.where('pressure')}: a pressure needs fn_per_bar in [dyno]")
    return Schedule(rig=rig, sections=sections, source=source)


def load_schedule(path: str | os.PathLike[str]) -> Schedule:
    """Read a schedule file (see ``loads_schedule``)."""
    path = Path(path)
    return loads_schedule(path.read_text(encoding="utf-8"), source=str(path))
