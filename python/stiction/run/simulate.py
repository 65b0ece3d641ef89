"""What ``Model.simulate`` hands off to: one run of a model with overrides, as a ``Result``."""

from __future__ import annotations

import copy
import functools
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from stiction.model.components import si_overrides
from stiction.model.model import numbers_read, parameter_values
from stiction.model.parameters import evaluate_parameters, expand_parameters
from stiction.model.runinfo import RunInfo
from stiction.results.result import Result
from stiction.run.compiled import merge_overrides, records_all

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["simulate"]


# The parameters repeat Model.simulate's on purpose: the method is the documented face (help(),
# IDEs) and stays one line; this is where the work is.
def simulate(
    model: Model,
    StartTime: float | None = None,  # MSL experiment names, hence capitalised
    StopTime: float | None = None,
    Interval: float | None = None,
    Tolerance: float | None = None,
    Solver: str | None = None,
    params: Mapping[str, Any] | None = None,
    record: str = "states",
) -> Result:
    """Run ``model`` once with these overrides (see ``Model.simulate``); the model is unchanged."""
    all_variables = records_all(record)
    given: dict[str, Any] = {"StartTime": StartTime, "StopTime": StopTime, "Interval": Interval}
    given |= {"Tolerance": Tolerance, "Solver": Solver}
    merged = merge_overrides(params, given)
    lazy = model._as_loaded() if all(map(_plain_override, merged.items())) else None
    if lazy is not None:
        # a loaded file as it stands, numbers overriding (none of them needs the model: no
        # unit, no top-level parameter): nothing of it made (see stiction/model/loaded.py)
        text, overrides, types = lazy.engine_text, merged, lazy.types
    else:
        text, overrides, known = _text_and_overrides(model, merged)
        types = model.types()
    raw = model._compile(text)._variant(overrides).simulate(record_all=all_variables)
    experiment = {k: float(v) for k, v in given.items() if v is not None and k != "Solver"}
    info = RunInfo(text, str(model.base_dir), experiment, Solver, types)
    result = Result.from_core(raw, name=model.name, info=info)
    if lazy is not None:  # the file's values, read from it when first asked for
        result.parameters = lazy.parameter_values
        return result
    # the values when first read (a model of thousands of components took 10 ms to list them),
    # of the model as it is now: a parameter changed in place after the run is not this run's
    if known is not None:
        result.parameters = functools.partial(dict, known)
    else:
        params = {n: dict(c.params) for n, c in model.components.items()}
        result.parameters = functools.partial(parameter_values, copy.deepcopy(model.parameters), params)
    return result


def _plain_override(item: tuple[str, Any]) -> bool:
    """An override a loaded file's run takes as it is: a number or Boolean (or the solver's
    name), nothing to convert or to evaluate."""
    name, value = item
    return type(value) in (int, float, bool) or (name == "Solver" and type(value) is str)


def _text_and_overrides(
    model: Model, merged: dict[str, Any]
) -> tuple[str, dict[str, Any], dict[str, float] | None]:
    """The engine text of ``model``, the run's overrides with their units converted and the
    top-level parameters among them expanded into the component values they imply, and the
    model's parameter values if they are known already."""
    overrides = si_overrides(model.components, merged)  # "100 rpm"
    text, known = model._derived_of(values=False)
    top = {k: overrides[k] for k in model.parameters if k in overrides}
    expanded = expand_parameters(model.parameters, model.components, overrides)
    if top and model.variables:  # the derived variables read this run's top-level values
        expanded |= numbers_read(model.variables, evaluate_parameters({**model.parameters, **top}))
    return text, expanded, known
