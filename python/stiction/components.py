"""Component descriptions: a type name plus parameter values, nothing more.

A component here is data, not behaviour; the engine owns the physics. Values are
normalised at construction to what a TOML model file can hold (numbers, booleans,
strings, arrays, small tables), so a model built in Python and one loaded from a file
are indistinguishable.
"""

from __future__ import annotations

import functools
import importlib
import numbers
import os
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar, Union

from .errors import ModelError

__all__ = ["FACTORIES", "Component", "ParamValue", "component_types", "factory"]

ParamValue = Union[bool, int, float, str, Sequence[Any], Mapping[str, Any], "os.PathLike[str]"]


def normalize_value(value: Any, where: str) -> Any:
    """Turn a parameter value into TOML-able data, or raise ModelError naming it."""
    if isinstance(value, bool):
        return value
    if type(value).__module__ == "numpy" and type(value).__name__ in ("bool", "bool_"):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "tolist") and not isinstance(value, (list, tuple)):  # numpy arrays
        return normalize_value(value.tolist(), where)
    if isinstance(value, Mapping):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise ModelError(f"{where}: table keys must be strings, got {key!r}")
            out[key] = normalize_value(item, f"{where}.{key}")
        return out
    if isinstance(value, (list, tuple)):
        return [normalize_value(item, where) for item in value]
    raise ModelError(f"{where}: unsupported value {value!r} ({type(value).__name__})")


class Component:
    """One component: an MSL-like type name and its parameter values.

    ``Component("Inertia", {"J": 2.0})`` works for any type the engine knows; the
    subclasses below (``Inertia(J=2.0)``) are the same with the type filled in.
    """

    type_name: ClassVar[str | None] = None
    __hash__ = None  # type: ignore[assignment]  # mutable

    def __init__(self, type: str, params: Mapping[str, Any] | None = None) -> None:
        if not isinstance(type, str) or not type:
            raise ModelError(f"component type must be a non-empty string, got {type!r}")
        self.type: str = type
        self.params: dict[str, Any] = {}
        for key, value in (params or {}).items():
            if not isinstance(key, str) or not key:
                raise ModelError(f"{type}: parameter names must be non-empty strings, got {key!r}")
            if key == "type":
                raise ModelError(f"{type}: 'type' is reserved and cannot be a parameter name")
            self.params[key] = normalize_value(value, f"{type}: parameter '{key}'")

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.type_name = cls.__name__

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Component):
            return NotImplemented
        return self.type == other.type and self.params == other.params

    def __repr__(self) -> str:
        if type(self).type_name == self.type:
            args = ", ".join(f"{k}={v!r}" for k, v in self.params.items())
            return f"{type(self).__name__}({args})"
        return f"Component({self.type!r}, {self.params!r})"


class _Factory(Component):
    """Base of the typed factories: keyword arguments are the parameters."""

    def __init__(self, **params: Any) -> None:
        super().__init__(type(self).type_name or "", params)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        FACTORIES[cls.__name__] = cls


FACTORIES: dict[str, type[Component]] = {}


# --- Modelica.Mechanics.Rotational.Components -----------------------------------------
class Inertia(_Factory):
    """Rigid rotating mass.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Inertia
    """


class Fixed(_Factory):
    """Flange fixed to the housing.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Fixed
    """


class Spring(_Factory):
    """Linear torsion spring.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Spring
    """


class Damper(_Factory):
    """Linear rotational damper.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Damper
    """


class SpringDamper(_Factory):
    """Spring and damper in parallel.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.SpringDamper
    """


class IdealGear(_Factory):
    """Lossless gear box.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.IdealGear
    """


class Brake(_Factory):
    """Coulomb friction between a shaft and its housing.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Brake
    """


class Clutch(_Factory):
    """Coulomb friction between two shafts.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.Clutch
    """


# --- Modelica.Mechanics.Rotational.Sources --------------------------------------------
class Torque(_Factory):
    """Torque from a signal input.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.Torque
    """


class ConstantTorque(_Factory):
    """Constant torque.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.ConstantTorque
    """


class TorqueStep(_Factory):
    """Torque step in time.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.TorqueStep
    """


class LinearSpeedDependentTorque(_Factory):
    """Torque linear in speed.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.LinearSpeedDependentTorque
    """


