"""``SweepResult``: a sweep's table (overrides, metrics, status, wall time), its trajectories and
plots; and the table a running sweep fills batch by batch."""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps

if TYPE_CHECKING:
    import pandas

    from stiction.run.compiled import CompiledModel


__all__ = ["SweepResult", "SweepTable"]


class SweepResult:
    """The outcome of a sweep: ``table`` (pandas), ``trajectories`` and their ``time``."""

    def __init__(
        self, table: pandas.DataFrame, trajectories: dict[str, np.ndarray], time: np.ndarray
    ) -> None:
        """Wrap the table and the kept trajectories (variants × ``len(time)`` each)."""
        self.table = table
        self.trajectories = trajectories
        self.time = time

    def __repr__(self) -> str:
        ok = int((self.table["status"] == "ok").sum())
        return f"<SweepResult: {len(self.table)} variants, {ok} ok>"

    def to_parquet(self, path: str | os.PathLike[str]) -> None:
        """Write the table (trajectories as list columns) to a Parquet file."""
        table = self.table.copy()
        for name, values in self.trajectories.items():
            table[f"trajectory:{name}"] = list(values)
        _table_for_arrow(table).to_parquet(path, index=False)

    def plot(self, x: str, y: str, hue: str | None = None, ax: Any = None) -> Any:
        """``y`` against ``x`` (one line per ``hue`` value); a heat map when the table is a
        2-D grid of ``x`` × ``hue`` and ``hue`` is given as ``"heatmap"``-style grid axis."""
        plt = _deps.pyplot

        if ax is None:
            _, ax = plt.subplots()
        ok = self.table[self.table["status"] == "ok"]
        if hue is not None and _is_grid(ok, x, hue):
            pivot = ok.pivot_table(index=hue, columns=x, values=y)
            mesh = ax.pcolormesh(pivot.columns, pivot.index, pivot.values, shading="nearest")
            ax.figure.colorbar(mesh, ax=ax, label=y)
            ax.set_ylabel(hue)
        elif hue is not None:
            for value, group in ok.groupby(hue):
                group = group.sort_values(x)
                ax.plot(group[x], group[y], marker="o", label=f"{hue} = {value}")
            ax.legend()
            ax.set_ylabel(y)
        else:
            ax.scatter(ok[x], ok[y], s=12)
            ax.set_ylabel(y)
        ax.set_xlabel(x)
        return ax


def _is_grid(table: pandas.DataFrame, x: str, hue: str) -> bool:
    nx, nh = table[x].nunique(), table[hue].nunique()
    return nx > 2 and nh > 2 and len(table) == nx * nh


def _table_for_arrow(table: pandas.DataFrame) -> pandas.DataFrame:
    """Object columns holding tables (lists) are written as their text (Parquet needs one type)."""
    table = table.copy()
    for column in table.columns:
        if table[column].dtype == object and not column.startswith("trajectory:"):
            values = table[column]
            if any(isinstance(v, list | tuple) for v in values):
                table[column] = [json.dumps(v) for v in values]
    return table


class SweepTable:
    """The sweep's results, preallocated: one NumPy column per metric (and ``wall_s``),
    filled batch by batch and handed to pandas without a copy."""

    def __init__(self, n: int, metrics: list[str], outputs: list[str], points: int) -> None:
        self.metrics, self.outputs = metrics, outputs
        self.values = {name: np.full(n, np.nan) for name in metrics}
        self.trajectories = {name: np.full((n, points), np.nan) for name in outputs}
        self.errors = np.full(n, None, dtype=object)
        self.wall = np.zeros(n)
        self.done = np.zeros(n, dtype=bool)

    def fill(self, rows: np.ndarray, part: Any) -> None:
        """Enter one finished batch: ``rows`` are its variants' indices."""
        values, trajectories, errors, wall = part
        rows = np.asarray(rows, dtype=np.intp)
        for m, column in enumerate(self.values.values()):
            column[rows] = values[:, m]
        for name, trajectory in zip(self.outputs, trajectories, strict=True):
            self.trajectories[name][rows] = trajectory
        self.errors[rows] = list(errors)
        self.wall[rows] = wall
        self.done[rows] = True

    def result(self, compiled: CompiledModel, frame: pandas.DataFrame) -> SweepResult:
        """The ``SweepResult``: the overrides, the metrics, ``status`` and ``wall_s``."""
        pd = _deps.pandas

        if not self.done.all():
            raise RuntimeError(f"internal: {int((~self.done).sum())} variants have no result")
        # one shared "ok", set elementwise (a NumPy string per row would be a Python object
        # per variant)
        self.errors[self.errors == None] = "ok"
        results = pd.DataFrame(
            {**self.values, "status": pd.Series(self.errors, dtype="str"), "wall_s": self.wall},
            copy=False,
        )
        table = pd.concat([frame, results], axis=1)
        time = np.asarray(compiled._core.grid(), dtype=float)
        return SweepResult(table, self.trajectories, time)
