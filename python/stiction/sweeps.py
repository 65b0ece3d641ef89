"""Sweeps: thousands of variants of one model — design studies and Monte Carlo.

``sweep(model, variants, metrics)`` runs every variant (a row of overrides: parameters,
start values, experiment settings by name) in the core, on every core, and returns a
``SweepResult`` whose ``table`` has one row per variant: the overrides, the metrics, the
variant's ``status`` ("ok" or its error) and ``wall_s``. ``grid`` and ``sample`` build the
variants. With ``client=`` (a ``distributed.Client``) batches run on a Dask cluster; with
``out=`` finished rows are written as Parquet parts as they arrive, and the same call
again runs only the variants not done yet.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import os
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .compiled import CompiledModel
from .errors import ModelError
from .model import Model
from .parameters import expand_parameters

if TYPE_CHECKING:
    import pandas

__all__ = ["SweepResult", "grid", "sample", "sweep"]


def grid(axes: Mapping[str, Sequence[Any]] | None = None, **more: Sequence[Any]) -> pandas.DataFrame:
    """Every combination of the values of each axis (full factorial), one column per name.

    Names with dots go in ``axes``: ``grid({"clutch1.fn_max": [10, 20], "sin1.f": [1, 2]})``;
    experiment settings may also be keywords (``StopTime=[1, 2]``).
    """
    import pandas as pd

    columns = {**dict(axes or {}), **more}
    if not columns:
        raise ValueError("grid() needs at least one axis")
    rows = list(itertools.product(*(list(v) for v in columns.values())))
    return pd.DataFrame(rows, columns=list(columns))


def sample(
    n: int,
    seed: int = 0,
    dists: Mapping[str, Any] | None = None,
    *,
    method: str = "lhs",
    **more: Any,
) -> pandas.DataFrame:
    """``n`` random variants (Latin hypercube by default, or ``method="random"``).

    Each distribution is a range ``(low, high)`` (uniform), a list of values (each equally
    likely), or a frozen ``scipy.stats`` distribution (anything with ``ppf``).
    """
    import pandas as pd

    if n < 1:
        raise ValueError(f"n must be at least 1, got {n}")
    if method not in ("lhs", "random"):
        raise ValueError(f"method must be 'lhs' or 'random', got {method!r}")
    rng = np.random.default_rng(seed)
    columns: dict[str, Any] = {}
    for name, dist in {**dict(dists or {}), **more}.items():
        u = (rng.permutation(n) + rng.random(n)) / n if method == "lhs" else rng.random(n)
        columns[name] = _quantiles(name, dist, u)
    return pd.DataFrame(columns)


def _quantiles(name: str, dist: Any, u: np.ndarray) -> Any:
    if hasattr(dist, "ppf"):
        return np.asarray(dist.ppf(u), dtype=float)
    if isinstance(dist, tuple) and len(dist) == 2:
        low, high = float(dist[0]), float(dist[1])
        return low + u * (high - low)
    if isinstance(dist, list) and dist:
        return [dist[min(int(x * len(dist)), len(dist) - 1)] for x in u]
    raise ValueError(f"{name}: a distribution is (low, high), a list of values, or has ppf(); got {dist!r}")


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
        import matplotlib.pyplot as plt

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


def _frame(variants: Any) -> pandas.DataFrame:
    import pandas as pd

    frame = variants if isinstance(variants, pd.DataFrame) else pd.DataFrame(dict(variants))
    return frame.reset_index(drop=True)


def _columns(frame: pandas.DataFrame, rows: np.ndarray) -> dict[str, list[Any]]:
    """The overrides of some variants as plain columns (one list per name), built per batch
    so that no per-variant Python object outlives its batch."""
    return {str(name): frame[name].to_numpy()[rows].tolist() for name in frame.columns}


def _expanded(model: Model, columns: dict[str, list[Any]]) -> list[dict[str, Any]]:
    """Variants of top-level parameters (``T2``) as the component values they imply."""
    names = list(columns)
    return [
        expand_parameters(model.parameters, model.components, dict(zip(names, row, strict=True)))
        for row in zip(*columns.values(), strict=True)
    ]


class _Batch:
    """The variants of one unit of work: their indices and their overrides."""

    def __init__(self, rows: np.ndarray, variants: dict[str, list[Any]] | list[dict[str, Any]]) -> None:
        self.rows = rows
        self.variants = variants


def _batches(frame: pandas.DataFrame, todo: np.ndarray, size: int, model: Any) -> Iterator[_Batch]:
    expand = isinstance(model, Model) and bool(model.parameters)
    for start in range(0, len(todo), size):
        rows = todo[start : start + size]
        columns = _columns(frame, rows)
        yield _Batch(rows, _expanded(model, columns) if expand else columns)


def _batch_size(workers: int | None, client: Any) -> int:
    """Variants per batch. Each batch ends with threads idle while the last runs finish, so
    local batches are long (256 runs per thread); Dask tasks are shorter (64 runs per core
    here) so that the cluster's workers stay evenly loaded to the end."""
    cores = os.cpu_count() or 1
    return 64 * cores if client is not None else 256 * (workers or cores)


