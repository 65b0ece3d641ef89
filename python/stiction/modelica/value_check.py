"""The engine's check of component values, for the importer: each component is checked
unconnected, in batches of distinct values, so a complaint can be placed at its modifier
(checking the assembled model costs seconds for thousands of components)."""

from __future__ import annotations

import functools
import math
import re
from typing import Any

from stiction.errors import ModelError
from stiction.model.components import Component, component_types

__all__ = ["always_valid", "batch_problem", "free_reals", "value_problems"]

# Signal inputs an unconnected component declares as model inputs (they need no source here).
_SIGNAL_INPUTS = ("f_normalized", "tau", "f", "u", "u1", "u2", "Gc")


def always_valid(stype: str, key: str, value: Any) -> bool:
    """Whether the catalogue declares ``key`` a Real without a range, so any finite number
    passes: 500 steps that differ only in ``startTime`` need one check, not 500."""
    if type(value) is not float or not math.isfinite(value):
        return False
    return key in free_reals().get(stype, ())


# Reals without a declared range that the engine still checks against others: a pulse
# starting long before the run would schedule millions of time events.
_CHECKED_TOGETHER = frozenset(
    {
        ("Pulse", "startTime"),
        # smax >= smin + L: the stops are checked against each other
        ("Translational.MassWithStopAndFriction", "smax"),
        ("Translational.MassWithStopAndFriction", "smin"),
    }
)


@functools.cache
def free_reals() -> dict[str, frozenset[str]]:
    """Per component type, the Real parameters any finite value passes (tested against the
    engine in test_modelica_errors.py)."""
    from stiction.model.catalogue import catalogue

    return {
        name: frozenset(
            p.name
            for p in info.parameters
            if p.kind == "Real" and p.range is None and (name, p.name) not in _CHECKED_TOGETHER
        )
        for name, info in catalogue().items()
    }


_BATCH = 32


def value_problems(items: list[tuple[str, str, dict[str, Any]]], base_dir: str) -> list[tuple[str, str]]:
    """(component, the engine's complaint about its parameters) for each bad one (the engine
    names one a check: a batch is checked again without it until it passes)."""
    found = []
    for start in range(0, len(items), _BATCH):
        batch = items[start : start + _BATCH]
        while batch:
            message = batch_problem(batch, base_dir)
            if message is None:
                break
            hit = re.match(r"component 'c(\d+)'", message)
            if hit and "parameter '" in message:
                name = batch.pop(int(hit.group(1)))[0]
                found.append((name, message.replace(hit.group(0), f"component '{name}'", 1)))
                continue
            for item in batch:  # a complaint about no parameter may hide one: check each alone
                alone = batch_problem([item], base_dir)
                if alone is not None and "parameter '" in alone:
                    found.append((item[0], alone.replace("component 'c0'", f"component '{item[0]}'", 1)))
            break
    return found


def batch_problem(items: list[tuple[str, str, dict[str, Any]]], base_dir: str) -> str | None:
    """The engine's complaint about unconnected components ``c0, c1, …``, or None."""
    from stiction.model.model import Model

    try:
        from stiction import _core
    except ImportError:
        return None
    model = Model("check", base_dir=base_dir)
    for k, (_, stype, params) in enumerate(items):
        try:
            model.components[f"c{k}"] = Component(stype, params)
        except ModelError as exc:  # a value out of its range once its expression is evaluated
            return str(exc).replace(f"{stype}: ", f"component 'c{k}' ({stype}): ", 1)
        for port in (component_types() or {}).get(stype, {}).get("ports", []):
            if port in _SIGNAL_INPUTS:
                model.inputs[f"c{k}.{port}"] = 0.0
    try:
        _core.check(model.engine_toml(), base_dir, motion=False)  # nothing is connected here
    except ModelError as exc:
        return str(exc)
    return None
