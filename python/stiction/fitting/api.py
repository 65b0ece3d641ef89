"""``st.fit``: identify parameters of a model from measured traces.

Every input is checked before any run: the data (a time column, increasing times, the named
columns), the model names of outputs and inputs, each parameter (a sweepable number or table
cell of the model) and its bounds. Then either the linear path (``stiction.fitting.linear``) or the
output-error fit: ``scipy.optimize.least_squares`` (trust region reflective, within the
bounds, ``loss`` "linear" or a robust one such as "soft_l1") on residuals whose Jacobian
columns are variants of the compiled model run in parallel (``stiction.fitting.problem``), from
the given start and, with ``starts > 1``, from a Latin hypercube of further starts.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from stiction import _deps
from stiction.errors import ModelError
from stiction.fitting.data import fit_model, read_data
from stiction.fitting.linear import linear_plan, solve_linear
from stiction.fitting.params import Param, apply, parse_params, silent_reason
from stiction.fitting.problem import STEP, Problem
from stiction.fitting.result import FitResult
from stiction.fitting.stats import silent_columns, uncertainty
from stiction.model.model import Model

__all__ = ["fit"]

METHODS = ("auto", "linear", "output-error")
#: a forward difference's column is accurate to about its relative step, so a singular value
#: of the scaled Jacobian below that (against the largest) cannot be told from zero: a
#: combination of parameters the data do not tell apart (mu_pos against a mu_T with no fixed row)
SINGULAR_DIFFERENCES = STEP


def fit(
    model: Model | str | os.PathLike[str],
    data: Any,
    params: Mapping[str, Any],
    outputs: Mapping[str, str] | Sequence[str] | None = None,
    inputs: Mapping[str, str] | Sequence[str] | None = None,
    weights: Mapping[str, Any] | None = None,
    method: str = "auto",
    workers: int | None = None,
    progress: bool = True,
    *,
    loss: str = "linear",
    starts: int = 1,
    seed: int = 0,
) -> FitResult:
    """Estimate ``params`` of ``model`` from ``data``.

    ``data``: a DataFrame or a CSV/.mat/Parquet path with a ``time`` column. ``outputs``:
    ``{"model.variable": "column"}`` to match (a list: columns of the same names; None: every
    other column). ``inputs``: ``{"brake.f_normalized": "pressure"}``, columns that drive model
    inputs (through a TimeTable). ``params``: ``{name: (low, high)}`` or ``(low, start, high)``;
    scalars, tables (``"brake.mu_pos"``) or cells (``"brake.mu_pos[:, 2]"``,
    ``"brake.mu_T[2:end, 2]"``: 1-based, ranges inclusive), top-level parameters, start
    values. ``weights``: per output, a number or one per sample (default: one
    over the output's largest magnitude). ``method``: "auto" (linear where it applies),
    "linear" or "output-error". ``workers``: threads for the model runs. ``loss``: least
    squares' loss ("linear", "soft_l1", "huber", "cauchy", "arctan"). ``starts``: starts in
    all (Latin hypercube beyond the first), the best kept.
    """
    if method not in METHODS:
        raise ModelError(f"fit: method must be one of {', '.join(METHODS)}, got {method!r}")
    if isinstance(model, str | os.PathLike):
        model = Model.load(model)
    measured = read_data(data, outputs, inputs)
    plist = parse_params(model, params)
    if int(starts) < 1:
        raise ModelError(f"fit: starts must be at least 1, got {starts}")
    if method != "output-error" and not measured.inputs and not weights and loss == "linear":
        plan = linear_plan(model, plist, measured)
        if not isinstance(plan, str):
            x, stats, fitted_tau = solve_linear(plan, plist)
            name = f"{plan.comp}.tau"
            return _result(
                model, plist, x, stats, "linear", 0, measured.time, {name: plan.tau}, {name: fitted_tau}, ""
            )
        if method == "linear":
            raise ModelError(f"fit: the linear path does not apply: {plan}")
    elif method == "linear":
        raise ModelError(
            "fit: the linear path takes measured outputs only (no inputs, weights or robust loss)"
        )
    problem = Problem(fit_model(model, measured), plist, measured, weights, workers)
    return _output_error(model, plist, problem, loss, int(starts), seed, progress)


def _output_error(
    model: Model, plist: list[Param], problem: Problem, loss: str, starts: int, seed: int, progress: bool
) -> FitResult:

    low = np.array([p.low for p in plist])
    high = np.array([p.high for p in plist])
    points = [np.array([p.start for p in plist])]
    if starts > 1:
        lhs = _deps.scipy_stats.qmc.LatinHypercube(d=len(plist), seed=seed).random(starts - 1)
        points += list(low + lhs * (high - low))
    bar = _deps.tqdm_auto.tqdm(total=len(points), desc="fit", unit="start") if progress else None
    best = None
    try:
        for x0 in points:
            sol = _solve(problem, x0, low, high, loss)
            if best is None or sol.cost < best.cost:
                best = sol
            if bar is not None:
                bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    assert best is not None
    r = problem.residual(best.x)
    jac = problem.jacobian(best.x)  # the last one computed, when the best start was the last
    hints = {p.label: h for p in plist if (h := silent_reason(model, p))}
    stats = uncertainty([p.label for p in plist], best.x, jac, r, hints, singular=SINGULAR_DIFFERENCES)
    fitted_rows = r + problem.data
    measured, fitted, at = {}, {}, 0
    for name in problem.outputs:
        n = len(problem.measured.time)
        scale = problem.scales[name]
        measured[name] = problem.measured.outputs[name]
        with np.errstate(divide="ignore", invalid="ignore"):
            fitted[name] = np.where(np.asarray(scale) != 0, fitted_rows[at : at + n] / scale, np.nan)
        at += n
    return _result(
        model,
        plist,
        best.x,
        stats,
        "output-error",
        problem.runs,
        problem.measured.time,
        measured,
        fitted,
        str(best.message),
    )


def _solve(problem: Problem, x0: np.ndarray, low: np.ndarray, high: np.ndarray, loss: str) -> Any:
    """One trust-region fit from ``x0``. Parameters the outputs do not change with at ``x0`` (a
    table point the data never reach) are held first — a free direction that the trust region
    would wander along for hundreds of runs — and freed again for a final fit if they act at
    the reduced fit's solution (e.g. a brake that comes to stick there)."""
    least_squares = _deps.scipy_optimize.least_squares

    def run(active: np.ndarray, start: np.ndarray) -> Any:
        def embed(z: np.ndarray) -> np.ndarray:
            x = start.copy()
            x[active] = z
            return x

        sol = least_squares(
            lambda z: problem.residual(embed(z)),
            start[active],
            jac=lambda z: problem.jacobian(embed(z))[:, active],
            bounds=(low[active], high[active]),
            method="trf",
            loss=loss,
            x_scale="jac",
        )
        sol.x = embed(sol.x)
        return sol

    silent = silent_columns(problem.jacobian(x0))
    if silent.any() and not silent.all():
        sol = run(~silent, np.asarray(x0, dtype=float))
        if silent_columns(problem.jacobian(sol.x))[silent].all():
            return sol
        x0 = sol.x
    return run(np.ones(len(x0), dtype=bool), np.asarray(x0, dtype=float))


def _result(
    model: Model,
    plist: list[Param],
    x: np.ndarray,
    stats: Any,
    method: str,
    runs: int,
    time: np.ndarray,
    measured: dict[str, np.ndarray],
    fitted: dict[str, np.ndarray],
    message: str,
) -> FitResult:
    known = [(p, v) for p, v in zip(plist, x, strict=True) if p.label not in stats.unidentifiable]
    estimates = {
        p.label: (None if p.label in stats.unidentifiable else float(v))
        for p, v in zip(plist, x, strict=True)
    }
    return FitResult(
        estimates=estimates,
        stderr=stats.stderr,
        intervals=stats.intervals,
        correlation=stats.correlation,
        unidentifiable=stats.unidentifiable,
        model=_fitted_model(model, [p for p, _ in known], [v for _, v in known]),
        method=method,
        runs=runs,
        time=time,
        measured=measured,
        fitted=fitted,
        sigma=stats.sigma,
        starts={p.label: p.start for p in plist},
        bounds={p.label: (p.low, p.high) for p in plist},
        message=message,
    )


def _fitted_model(model: Model, plist: list[Param], values: list[float]) -> Model:
    """A copy of ``model`` with the estimates set (unidentifiable ones keep their value)."""
    fitted = Model.loads(model.to_toml(), model.base_dir, default_name=model.name)
    for name, value in apply(model, plist, values).items():
        if name in fitted.parameters:
            fitted.parameters[name] = value
        else:
            fitted.set(name, value)
    return fitted