def run_batch(
    compiled: CompiledModel,
    variants: dict[str, list[Any]] | list[dict[str, Any]],
    metrics: list[str],
    outputs: list[str],
    workers: int | None = None,
) -> tuple[np.ndarray, list[np.ndarray], list[str | None], np.ndarray]:
    """Run some variants in the core (the unit of work locally and on a Dask worker).

    ``variants``: columns (``{name: [value per variant]}``) or a list of ``{name: value}``.
    Returns metrics (variants × metrics), trajectories (one variants × grid array per
    output), each variant's error or None, and its wall time in the core.
    """
    return compiled._core.sweep(variants, metrics, outputs, workers)


def sweep(
    model: Model | CompiledModel,
    variants: Any,
    metrics: Iterable[str],
    *,
    outputs: Iterable[str] = (),
    workers: int | None = None,
    client: Any = None,
    out: str | os.PathLike[str] | None = None,
    progress: bool = True,
    batch_size: int | None = None,
) -> SweepResult:
    """Run every variant of ``model`` and compute ``metrics`` (see the module docstring).

    ``variants``: a DataFrame or a dict of equal-length columns, one per override name
    (a top-level parameter of ``model``, e.g. ``T2``, recomputes what depends on it).
    ``outputs``: variables kept as trajectories on the output grid. ``workers``: threads
    per process (None: every core locally, one per Dask task; 1: serial). ``client``: a
    ``distributed.Client``. ``out``: a folder for Parquet parts (resumable). ``progress``:
    a tqdm bar.
    """
    compiled = model.compile() if isinstance(model, Model) else model
    metrics, outputs = [str(m) for m in metrics], [str(o) for o in outputs]
    frame = _frame(variants)
    if outputs and any(k in ("StartTime", "StopTime", "Interval") for k in frame.columns):
        raise ModelError(
            "trajectories need one output grid: do not vary StartTime, StopTime or Interval with outputs="
        )
    compiled._core.check_plan(metrics, outputs)
    table = _Table(len(frame), metrics, outputs, len(compiled._core.grid()))
    store = _PartStore(out, compiled, frame, metrics, outputs) if out is not None else None
    if store:
        store.load(table)
    todo = np.flatnonzero(~table.done)
    size = batch_size or _batch_size(workers, client)
    bar = _progress(len(frame), len(frame) - len(todo), progress)
    try:
        batches = _batches(frame, todo, size, model)
        for rows, part in _run(compiled, batches, metrics, outputs, workers, client):
            if store:
                store.write(rows, part)
            table.fill(rows, part)
            bar.update(len(rows))
    finally:
        bar.close()
    return table.result(compiled, frame)


