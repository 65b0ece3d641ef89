"""Typed interface of the compiled engine (Rust, PyO3); stiction.model is its face."""

from typing import Any, TypedDict, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "CancelHandle",
    "CompiledModel",
    "ModelError",
    "ParsedModel",
    "RawResult",
    "Simulation",
    "SimulationError",
    "State",
    "catalogue",
    "check",
    "check_parameters",
    "check_signal",
    "experiment",
    "initialization",
    "load_model",
    "parse_toml",
    "simulate",
    "time_event_sources",
    "tube",
    "write_csv",
    "write_mat",
]

class ModelError(ValueError):
    """A model is invalid; the message names the component and the parameter or port."""

class SimulationError(RuntimeError):
    """A valid model could not be simulated (singular system, no consistent mode, ...)."""

class _ParameterInfo(TypedDict):
    name: str
    kind: str
    default: Any
    required: bool
    unit: str
    description: str
    range: str | None

class _TypeInfo(TypedDict):
    name: str
    msl_class: str
    description: str
    parameters: list[_ParameterInfo]
    ports: list[tuple[str, str, str | None]]
    variables: list[tuple[str, str]]

@final
class RawResult:
    """One run: states on the output grid and both sides of every event.

    Variables are computed from the recorded rows when first asked for.
    """

    @property
    def names(self) -> list[str]:
        """Every variable by MSL name; names[0] == "time"."""
    @property
    def rows(self) -> int: ...
    @property
    def events(self) -> list[tuple[float, str, int, int, str]]:
        """(time, component, old_mode, new_mode, cause) per mode change."""
    @property
    def stats(self) -> dict[str, float | int]:
        """steps, rejected_steps, rhs_evals, events, state_events, time_events, ..."""
    @property
    def delivering(self) -> list[str]:
        """Switching elements whose loss power went negative beyond the event band at the end
        of some step: the runs whose energy audit is checked."""
    def column(self, name: str) -> npt.NDArray[np.float64]:
        """One variable over all rows; KeyError for an unknown name."""
    def table(self) -> npt.NDArray[np.float64]:
        """All variables, shape (rows, len(names)); event instants appear twice."""
    def is_direct(self, name: str) -> bool:
        """Whether ``column`` computes a variable alone, without each row's mode solve (an
        angle, a speed, a mode, a flag, the kinetic energy); any other is a column of ``table()``."""
    def held_rows(self, name: str) -> list[bool]:
        """Per row, whether a locked element holds the speed variable (its own relative speed,
        or a shaft it holds against ground): where ``first`` and ``time_of`` read it as 0."""
    def metric(self, text: str) -> float:
        """A metric of this run (``max(J1.w)``, ``time_of(clutch2.locked)``, ...), as a sweep computes it."""
    def audit(self) -> list[dict[str, Any]]:
        """The energy audit per element: one dict of ``ElementBalance``'s fields per component with flanges."""

def simulate(
    model_toml: str, base_dir: str = ".", overrides: dict[str, float] | None = None, solver: str | None = None
) -> RawResult:
    """Run a model given as model-file text.

    ``overrides`` keys: StartTime, StopTime, Interval, Tolerance; ``solver`` overrides Solver.
    """

def check_parameters(model_toml: str, base_dir: str = ".") -> None:
    """Check every component's parameters without assembling; raises ModelError."""

def time_event_sources(
    model_toml: str, base_dir: str, overrides: dict[str, float], times: list[float]
) -> list[list[str]]:
    """For each time, the components ("name (Type)") whose time event falls on it."""

def experiment(
    model_toml: str, base_dir: str = ".", overrides: dict[str, float] | None = None, solver: str | None = None
) -> dict[str, Any]:
    """The experiment settings a run uses, and under "defaults" those nobody gave."""

def initialization(model_toml: str, base_dir: str = ".") -> list[tuple[str, float, str, float]]:
    """(variable, start, "fixed" | "guessed" | "computed", initial value) per start value."""

def parse_toml(text: str) -> dict[str, Any] | None:
    """The TOML document as ``tomllib.loads`` gives it; None if invalid or holding a date (the
    caller asks ``tomllib`` then, for the message or the datetime)."""

@final
class ParsedModel:
    """A model file's engine description from ``load_model``; one compile takes it."""

def load_model(
    text: str, base_dir: str, name: str
) -> tuple[tuple[str | None, int, int, CompiledModel] | None, dict[str, Any] | None, ParsedModel | None]:
    """A model file parsed once: a plain one compiled (its own name, counts of components and
    connections, the compile), or ``parse_toml``'s document and, from the same parse, the
    engine's description (None if refused, or with top-level parameters or declarations)."""

def check(model_toml: str, base_dir: str = ".", motion: bool = True) -> None:
    """Validate a model without running it (with ``motion``: also that every shaft's motion is
    determined); raises ModelError."""

def catalogue() -> list[_TypeInfo]:
    """Every component type: MSL class, parameters, ports (name, kind, enabling Boolean), variables."""

