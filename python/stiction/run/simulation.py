"""``Simulation``: a run that can be advanced in pieces, driven through inputs and read live.

This is what a co-simulation master, an FMU host or an interactive session needs: advance to
a time, set a model input (an event at that instant when its value jumps) or a tunable
parameter (the same kind of event), read any variable, save and restore the whole state.
Advancing in many small pieces gives exactly the result of one ``Model.simulate`` call: the
integrator is not restarted where a piece ends.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from stiction.errors import UsageError
from stiction.model.components import si_overrides
from stiction.model.names import split_last
from stiction.model.parameters import evaluate_parameters, is_table, resolve_params
from stiction.model.runinfo import RunInfo
from stiction.results.result import Result

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["CancelHandle", "Simulation", "SimulationState"]


class Simulation:
    """A resumable run of a model; see ``Model.simulation``.

    ``Simulation(model, StopTime=2.0)`` initializes the model (start values, MSL
    initialization) at its StartTime. Keyword arguments override the experiment.
    """

    def __init__(self, model: Model, Solver: str | None = None, **experiment: float) -> None:
        from stiction import _core

        overrides = {k: float(v) for k, v in experiment.items()}
        self._name = model.name
        self._parameters = evaluate_parameters(model.parameters)
        self._components = dict(model.components)  # their types: "2.5 kN" in set_parameter
        text, base = model.engine_toml(), str(model.base_dir)
        self._core = _core.Simulation(text, base, overrides, Solver)
        self._info = RunInfo(text, base, overrides, Solver, model.types())

    @property
    def time(self) -> float:
        """The time the run was advanced to."""
        return float(self._core.time)

    @property
    def finished(self) -> bool:
        """Whether the run reached its StopTime."""
        return bool(self._core.finished)

    def advance_to(self, t: float) -> None:
        """Advance to ``t`` (at most StopTime), handling every event on the way."""
        self._core.advance_to(float(t))

    def run(self, StopTime: float | None = None) -> None:  # MSL name, hence capitalised
        """Advance to ``StopTime`` (the experiment's when not given)."""
        self._core.advance_to(self._core.stop_time if StopTime is None else float(StopTime))

    @property
    def inputs(self) -> dict[str, float]:
        """The model inputs and their current values."""
        return dict(self._core.inputs())

    def set_input(self, name: str, value: float) -> None:
        """Set a model input from the current time on; a new value is an event now."""
        self._core.set_input(name, float(value))

    def reinit(self, name: str, value: float) -> None:
        """Set an inertia's speed (``"J.w"``) or a mass's (``"m.v"``) to ``value`` now.

        An event at this instant, like MSL's ``reinit`` driven from outside (a dynamometer's
        motor spinning the inertia up): the left row keeps the old speed, the modes are found
        anew. The kinetic energy it adds counts as work supplied to the model. A run re-driven
        so cannot be saved with ``state()``.
        """
        comp, var = split_last(name)
        if var not in ("w", "v") or not comp:
            raise UsageError(f"reinit '{name}': expected an inertia's speed 'J.w' or a mass's 'm.v'")
        self._core.reinit_speed(comp, float(value))

    def advance_until(self, name: str, level: float, t_max: float | None = None) -> bool:
        """Advance until variable ``name`` reaches ``level`` from the side it is on now, at
        most to ``t_max`` (StopTime when not given); returns whether it did.

        The run then stands exactly at the crossing: found on the integrator's dense output
        inside a step (to round-off), or at the state event where the variable lands on the
        level (a speed reaching 0 where a brake sticks).
        """
        t_max = self._core.stop_time if t_max is None else min(float(t_max), self._core.stop_time)
        return bool(self._core.advance_until(name, float(level), t_max))

    def set_recording(self, recording: bool) -> None:
        """Whether rows are kept for ``result()``: a long driven run (a dynamometer schedule)
        that reads its values live keeps none."""
        self._core.set_recording(bool(recording))

    def set_parameter(self, name: str, value: float | str | Sequence[Sequence[float]]) -> None:
        """Set a tunable parameter (``"brake.fn_max"``) from the current time on.

        The change is an event now, as an input's jump is: the row before it has the old
        value, the modes are found anew with the new one and the integrator restarts. A
        fixed parameter (a gear's ``ratio``, a ``startTime``, a Boolean, a start value; see
        ``Parameter.tunable`` in ``stiction.catalogue``) or a value out of range raises
        ``ModelError`` naming the component and the parameter, and the run goes on unchanged.
        """
        self.set_parameters({name: value})

    def set_parameters(self, values: Mapping[str, float | str | Sequence[Sequence[float]]]) -> None:
        """Set several tunable parameters (``{"brake.fn_max": 200.0, "spring.c": 1e4}``) from
        the current time on, at one event; a table (``lossy.lossTable``) is given whole.
        Nothing changes if one is refused (see ``set_parameter``). A value may be a quantity,
        ``"2.5 kN"``, converted to the parameter's unit."""
        values = si_overrides(self._components, dict(values))
        for name, value in values.items():  # a table with expression cells: this run's values
            if is_table(value):
                comp, key = split_last(name)
                values[name] = resolve_params(comp, {key: value}, self._parameters)[key]
        self._core.set_parameters(values)

    def get(self, name: str) -> float:
        """One variable at the current time, by its MSL name (``"J1.w"``)."""
        return float(self._core.get(name))

    def __getitem__(self, name: str) -> float:
        return self.get(name)

    def values(self) -> dict[str, float]:
        """Every variable at the current time, by name."""
        return dict(zip(self._core.names(), self._core.values()))

    def cancel_handle(self) -> CancelHandle:
        """A handle that cancels this run from another thread."""
        return CancelHandle(self._core.cancel_handle())

    def state(self) -> SimulationState:
        """The whole state at the current time (restore it with ``set_state``)."""
        return SimulationState(self._core.state())

    def set_state(self, state: SimulationState) -> None:
        """Continue from a saved state of this model, bit for bit as the run that saved it
        went on (its input events are replayed from the start, so this costs the run to the
        saved time)."""
        if not isinstance(state, SimulationState):
            raise UsageError(f"set_state expects a state from Simulation.state(), got {state!r}")
        self._core.set_state(state._core)

    def reset(self) -> None:
        """Back to the start, initialized anew."""
        self._core.reset()

    def result(self) -> Result:
        """The rows recorded so far, as a ``Result``; the simulation is closed."""
        return Result.from_core(
            self._core.result(),
            name=self._name,
            info=self._info,
        )

    def __repr__(self) -> str:
        return f"<Simulation {self._name!r} at t = {self.time}>"


class CancelHandle:
    """Cancels a running ``Simulation`` from any thread (it raises ``SimulationCancelled``)."""

    def __init__(self, core: object) -> None:
        self._core = core

    def cancel(self) -> None:
        """Stop the run after its current step."""
        self._core.cancel()  # type: ignore[attr-defined]


class SimulationState:
    """A saved state of a ``Simulation``: opaque, and bytes when asked (``to_bytes``), the
    core's one format, which an FMU's serialized state holds too. It pickles as those bytes,
    under its public name ``stiction.SimulationState``."""

    def __init__(self, core: object) -> None:
        self._core = core

    @property
    def time(self) -> float:
        """The time the state was saved at."""
        return float(self._core.time)  # type: ignore[attr-defined]

    def to_bytes(self) -> bytes:
        """The state as bytes: versioned, every value's bit pattern, a checksum."""
        return bytes(self._core.to_bytes())  # type: ignore[attr-defined]

    @classmethod
    def from_bytes(cls, data: bytes) -> SimulationState:
        """A state from ``to_bytes``; ``UsageError`` saying what is wrong with other bytes."""
        from stiction import _core

        return cls(_core.State.from_bytes(bytes(data)))

    def __reduce__(self) -> tuple[object, tuple[bytes]]:
        return (SimulationState.from_bytes, (self.to_bytes(),))


SimulationState.__module__ = "stiction"  # pickles by its public name, wherever it lives
