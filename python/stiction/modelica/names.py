"""MSL class names: the catalogue of what stiction implements, and Modelica's name lookup.

A class name in a model resolves as Modelica resolves it, restricted to the MSL packages
stiction knows: through the model's imports, then relative to each enclosing package
(``within Modelica.Mechanics.Rotational.Examples`` makes ``Rotational.Components.Inertia``
and ``Components.Clutch`` name MSL classes), then as a fully qualified name. Names MSL 3.2.x
used and 4.x renamed are mapped as MSL's conversion script maps them.
"""

from __future__ import annotations

from stiction.expressions.evaluate import MSL_CONSTANTS as CONSTANTS
from stiction.expressions.evaluate import PARAMETER_FUNCTIONS
from stiction.expressions.lexer import ModelicaError, Pos
from stiction.modelica.ast import Import

__all__ = [
    "CONNECTOR_KINDS",
    "FADE_CLASSES",
    "FADE_PARAMETERS",
    "MSL_CLASSES",
    "OWN_COMPONENTS",
    "PARAMETER_RENAMES",
    "TYPE_OF",
    "WEAR_ANNOTATION",
    "Scope",
    "is_enumeration",
    "is_icon",
    "is_unit_type",
]

_ROT = "Modelica.Mechanics.Rotational"
_TRANS = "Modelica.Mechanics.Translational"
_HEAT = "Modelica.Thermal.HeatTransfer"
# a friction element's `wear` record (a stiction extension) as a component annotation
WEAR_ANNOTATION = "__stiction_wear"
OWN_COMPONENTS = ("SlipWheel",)  # beyond the MSL: exported as Stiction.Components.<type>