class QuadraticSpeedDependentTorque(_Factory):
    """Torque quadratic in speed.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.QuadraticSpeedDependentTorque
    """


class SignTorque(_Factory):
    """Regularised sign(w) torque.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.SignTorque
    """


class InverseSpeedDependentTorque(_Factory):
    """Torque inverse to speed.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.InverseSpeedDependentTorque
    """


class ConstantSpeed(_Factory):
    """Imposed constant speed.

    MSL counterpart: Modelica.Mechanics.Rotational.Sources.ConstantSpeed
    """


# --- Modelica.Blocks ------------------------------------------------------------------
class Constant(_Factory):
    """Constant signal.

    MSL counterpart: Modelica.Blocks.Sources.Constant
    """


class Step(_Factory):
    """Step signal.

    MSL counterpart: Modelica.Blocks.Sources.Step
    """


class Ramp(_Factory):
    """Ramp signal.

    MSL counterpart: Modelica.Blocks.Sources.Ramp
    """


class Sine(_Factory):
    """Sine signal.

    MSL counterpart: Modelica.Blocks.Sources.Sine
    """


class TimeTable(_Factory):
    """Piecewise-linear signal from a table or CSV file.

    MSL counterpart: Modelica.Blocks.Sources.TimeTable
    """


class Product(_Factory):
    """Product of two signals.

    MSL counterpart: Modelica.Blocks.Math.Product
    """


class Feedback(_Factory):
    """Difference u1 - u2.

    MSL counterpart: Modelica.Blocks.Math.Feedback
    """


class Add(_Factory):
    """Weighted sum k1*u1 + k2*u2.

    MSL counterpart: Modelica.Blocks.Math.Add
    """


class Gain(_Factory):
    """Signal times a constant.

    MSL counterpart: Modelica.Blocks.Math.Gain
    """


# --- Modelica.Thermal.HeatTransfer ----------------------------------------------------
class HeatCapacitor(_Factory):
    """Lumped thermal mass.

    MSL counterpart: Modelica.Thermal.HeatTransfer.Components.HeatCapacitor
    """


class ThermalConductor(_Factory):
    """Lumped thermal conduction.

    MSL counterpart: Modelica.Thermal.HeatTransfer.Components.ThermalConductor
    """


class Convection(_Factory):
    """Convective heat transfer from a signal Gc.

    MSL counterpart: Modelica.Thermal.HeatTransfer.Components.Convection
    """


class FixedTemperature(_Factory):
    """Fixed-temperature boundary.

    MSL counterpart: Modelica.Thermal.HeatTransfer.Sources.FixedTemperature
    """


# --- the rest of the MSL Coulomb-friction family ---------------------------------------
class OneWayClutch(_Factory):
    """Freewheel in parallel with a clutch: slides forward, locks instead of sliding backward.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.OneWayClutch
    """


class BearingFriction(_Factory):
    """Coulomb friction in bearings, the torque given by ``tau_pos``.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.BearingFriction
    """


class LossyGear(_Factory):
    """Gear with mesh efficiency and bearing friction (``lossTable``); can stick.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.LossyGear
    """


class ElastoBacklash(_Factory):
    """Backlash in series with a spring and damper, soft contact.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.ElastoBacklash
    """


class IdealPlanetary(_Factory):
    """Planetary gear (sun, carrier, ring) without inertia.

    MSL counterpart: Modelica.Mechanics.Rotational.Components.IdealPlanetary
    """


class Pulse(_Factory):
    """Periodic pulse signal; every edge is a time event.

    MSL counterpart: Modelica.Blocks.Sources.Pulse
    """


@functools.cache
def component_types() -> dict[str, dict[str, list[str]]] | None:
    """Give the engine's types with their parameters and ports; None if not built."""
    try:
        _core = importlib.import_module(f"{__package__}._core")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__package__}._core":
            raise
        return None
    return {
        name: {key: list(values) for key, values in info.items()}
        for name, info in _core.component_types().items()
    }


def factory(type_name: str) -> type[Component]:
    """Give the factory class of a type; engine types without one get one made."""
    if type_name in FACTORIES:
        return FACTORIES[type_name]
    known = component_types()
    if known is None or type_name not in known or not type_name.isidentifier():
        raise AttributeError(type_name)
    cls = type(
        type_name,
        (_Factory,),
        {"__doc__": f"{type_name} (engine type).", "__module__": __name__},
    )
    return cls