@final
class State:
    """A saved simulation state (opaque; restore it with ``Simulation.set_state``).

    Pickles as its bytes, the core's saved-state format (the FMU's serialized states carry the
    same bytes).
    """

    @property
    def time(self) -> float:
        """The time the state was saved at."""
    def to_bytes(self) -> bytes:
        """The state as bytes: versioned, f64 bit patterns, a checksum."""
    @staticmethod
    def from_bytes(data: bytes) -> State:
        """The state in bytes from ``to_bytes``; UsageError if they are not valid."""
    def __reduce__(self) -> tuple[Any, tuple[bytes]]: ...

def tube(
    ref_time: npt.NDArray[np.float64],
    ref_values: npt.NDArray[np.float64],
    time: npt.NDArray[np.float64],
    tolerance: float,
    floor: float,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], float, float]:
    """The MSL tube around a reference at ``time``: ``(lower, upper, x, y)``, its edges and its
    half-sizes in time and value (``y >= floor``). ValueError if the reference has no rows or its
    arrays differ in length."""

def check_signal(
    ref_time: npt.NDArray[np.float64],
    ref_values: npt.NDArray[np.float64],
    time: npt.NDArray[np.float64],
    values: npt.NDArray[np.float64],
    tolerance: float,
    floor: float,
) -> tuple[float, float | None, int, float, float]:
    """One signal against the tube around its reference: ``(max_excess, worst_time,
    points_outside, x, y)``; max_excess in tube half-heights (0.0 when every point is inside, inf
    for a NaN), worst_time None when every point is inside."""

def write_csv(path: str, names: list[str], integer: list[bool], data: npt.NDArray[np.float64]) -> None:
    """Write ``data`` (rows x names, C-contiguous) as an MSL-style CSV; ``integer`` marks mode
    and flag columns. OSError as ``open`` raises it."""

def write_mat(
    path: str,
    names: list[str],
    descriptions: list[str],
    data: npt.NDArray[np.float64],
    parameters: list[tuple[str, str, float]],
) -> None:
    """Write ``data`` (rows x names, ``time`` first) and ``parameters`` (name, description, value)
    as a Dymola/OpenModelica result file (MATLAB v4)."""

@final
class CancelHandle:
    """Cancels a running ``Simulation`` from any thread."""

    def cancel(self) -> None: ...

@final
class Simulation:
    """A run advanced in pieces (``advance_to``), driven through its inputs and parameters."""

    def __new__(
        cls,
        model_toml: str,
        base_dir: str = ".",
        overrides: dict[str, float] | None = None,
        solver: str | None = None,
    ) -> Simulation: ...
    @property
    def time(self) -> float: ...
    @property
    def stop_time(self) -> float: ...
    @property
    def finished(self) -> bool: ...
    def advance_to(self, t: float) -> None: ...
    def inputs(self) -> list[tuple[str, float]]: ...
    def set_input(self, name: str, value: float) -> None: ...
    def reinit_speed(self, mass: str, w: float) -> None: ...
    def advance_until(self, name: str, level: float, t_max: float) -> bool: ...
    def set_recording(self, recording: bool) -> None: ...
    def set_parameters(self, values: dict[str, Any]) -> None: ...
    def names(self) -> list[str]: ...
    def values(self) -> list[float]: ...
    def get(self, name: str) -> float: ...
    def cancel_handle(self) -> CancelHandle: ...
    def state(self) -> State: ...
    def set_state(self, state: State) -> None: ...
    def reset(self) -> None: ...
    def result(self) -> RawResult: ...

@final
class CompiledModel:
    """A model compiled once; variants with other values are one build each."""

    def __new__(cls, model_toml: str, base_dir: str = ".") -> CompiledModel: ...
    @staticmethod
    def from_parsed(parsed: ParsedModel) -> CompiledModel | None:
        """The model ``load_model`` read (None when a compile took it already)."""
    def parameter_names(self) -> list[str]:
        """Every name a variant may set: ``component.parameter``, then the experiment settings."""
    def grid(self) -> list[float]:
        """The output grid's times (where sweep trajectories are kept)."""
    def variant(self, values: dict[str, Any] | None = None) -> CompiledModel:
        """A variant with these overrides (each checked now, naming component and parameter)."""
    def simulate(self, record_all: bool = False) -> RawResult: ...
    def check_plan(self, metrics: list[str], outputs: list[str]) -> None:
        """Checks metrics and outputs before a sweep (ModelError naming the bad one)."""
    def sweep(
        self,
        variants: dict[str, list[Any]] | list[dict[str, Any]],
        metrics: list[str],
        outputs: list[str],
        workers: int | None = None,
    ) -> tuple[
        npt.NDArray[np.float64], list[npt.NDArray[np.float64]], list[str | None], npt.NDArray[np.float64]
    ]:
        """``(metrics, trajectories, errors, wall_s)`` of every variant, run on ``workers`` threads."""