# stiction type -> MSL class (the name export writes)
MSL_CLASSES: dict[str, str] = {
    **{
        t: f"{_ROT}.Components.{t}"
        for t in [
            "Inertia",
            "Fixed",
            "Spring",
            "Damper",
            "SpringDamper",
            "ElastoBacklash",
            "ElastoBacklash2",
            "Disc",
            "RelativeStates",
            "IdealGear",
            "IdealPlanetary",
            "Brake",
            "Clutch",
            "OneWayClutch",
            "BearingFriction",
            "LossyGear",
            "TorqueToAngleAdaptor",
            "AngleToTorqueAdaptor",
            "IdealRollingWheel",
            "IdealGearR2T",
            "GeneralTorqueToAngleAdaptor",
            "GeneralAngleToTorqueAdaptor",
            "InitializeFlange",
            "Gearbox",
        ]
    },
    **{
        t: f"{_ROT}.Sources.{t}"
        for t in [
            "Torque",
            "ConstantTorque",
            "TorqueStep",
            "LinearSpeedDependentTorque",
            "QuadraticSpeedDependentTorque",
            "SignTorque",
            "InverseSpeedDependentTorque",
            "ConstantSpeed",
            "Speed",
            "Position",
            "Accelerate",
            "Move",
            "EddyCurrentTorque",
            "Torque2",
        ]
    },
    **{
        t: f"{_ROT}.Sensors.{t}"
        for t in [
            "AngleSensor",
            "SpeedSensor",
            "AccSensor",
            "RelAngleSensor",
            "RelSpeedSensor",
            "RelAccSensor",
            "TorqueSensor",
            "PowerSensor",
            "MultiSensor",
        ]
    },
    # the translational types are named Translational.<MSL name> (Translational.Fixed)
    **{
        f"Translational.{t}": f"{_TRANS}.Components.{t}"
        for t in [
            "Mass",
            "Fixed",
            "Spring",
            "Damper",
            "SpringDamper",
            "ElastoGap",
            "Rod",
            "Brake",
            "SupportFriction",
            "MassWithStopAndFriction",
            "GeneralForceToPositionAdaptor",
            "GeneralPositionToForceAdaptor",
        ]
    },
    **{
        f"Translational.{t}": f"{_TRANS}.Sources.{t}"
        for t in ["Force", "ConstantForce", "LinearSpeedDependentForce", "QuadraticSpeedDependentForce"]
    },
    **{f"Translational.{t}": f"{_TRANS}.Components.{t}" for t in ["Vehicle", "RollingResistance"]},
    **{
        f"Translational.{t}": f"{_TRANS}.Sources.{t}"
        for t in [
            "Position",
            "Speed",
            "Accelerate",
            "Move",
            "Force2",
            "ForceStep",
            "SignForce",
            "EddyCurrentForce",
        ]
    },
    **{
        f"Translational.{t}": f"{_TRANS}.Sensors.{t}"
        for t in [
            "PositionSensor",
            "SpeedSensor",
            "AccSensor",
            "ForceSensor",
            "PowerSensor",
            "MultiSensor",
            "RelPositionSensor",
            "RelSpeedSensor",
            "RelAccSensor",
        ]
    },
    **{t: f"Modelica.Blocks.Sources.{t}" for t in ["Constant", "Step", "Ramp", "Sine", "Pulse", "TimeTable"]},
    **{t: f"Modelica.Blocks.Math.{t}" for t in ["Product", "Feedback", "Add", "Gain", "Abs"]},
    "CombiTable1Ds": "Modelica.Blocks.Tables.CombiTable1Ds",
    **{
        t: f"{_HEAT}.Components.{t}"
        for t in ["HeatCapacitor", "ThermalConductor", "Convection", "BodyRadiation"]
    },
    "FixedTemperature": f"{_HEAT}.Sources.FixedTemperature",
    "Celsius.FixedTemperature": f"{_HEAT}.Celsius.FixedTemperature",
    # stiction's own components, not MSL's: a class in the Stiction namespace, which only
    # stiction's importer maps back (other tools will not know it; docs/modelica.md)
    **{t: f"Stiction.Components.{t}" for t in OWN_COMPONENTS},
}
# MSL class -> stiction type
TYPE_OF: dict[str, str] = {msl: t for t, msl in MSL_CLASSES.items()}
TYPE_OF["Modelica.Blocks.Sources.CombiTimeTable"] = "CombiTimeTable"  # read as a TimeTable
# Fade (docs/fade.md): a friction element with any of these parameters is beyond the MSL and
# exports as the Stiction class of the same name (MSL's class plus these parameters), which
# only stiction's importer maps back
FADE_PARAMETERS = ("mu_T", "peak_T", "mu_fn", "mu_table")
FADE_CLASSES: dict[str, str] = {
    "Brake": "Stiction.Components.Brake",
    "Clutch": "Stiction.Components.Clutch",
    "OneWayClutch": "Stiction.Components.OneWayClutch",
    "Translational.Brake": "Stiction.Components.Translational.Brake",
}
TYPE_OF.update({cls: t for t, cls in FADE_CLASSES.items()})

# MSL 3.2.x -> 4.x (MSL's ConvertModelica_from_3.2.3_to_4.0.0 script)
_PACKAGE_RENAMES = {  # the more specific first
    "Modelica.SIunits.Conversions": "Modelica.Units.Conversions",
    "Modelica.SIunits": "Modelica.Units.SI",
}
PARAMETER_RENAMES: dict[str, dict[str, str]] = {
    "Sine": {"freqHz": "f"},
    "Brake": {"mue_pos": "mu_pos"},
    "Clutch": {"mue_pos": "mu_pos"},
    "OneWayClutch": {"mue_pos": "mu_pos"},
}
# The connectors a user's class declares as its interface: MSL class -> kind of port
CONNECTOR_KINDS: dict[str, str] = {
    f"{_ROT}.Interfaces.Flange_a": "flange",
    f"{_ROT}.Interfaces.Flange_b": "flange",
    f"{_ROT}.Interfaces.Support": "flange",
    f"{_TRANS}.Interfaces.Flange_a": "translational flange",
    f"{_TRANS}.Interfaces.Flange_b": "translational flange",
    f"{_TRANS}.Interfaces.Support": "translational flange",
    "Modelica.Blocks.Interfaces.RealInput": "signal input",
    "Modelica.Blocks.Interfaces.RealOutput": "signal output",
    f"{_HEAT}.Interfaces.HeatPort_a": "heat port",
    f"{_HEAT}.Interfaces.HeatPort_b": "heat port",
}
_UNIT_PACKAGES = ("Modelica.Units.SI.", "Modelica.Units.NonSI.")
_ENUMERATIONS = ("Regularization", "Smoothness", "Extrapolation", "TimeEvents", "StateSelect", "Init")
_PACKAGES = frozenset(
    ".".join(name.split(".")[:i])
    for name in [
        *TYPE_OF,
        *CONNECTOR_KINDS,
        *CONSTANTS,
        *PARAMETER_FUNCTIONS,
        "Modelica.Units.SI.X",
        "Modelica.Units.NonSI.X",
        "Modelica.Icons.X",
        "Modelica.Constants.X",
        "Modelica.Electrical.Machines.Thermal.Constants.X",
        "Modelica.Math.X",
        "Modelica.Units.Conversions.X",
        f"{_ROT}.Types.X",
        "Modelica.Blocks.Types.X",
    ]
    for i in range(1, name.count(".") + 1)
)
_BUILTIN_TYPES = ("Real", "Integer", "Boolean", "String")


