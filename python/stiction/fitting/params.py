"""What a fit estimates: parameters by MSL name with bounds, parsed and checked before any run.

``{"brake.peak": (1, 2)}`` (low, high; the start is the model's value), ``(low, start, high)``,
whole tables (``"brake.mu_pos"``: every cell of the value columns, the abscissas stay) or chosen
cells (``"brake.mu_pos[:, 2]"``, ``"brake.mu_pos[3, 2]"``, ``"brake.mu_T[2:4, 2]"``: 1-based
row and column, ranges inclusive as in Modelica, ``2:end`` to the last), top-level parameters
(``"T2"``) and start values (``"J.w"``). A 2-D table (``mu_table``, CombiTable2D's layout: row 1
and column 1 are the abscissae) fitted whole, or with ``:``, varies its coefficients only
(rows and columns from 2).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from stiction.errors import ModelError
from stiction.model.catalogue import describe
from stiction.model.model import Model
from stiction.model.modelfile import EXPERIMENT_KEYS
from stiction.model.names import split_last
from stiction.model.parameters import evaluate_parameters

__all__ = ["Param", "apply", "parse_params"]

_CELLS = re.compile(r"^(?P<name>[^\[\]]+)\[\s*(?P<row>[^,\]]+?)\s*,\s*(?P<col>[^,\]]+?)\s*\]$")
_FITTABLE = ("Real", "start value", "Integer")
#: tables in CombiTable2D's layout: row 1 and column 1 hold the abscissae, cell [1,1] is unused
TABLES_2D = ("mu_table",)
#: what the first column of a friction element's 1-D tables is, for the reasons a fit gives
_ABSCISSA = {
    "mu_pos": ("the slip speed", ""),
    "mu_T": ("the heat port's temperature", " K"),
    "peak_T": ("the heat port's temperature", " K"),
    "mu_fn": ("the normal force", " N"),
}


@dataclass
class Param:
    """One estimated number: its label (``brake.mu_pos[2,2]``), the override it changes
    (``brake.mu_pos``), the 0-based cell of a table or None, and its bounds and start."""

    label: str
    target: str
    cell: tuple[int, int] | None
    low: float
    start: float
    high: float


def _bounds(name: str, given: Any) -> tuple[float, float | None, float]:
    if not isinstance(given, tuple | list) or len(given) not in (2, 3):
        raise ModelError(
            f"fit parameter '{name}': bounds are (low, high) or (low, start, high), got {given!r}"
        )
    try:
        values = [float(v) for v in given]
    except (TypeError, ValueError):
        raise ModelError(f"fit parameter '{name}': bounds must be numbers, got {given!r}") from None
    low, high = values[0], values[-1]
    start = values[1] if len(values) == 3 else None
    if any(math.isnan(v) for v in values) or not low < high:
        raise ModelError(
            f"fit parameter '{name}': low must be below high, got low = {low:g}, high = {high:g}"
        )
    if start is not None and not low <= start <= high:
        raise ModelError(f"fit parameter '{name}': start {start:g} is not within [{low:g}, {high:g}]")
    return low, start, high


def _current(model: Model, target: str) -> tuple[Any, str]:
    """The value ``target`` has in ``model`` (its default when not set) and its kind; refuses
    what a fit cannot vary (experiment settings, Booleans, choices, structure)."""
    if target in EXPERIMENT_KEYS:
        raise ModelError(
            f"fit parameter '{target}': an experiment setting is not sweepable, not a parameter to fit"
        )
    model.check_name(target, "fit parameter")
    if target in model.parameters:
        value = evaluate_parameters(model.parameters).get(target)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ModelError(
                f"fit parameter '{target}': a top-level parameter that is not a number ({value!r})"
            )
        return float(value), "Real"
    comp, param = split_last(target)
    info = describe(model.components[comp].type).parameter(param)
    if not (info.kind in _FITTABLE or info.kind.startswith("table")) or info.choices:
        raise ModelError(
            f"fit parameter '{target}': component '{comp}' ({model.components[comp].type}): "
            f"'{param}' ({info.kind}) is not sweepable as a number: it decides the model's structure or is not a number"
        )
    value = model.components[comp].params.get(param, info.default)
    if value is None:
        raise ModelError(f"fit parameter '{target}': the model has no value for it (required parameter)")
    return value, info.kind


def _indices(text: str, size: int, what: str, name: str, first: int = 1) -> list[int]:
    """0-based indices of ``text``: ``:`` (from ``first``), ``i``, or an inclusive range
    ``i:j`` / ``i:end`` / ``i:``; 1-based and checked against ``size``."""
    if text == ":":
        return list(range(first - 1, size))
    low, sep, high = text.partition(":")
    try:
        i = int(low)
        j = i if not sep else size if high in ("", "end") else int(high)
    except ValueError:
        raise ModelError(
            f"fit parameter '{name}': {what} index must be ':', a number or a range i:j, got {text!r}"
        ) from None
    for k in (i, j):
        if not 1 <= k <= size:
            raise ModelError(f"fit parameter '{name}': {what} {k} is outside the table's 1..{size}")
    if j < i:
        raise ModelError(f"fit parameter '{name}': {what} range {text} is empty")
    return list(range(i - 1, j))


def _table_params(name: str, target: str, table: Any, rows: str, cols: str, bounds: tuple) -> list[Param]:
    try:
        cells = [[float(c) for c in row] for row in table]
    except (TypeError, ValueError):
        raise ModelError(
            f"fit parameter '{name}': the table has expression cells; fit the parameters they read"
        ) from None
    n_rows, n_cols = len(cells), len(cells[0]) if cells else 0
    first = 2 if split_last(target)[1] in TABLES_2D else 1  # a 2-D table's ':' skips the abscissae
    row_ids = _indices(rows, n_rows, "row", name, first)
    col_ids = _indices(cols, n_cols, "column", name, first) if cols != "values" else list(range(1, n_cols))
    low, start, high = bounds
    out = []
    for i in row_ids:
        for j in col_ids:
            value = cells[i][j] if start is None else start
            out.append(
                Param(f"{target}[{i + 1},{j + 1}]", target, (i, j), low, min(max(value, low), high), high)
            )
    return out


def parse_params(model: Model, params: Mapping[str, Any]) -> list[Param]:
    """The estimated numbers of ``params`` (see the module docstring), each name, bound and
    cell checked against ``model``: a ``ModelError`` naming the first bad one."""
    if not params:
        raise ModelError("fit: params is empty; name at least one parameter with its bounds")
    out: list[Param] = []
    for name, given in params.items():
        bounds = _bounds(name, given)
        match = _CELLS.match(name.replace(" ", ""))
        target = match.group("name") if match else name
        value, kind = _current(model, target)
        if kind.startswith("table"):
            rows, cols = (match.group("row"), match.group("col")) if match else (":", "values")
            out += _table_params(name, target, value, rows, cols, bounds)
        elif match:
            raise ModelError(
                f"fit parameter '{name}': '{target}' is not a table; name it without [row, column]"
            )
        else:
            low, start, high = bounds
            v = float(value) if start is None else start
            out.append(Param(target, target, None, low, min(max(v, low), high), high))
    labels = [p.label for p in out]
    for label in labels:
        if labels.count(label) > 1:
            raise ModelError(f"fit parameter '{label}' is named twice")
    return out


def apply(model: Model, params: list[Param], values: Any) -> dict[str, Any]:
    """The overrides setting ``values`` (one per ``params``): scalars by name, a table whole
    with its chosen cells replaced."""
    overrides: dict[str, Any] = {}
    for p, v in zip(params, values, strict=True):
        if p.cell is None:
            overrides[p.target] = float(v)
            continue
        if p.target not in overrides:
            table, _ = _current(model, p.target)
            overrides[p.target] = [[float(c) for c in row] for row in table]
        overrides[p.target][p.cell[0]][p.cell[1]] = float(v)
    return overrides


def _where(values: list[float], k: int, quantity: str, unit: str) -> str:
    """Where the table's point ``k`` (0-based, of ``values``) acts under linear interpolation
    held beyond the ends: between its neighbours, or beyond the one it has."""
    if len(values) == 1:
        return f"{quantity} is anywhere"
    if k == 0:
        return f"{quantity} is below {values[1]:g}{unit}"
    if k == len(values) - 1:
        return f"{quantity} is above {values[-2]:g}{unit}"
    return f"{quantity} is between {values[k - 1]:g}{unit} and {values[k + 1]:g}{unit}"


def silent_reason(model: Model, p: Param) -> str | None:
    """Why a friction table's cell can have no effect: the point acts only over a span of its
    abscissa (speed, temperature, normal force) the data may never reach. None for others."""
    if p.cell is None or p.target in model.parameters:
        return None
    comp, param = split_last(p.target)
    table, _ = _current(model, p.target)
    i, j = p.cell
    try:
        cells = [[float(c) for c in row] for row in table]
    except (TypeError, ValueError):
        return None
    if param in TABLES_2D and i > 0 and j > 0:
        speeds = [row[0] for row in cells[1:]]
        temps = cells[0][1:]
        at = f"{p.target} cell [{i + 1},{j + 1}] (speed {speeds[i - 1]:g}, T = {temps[j - 1]:g} K)"
        span = (
            f"{_where(speeds, i - 1, 'the slip speed', '')} and "
            f"{_where(temps, j - 1, 'the temperature', ' K')}"
        )
    elif param in _ABSCISSA and j > 0:
        quantity, unit = _ABSCISSA[param]
        xs = [row[0] for row in cells]
        at = f"{p.target} row {i + 1} ({xs[i]:g}{unit})"
        span = _where(xs, i, quantity, unit)
    else:
        return None
    return f"{at} acts only while {span} in '{comp}', and the data never get there"
