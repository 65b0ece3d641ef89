"""The exceptions stiction raises, one class per kind of failure.

They are defined here, in Python, and the compiled core raises these very classes (it looks
them up by name), so ``except stiction.ModelError`` catches an error from either side::

    StictionError
    ├── ModelError (also a ValueError)          the model is invalid
    ├── UsageError (also a ValueError)          a call the running simulation cannot honour
    └── SimulationError (also a RuntimeError)   a valid model could not be simulated
        ├── SingularSystemError                 accelerations not determined in some mode
        ├── EventIterationError                 no consistent stick/slip state at an event
        ├── ChatteringError                     mode changes without end
        ├── StepLimitError                      more integration steps than any sane run needs
        ├── LimitExceededError                  a limit the user set (max_events, max_steps, timeout)
        ├── NonFiniteStateError                 the state became infinite or NaN
        ├── NegativeFrictionError               a friction table extrapolated below 0 in the run
        ├── WearLimitError                      a worn pad reached its thickness_min
        ├── IntegratorError                     the ODE integrator failed
        └── SimulationCancelled                 the run was cancelled

and one warning, ``EnergyWarning`` (a ``UserWarning``): a run whose energy audit finds a passive
element that delivered energy.
"""

from __future__ import annotations

__all__ = [
    "ChatteringError",
    "EnergyWarning",
    "EventIterationError",
    "IntegratorError",
    "LimitExceededError",
    "ModelError",
    "NegativeFrictionError",
    "NonFiniteStateError",
    "SimulationCancelled",
    "SimulationError",
    "SingularSystemError",
    "StepLimitError",
    "StictionError",
    "UsageError",
    "WearLimitError",
    "core_available",
]


class StictionError(Exception):
    """Base class of every error stiction raises on purpose."""


class ModelError(StictionError, ValueError):
    """The model is invalid; the message names the component and the parameter or port."""


class UsageError(StictionError, ValueError):
    """A request a running simulation cannot honour (unknown input or variable, a past time)."""


class SimulationError(StictionError, RuntimeError):
    """A valid model could not be simulated; the message says when and what failed."""


class SingularSystemError(SimulationError):
    """The accelerations are not determined in some mode (names the shafts without inertia)."""


class EventIterationError(SimulationError):
    """The event iteration found no consistent stick/slip state (names the elements)."""


class ChatteringError(SimulationError):
    """One element changes its mode again and again within a vanishing time window; the
    message names the element, the instant and the relation."""


class LimitExceededError(SimulationError):
    """The run reached a limit set in the experiment (``max_events``, ``max_steps``, ``timeout``)."""


class StepLimitError(SimulationError):
    """The run needed more integration steps than any sensible model does."""


class NonFiniteStateError(SimulationError):
    """The state became infinite or NaN (overflow, or a mode without a solution)."""


class NegativeFrictionError(SimulationError):
    """A friction table, continued linearly past its last row as MSL does, gave a negative
    coefficient (or torque) at the slip the run reached; the message names the element, the
    slip speed and the table. ``extrapolation = "HoldLastPoint"`` holds the last row's value
    instead."""


class WearLimitError(SimulationError):
    """A friction element's pad wore down to the ``thickness_min`` of its ``wear`` record; the
    message names the element and the instant (located as a state event)."""


class IntegratorError(SimulationError):
    """The ODE integrator failed (step size too small, nonlinear solver failures, …)."""


class SimulationCancelled(SimulationError):
    """The run was cancelled (``Simulation.cancel`` from another thread)."""


class EnergyWarning(UserWarning):
    """The energy audit of a run found a passive element that delivered energy (its balance
    does not close beyond the audit's bound): the result is physically wrong. The message names
    the element and the energy; ``Result.audit()`` has the details."""


for _cls in (
    StictionError,
    ModelError,
    UsageError,
    SimulationError,
    SingularSystemError,
    EventIterationError,
    ChatteringError,
    StepLimitError,
    NonFiniteStateError,
    NegativeFrictionError,
    WearLimitError,
    IntegratorError,
    SimulationCancelled,
    EnergyWarning,
):
    _cls.__module__ = "stiction"
del _cls


def core_available() -> bool:
    """Tell whether the compiled engine is importable (true in any installation)."""
    try:
        from stiction import _core  # noqa: F401
    except ModuleNotFoundError as exc:  # only "not built"; a broken build must still fail
        if exc.name != f"{__package__}._core":
            raise
        return False
    return True