def is_unit_type(name: str) -> bool:
    """``Modelica.Units.SI.Inertia`` and friends: a Real with a unit."""
    return name.startswith(_UNIT_PACKAGES)


def is_icon(name: str) -> bool:
    """``Modelica.Icons.Example``: only a picture, ignored."""
    return name.startswith("Modelica.Icons.")


def is_enumeration(name: str) -> bool:
    """``Modelica.Mechanics.Rotational.Types.Regularization.Linear`` and the like."""
    parts = name.split(".")
    return len(parts) >= 2 and parts[-2] in _ENUMERATIONS


def _renamed(name: str) -> str:
    for old, new in _PACKAGE_RENAMES.items():
        if name == old or name.startswith(old + "."):
            return new + name[len(old) :]
    return name


def _known(name: str) -> bool:
    return (
        name in TYPE_OF
        or name in CONNECTOR_KINDS
        or name in CONSTANTS
        or name in _PACKAGES
        or name in PARAMETER_FUNCTIONS
        or is_unit_type(name)
        or is_enumeration(name)
    )


class Scope:
    """Where names of one model are looked up: its enclosing packages and its imports."""

    def __init__(self, enclosing: str, imports: list[Import], local_classes: dict[str, str]) -> None:
        # enclosing packages, innermost first: "A.B.C" -> ["A.B.C", "A.B", "A"]
        parts = enclosing.split(".") if enclosing else []
        self.prefixes = [".".join(parts[:i]) for i in range(len(parts), 0, -1)]
        self.local_classes = local_classes  # name -> qualified name of classes in this file
        self.aliases: dict[str, str] = {}
        self.wildcards: list[str] = []
        for imp in imports:
            target = _renamed(imp.target)
            if imp.wildcard:
                self.wildcards.append(target)
            else:
                self.aliases[imp.alias or target.rsplit(".", 1)[-1]] = target
        if enclosing.split(".")[0] == "Modelica":  # MSL's packages import SI themselves
            self.aliases.setdefault("SI", "Modelica.Units.SI")
        self._resolved: dict[str, str] = {}  # a model names few classes, each many times

    def resolve(self, name: str, pos: Pos, what: str = "class") -> str:
        """The fully qualified name ``name`` denotes here (MSL 3.2 names renamed)."""
        full = self._resolved.get(name)
        if full is None:
            full = self._resolved[name] = self._lookup(name, pos, what)
        return full

    def _lookup(self, name: str, pos: Pos, what: str) -> str:
        if name in _BUILTIN_TYPES:
            return name
        first, _, rest = name.partition(".")
        tail = f".{rest}" if rest else ""
        if first in self.local_classes:
            return self.local_classes[first] + tail
        if first in self.aliases:
            return _renamed(self.aliases[first] + tail)
        for package in self.wildcards:
            if _known(f"{package}.{first}"):
                return _renamed(f"{package}.{name}")
        for prefix in self.prefixes:
            candidate = _renamed(f"{prefix}.{name}")
            if _known(f"{_renamed(prefix)}.{first}") or candidate in TYPE_OF:
                return candidate
        full = _renamed(name)
        if first == "Modelica" or _known(full):
            return full
        raise ModelicaError(
            pos, f"unknown {what} '{name}': not found through the imports or enclosing packages"
        )
