"""Variant tables: ``grid`` (every combination) and ``sample`` (Latin hypercube or random draws)."""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps

if TYPE_CHECKING:
    import pandas


__all__ = ["grid", "sample"]


def grid(axes: Mapping[str, Sequence[Any]] | None = None, **more: Sequence[Any]) -> pandas.DataFrame:
    """Every combination of the values of each axis (full factorial), one column per name.

    Names with dots go in ``axes``: ``grid({"clutch1.fn_max": [10, 20], "sin1.f": [1, 2]})``;
    experiment settings may also be keywords (``StopTime=[1, 2]``).
    """
    pd = _deps.pandas

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
    pd = _deps.pandas

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
