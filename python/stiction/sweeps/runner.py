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

import os
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps
from stiction.errors import ModelError
from stiction.model.components import si_overrides
from stiction.model.model import Model, numbers_read
from stiction.model.parameters import evaluate_parameters, expand_parameters, is_table
from stiction.run.compiled import CompiledModel
from stiction.sweeps.result import SweepResult, SweepTable
from stiction.sweeps.store import PartStore
from stiction.sweeps.variants import grid, sample

if TYPE_CHECKING:
    import pandas

__all__ = ["SweepResult", "grid", "run_batch", "sample", "sweep"]


def _frame(variants: Any) -> pandas.DataFrame:
    pd = _deps.pandas

    frame = variants if isinstance(variants, pd.DataFrame) else pd.DataFrame(dict(variants))
    return frame.reset_index(drop=True)


def _columns(frame: pandas.DataFrame, rows: np.ndarray) -> dict[str, list[Any]]:
    """The overrides of some variants as plain columns (one list per name), built per batch
    so that no per-variant Python object outlives its batch."""
    return {str(name): frame[name].to_numpy()[rows].tolist() for name in frame.columns}


def _in_si(model: Model, frame: pandas.DataFrame) -> pandas.DataFrame:
    """The variants with their quantities in SI (``"100 rpm"`` → 10.47 for ``J1.w``), each
    column converted once, before any batch; table cells that are expressions are kept as
    text, evaluated per variant (``_expanded``)."""
    for name in frame.columns:
        values = frame[name].tolist()
        if all(type(v) in (float, int, bool) for v in values):
            continue
        converted = [si_overrides(model.components, {str(name): v})[str(name)] for v in values]
        frame[name] = converted if any(is_table(v) for v in converted) else _numbers(converted)
    return frame


def _numbers(values: list[Any]) -> Any:
    """A column of numbers as floats (a column of text is left as it is, for the core to name)."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return values


def _table_expressions(frame: pandas.DataFrame) -> bool:
    """Whether a column holds a table with an expression cell (evaluated per variant)."""
    return any(
        is_table(v) and any(type(c) is str for row in v for c in row)
        for name in frame.columns
        if frame[name].dtype == object
        for v in frame[name]
    )


def _expanded(model: Model, columns: dict[str, list[Any]]) -> list[dict[str, Any]]:
    """Variants of top-level parameters (``T2``) as the component values they imply (and
    the values the derived variables read, where they read one)."""
    names = list(columns)
    read = bool(model.variables) and any(n in model.parameters for n in names)
    variants = []
    for row in zip(*columns.values(), strict=True):
        given = dict(zip(names, row, strict=True))
        variant = expand_parameters(model.parameters, model.components, given)
        if read:
            top = {k: v for k, v in given.items() if k in model.parameters}
            variant |= numbers_read(model.variables, evaluate_parameters({**model.parameters, **top}))
        variants.append(variant)
    return variants


class _Batch:
    """The variants of one unit of work: their indices and their overrides."""

    def __init__(self, rows: np.ndarray, variants: dict[str, list[Any]] | list[dict[str, Any]]) -> None:
        self.rows = rows
        self.variants = variants


def _batches(frame: pandas.DataFrame, todo: np.ndarray, size: int, model: Any) -> Iterator[_Batch]:
    expand = isinstance(model, Model) and (bool(model.parameters) or _table_expressions(frame))
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
    (a top-level parameter of ``model``, e.g. ``T2``, recomputes what depends on it; a
    quantity such as ``"100 rpm"`` is converted to the parameter's unit; a table may have
    expression cells, ``[[0, "mu0"], [100, "0.9*mu0"]]``).
    ``outputs``: variables kept as trajectories on the output grid. ``workers``: threads
    per process (None: every core locally, one per Dask task; 1: serial). ``client``: a
    ``distributed.Client``. ``out``: a folder for Parquet parts (resumable). ``progress``:
    a tqdm bar.
    """
    compiled = model.compile() if isinstance(model, Model) else model
    metrics, outputs = [str(m) for m in metrics], [str(o) for o in outputs]
    frame = _frame(variants)
    described = model if isinstance(model, Model) else Model.loads(compiled.text, compiled.base_dir)
    for name in frame.columns:  # a wrong name is the caller's mistake, not each variant's
        described.check_name(str(name), "sweep")
    frame = _in_si(described, frame)
    if outputs and any(k in ("StartTime", "StopTime", "Interval") for k in frame.columns):
        raise ModelError(
            "trajectories need one output grid: do not vary StartTime, StopTime or Interval with outputs="
        )
    compiled._core.check_plan(metrics, outputs)
    table = SweepTable(len(frame), metrics, outputs, len(compiled._core.grid()))
    store = PartStore(out, compiled, frame, metrics, outputs) if out is not None else None
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
    as_completed = _deps.distributed.as_completed

    shared = client.scatter(compiled, broadcast=True, hash=False)
    futures = {
        client.submit(run_batch, shared, b.variants, metrics, outputs, workers or 1, pure=False): b.rows
        for b in batches
    }
    for future in as_completed(futures):
        yield futures[future], future.result()
        future.release()


def _progress(total: int, initial: int, enabled: bool) -> Any:
    tqdm = _deps.tqdm_auto.tqdm

    return tqdm(total=total, initial=initial, disable=not enabled, unit="variant", desc="sweep")
