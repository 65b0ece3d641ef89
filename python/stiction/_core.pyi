"""Typed interface of the compiled engine (Rust, PyO3); stiction.model is its face."""

from typing import TypedDict

import numpy as np
import numpy.typing as npt

class ModelError(ValueError):
    """A model is invalid; the message names the component and the parameter or port."""

class SimulationOutput(TypedDict):
    names: list[str]  # names[0] == "time"
    data: npt.NDArray[np.float64]  # shape (rows, len(names)); event instants appear twice
    events: list[tuple[float, str, int, int, str]]  # (time, component, old_mode, new_mode, cause)
    stats: dict[str, float | int]  # steps, rhs_evals, events, wall_ms

class ComponentType(TypedDict):
    parameters: list[str]
    ports: list[str]

def simulate(model_toml: str, base_dir: str, overrides: dict[str, float]) -> SimulationOutput:
    """Run a model given as model-file text.

    ``overrides`` keys: StartTime, StopTime, Interval, Tolerance.
    """

def check(model_toml: str, base_dir: str) -> None:
    """Validate a model without running it; raises ModelError."""

def component_types() -> dict[str, ComponentType]:
    """Every component type the engine knows, with its parameter and port names."""
