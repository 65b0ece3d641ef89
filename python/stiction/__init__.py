"""stiction: rotational drivetrains with exact Coulomb friction, MSL semantics.

Build a model from components (``Model``, ``Inertia``, ``Brake`` …) or load a TOML
model file, run it (``Model.simulate`` → ``Result``), and check results against MSL
references (``compare``).
"""

from __future__ import annotations

from typing import Any as _Any

from .compare import CompareReport, compare
from .compiled import CompiledModel
from .components import (
    Add,
    BearingFriction,
    Brake,
    Clutch,
    Component,
    Constant,
    ConstantSpeed,
    ConstantTorque,
    Convection,
    Damper,
    ElastoBacklash,
    Feedback,
    Fixed,
    FixedTemperature,
    Gain,
    HeatCapacitor,
    IdealGear,
    IdealPlanetary,
    Inertia,
    InverseSpeedDependentTorque,
    LinearSpeedDependentTorque,
    LossyGear,
    OneWayClutch,
    Product,
    Pulse,
    QuadraticSpeedDependentTorque,
    Ramp,
    SignTorque,
    Sine,
    Spring,
    SpringDamper,
    Step,
    ThermalConductor,
    TimeTable,
    Torque,
    TorqueStep,
)
from .errors import (
    ChatteringError,
    EventIterationError,
    IntegratorError,
    LimitExceededError,
    ModelError,
    NonFiniteStateError,
    SimulationCancelled,
    SimulationError,
    SingularSystemError,
    StepLimitError,
    StictionError,
    UsageError,
)
from .model import Model
from .parameters import expr
from .result import Event, Result
from .simulation import CancelHandle, Simulation, SimulationState
from .sweeps import SweepResult, grid, sample, sweep

try:
    from importlib.metadata import PackageNotFoundError, version

    __version__ = version("stiction")
except PackageNotFoundError:  # running from a source tree without installing
    __version__ = "0+unknown"

__all__ = [
    "Add",
    "BearingFriction",
    "Brake",
    "CancelHandle",
    "ChatteringError",
    "Clutch",
    "CompareReport",
    "CompiledModel",
    "Component",
    "Constant",
    "ConstantSpeed",
    "ConstantTorque",
    "Convection",
    "Damper",
    "ElastoBacklash",
    "Event",
    "EventIterationError",
    "Feedback",
    "Fixed",
    "FixedTemperature",
    "Gain",
    "HeatCapacitor",
    "IdealGear",
    "IdealPlanetary",
    "Inertia",
    "IntegratorError",
    "InverseSpeedDependentTorque",
    "LimitExceededError",
    "LinearSpeedDependentTorque",
    "LossyGear",
    "Model",
    "ModelError",
    "NonFiniteStateError",
    "OneWayClutch",
    "Product",
    "Pulse",
    "QuadraticSpeedDependentTorque",
    "Ramp",
    "Result",
    "SignTorque",
    "Simulation",
    "SimulationCancelled",
    "SimulationError",
    "SimulationState",
    "Sine",
    "SingularSystemError",
    "Spring",
    "SpringDamper",
    "Step",
    "StepLimitError",
    "StictionError",
    "SweepResult",
    "ThermalConductor",
    "TimeTable",
    "Torque",
    "TorqueStep",
    "UsageError",
    "compare",
    "expr",
    "grid",
    "sample",
    "sweep",
]


def __getattr__(name: str) -> _Any:
    """Make factories on demand for engine types without a class here.

    For example ``st.OneWayClutch`` when the engine knows that type.
    """
    from .components import factory

    if name.startswith("_"):  # submodule imports (e.g. `from . import _core`) must not land here
        raise AttributeError(f"module 'stiction' has no attribute {name!r}")
    try:
        return factory(name)
    except AttributeError:
        raise AttributeError(f"module 'stiction' has no attribute {name!r}") from None