def _run(
    compiled: CompiledModel,
    batches: Iterator[_Batch],
    metrics: list[str],
    outputs: list[str],
    workers: int | None,
    client: Any,
) -> Iterator[tuple[np.ndarray, Any]]:
    """Batches as they finish: (variant indices, what ``run_batch`` returned)."""
    if client is None:
        for batch in batches:
            yield batch.rows, run_batch(compiled, batch.variants, metrics, outputs, workers)
        return
    yield from _run_on_dask(client, compiled, batches, metrics, outputs, workers)


def _run_on_dask(
    client: Any,
    compiled: CompiledModel,
    batches: Iterator[_Batch],
    metrics: list[str],
    outputs: list[str],
    workers: int | None,
) -> Iterator[tuple[np.ndarray, Any]]:
    """Each batch a task. The model travels once to every worker (``scatter``), not with
    each task (where each would compile it again); a task's rayon threads default to one,
    since Dask's own workers and threads are the parallelism."""
    from distributed import as_completed

    shared = client.scatter(compiled, broadcast=True, hash=False)
    futures = {
        client.submit(run_batch, shared, b.variants, metrics, outputs, workers or 1, pure=False): b.rows
        for b in batches
    }
    for future in as_completed(futures):
        yield futures[future], future.result()
        future.release()


class _Table:
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
        import pandas as pd

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


def _progress(total: int, initial: int, enabled: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, disable=not enabled, unit="variant", desc="sweep")


class _PartStore:
    """Finished rows as Parquet parts in a folder, with a manifest naming the sweep."""

    def __init__(
        self,
        out: str | os.PathLike[str],
        compiled: CompiledModel,
        frame: pandas.DataFrame,
        metrics: list[str],
        outputs: list[str],
    ) -> None:
        self.dir = Path(out)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.metrics, self.outputs = metrics, outputs
        digest = hashlib.sha256()
        digest.update(compiled.text.encode())
        digest.update(frame.to_json().encode())
        digest.update(json.dumps([metrics, outputs]).encode())
        manifest = {
            "sweep": digest.hexdigest(),
            "variants": len(frame),
            "metrics": metrics,
            "outputs": outputs,
        }
        path = self.dir / "sweep.json"
        if path.exists() and json.loads(path.read_text())["sweep"] != manifest["sweep"]:
            raise ModelError(
                f"{self.dir} holds the parts of another sweep (model, variants or metrics differ)"
            )
        path.write_text(json.dumps(manifest, indent=1))

    def load(self, table: _Table) -> None:
        """Enter the rows of the parts written so far into ``table``."""
        import pyarrow.parquet as pq

        for part in sorted(self.dir.glob("part-*.parquet")):
            t = pq.read_table(part)
            rows = t.column("variant").to_numpy()
            values = np.column_stack([t.column(m).to_numpy() for m in self.metrics]).reshape(len(rows), -1)
            trajectories = [
                np.array(t.column(f"trajectory:{o}").to_pylist(), dtype=float) for o in self.outputs
            ]
            table.fill(
                rows, (values, trajectories, t.column("error").to_pylist(), t.column("wall_s").to_numpy())
            )

    def write(self, indices: np.ndarray, part: Any) -> None:
        """Write one finished batch (atomically: a part is whole or absent)."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        values, trajectories, status, wall = part
        columns: dict[str, Any] = {"variant": indices}
        for m, name in enumerate(self.metrics):
            columns[name] = values[:, m]
        columns["error"] = list(status)
        columns["wall_s"] = wall
        for o, name in enumerate(self.outputs):
            columns[f"trajectory:{name}"] = [list(row) for row in trajectories[o]]
        path = self.dir / f"part-{int(indices[0]):09d}.parquet"
        tmp = path.with_suffix(".tmp")
        pq.write_table(pa.table(columns), tmp)
        tmp.replace(path)
