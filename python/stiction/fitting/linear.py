"""The linear path: where the data measure a brake's or clutch's friction torque, its normal
force and its slip speed, the sliding torque ``tau = cgeo*fn*mu(|w|)*sign(w)`` is linear in the
``mu_pos`` ordinates (the table interpolates linearly), so they are a bounded linear least
squares (``scipy.optimize.lsq_linear``), and ``peak`` is read from the break-away points: the
torque held just before the slip starts is ``peak*mu(0)*cgeo*fn``. No model run is needed."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stiction import _deps
from stiction.errors import ModelError
from stiction.fitting.data import Measured
from stiction.fitting.params import Param, _current
from stiction.fitting.stats import Uncertainty, uncertainty
from stiction.model.model import Model

__all__ = ["LinearPlan", "linear_plan", "solve_linear"]

FRICTION_TYPES = ("Brake", "Clutch")
#: samples a stuck stretch lasts at least: a noisy speed passing through zero while sliding
#: looks stuck for a sample or two, a stick lasts longer
MIN_STICK = 10


@dataclass
class LinearPlan:
    """The component, its table and the measured signals the linear path reads."""

    comp: str
    table: np.ndarray
    extrapolation: str
    cgeo: float
    tau: np.ndarray
    fn: np.ndarray
    w: np.ndarray


def linear_plan(model: Model, params: list[Param], measured: Measured) -> LinearPlan | str:
    """The plan, or why the linear path does not apply (a sentence)."""
    comps = {p.target.rpartition(".")[0] for p in params}
    if len(comps) != 1:
        return "the parameters belong to more than one component"
    comp = comps.pop()
    kind = model.components[comp].type if comp in model.components else None
    if kind not in FRICTION_TYPES:
        return f"'{comp}' is not a Brake or Clutch"
    for p in params:
        if p.target == f"{comp}.mu_pos" and p.cell is not None and p.cell[1] == 1:
            continue
        if p.target == f"{comp}.peak":
            continue
        return f"'{p.label}' is not a mu_pos coefficient or peak"
    have = measured.outputs | measured.inputs
    speed = next((have[n] for n in (f"{comp}.w", f"{comp}.w_rel") if n in have), None)
    tau = have.get(f"{comp}.tau")
    fn = have.get(f"{comp}.fn")
    if fn is None and f"{comp}.f_normalized" in have:
        fn = float(_current(model, f"{comp}.fn_max")[0]) * have[f"{comp}.f_normalized"]
    if speed is None or tau is None or fn is None:
        return f"the data do not measure '{comp}.tau', its normal force ('{comp}.fn' or '{comp}.f_normalized') and its slip speed"
    table = np.asarray(_current(model, f"{comp}.mu_pos")[0], dtype=float)
    extrapolation = str(model.components[comp].params.get("extrapolation", "LastTwoPoints"))
    cgeo = float(_current(model, f"{comp}.cgeo")[0])
    return LinearPlan(comp, table, extrapolation, cgeo, tau, fn, speed)


def basis(w: np.ndarray, abscissa: np.ndarray, extrapolation: str) -> np.ndarray:
    """mu(w) = basis(w) @ ordinates: the table's linear interpolation (and extrapolation)."""
    n = len(abscissa)
    out = np.zeros((len(w), n))
    if n == 1:
        out[:, 0] = 1.0
        return out
    k = np.clip(np.searchsorted(abscissa, w, side="right") - 1, 0, n - 2)
    frac = (w - abscissa[k]) / (abscissa[k + 1] - abscissa[k])
    if extrapolation == "HoldLastPoint":
        frac = np.clip(frac, 0.0, 1.0)
    rows = np.arange(len(w))
    out[rows, k] = 1.0 - frac
    out[rows, k + 1] += frac
    return out


def _noise(w: np.ndarray) -> float:
    """The speed signal's noise, from its second differences (robust to the motion)."""
    d2 = np.diff(w, 2)
    return float(np.median(np.abs(d2)) / 0.6745 / np.sqrt(6.0)) if len(d2) else 0.0


def solve_linear(plan: LinearPlan, params: list[Param]) -> tuple[np.ndarray, Uncertainty, np.ndarray]:
    """Estimates, their uncertainty and the fitted friction torque (see the module docstring)."""
    lsq_linear = _deps.scipy_optimize.lsq_linear

    w, tau, fn = plan.w, plan.tau, plan.fn
    eps = max(5.0 * _noise(w), 1e-9 * float(np.max(np.abs(w))))
    sliding = (np.abs(w) > eps) & (fn > 0)
    mu_params = [i for i, p in enumerate(params) if p.cell is not None]
    peak = next((i for i, p in enumerate(params) if p.cell is None), None)
    table = plan.table.copy()
    phi = basis(np.abs(w), table[:, 0], plan.extrapolation) * (plan.cgeo * fn * np.sign(w))[:, None]
    x = np.array([p.start for p in params], dtype=float)
    reasons: dict[str, str] = {}
    fitted = tau.copy()
    if mu_params:
        rows = [params[i].cell[0] for i in mu_params]  # type: ignore[index]
        fixed = [r for r in range(len(table)) if r not in rows]
        a = phi[sliding][:, rows]
        b = tau[sliding] - phi[sliding][:, fixed] @ table[fixed, 1]
        if not np.any(sliding):
            raise ModelError(f"fit (linear): '{plan.comp}' never slides in the data; mu_pos cannot be fitted")
        sol = lsq_linear(
            a, b, bounds=([params[i].low for i in mu_params], [params[i].high for i in mu_params])
        )
        x[mu_params] = sol.x
        table[rows, 1] = sol.x
        fitted[sliding] = phi[sliding] @ table[:, 1]
        mu_stats = uncertainty([params[i].label for i in mu_params], sol.x, a, a @ sol.x - b)
    labels = [p.label for p in params]
    n = len(params)
    stderr: dict[str, float | None] = dict.fromkeys(labels)
    intervals: dict[str, tuple[float, float] | None] = dict.fromkeys(labels)
    corr = np.full((n, n), np.nan)
    sigma, dof = 0.0, 1
    if mu_params:
        for k, i in enumerate(mu_params):
            stderr[labels[i]] = mu_stats.stderr[labels[i]]
            intervals[labels[i]] = mu_stats.intervals[labels[i]]
            corr[i, mu_params] = mu_stats.correlation[k]
        reasons |= mu_stats.unidentifiable
        sigma, dof = mu_stats.sigma, mu_stats.dof
    if peak is not None:
        value, se, why = _peak(plan, table, sliding, eps)
        p = params[peak]
        if why:
            reasons[p.label] = why
        else:
            t_q = float(_deps.scipy_stats.t.ppf(0.975, max(dof, 1)))
            x[peak] = min(max(value, p.low), p.high)
            stderr[p.label] = se
            intervals[p.label] = (x[peak] - t_q * se, x[peak] + t_q * se)
            corr[peak, peak] = 1.0
    for label in reasons:
        stderr[label] = intervals[label] = None
    return x, Uncertainty(stderr, intervals, corr, reasons, sigma, dof), fitted


def _passing(w: np.ndarray, eps: float) -> bool:
    """Whether a stretch of speeds within the noise band is the motion passing through it (a
    trend across the band) rather than a stick (flat, but for its edges)."""
    n = len(w)
    slope = np.polyfit(np.arange(n), w, 1)[0]
    return bool(abs(slope) * n > 0.5 * eps)


def _peak(plan: LinearPlan, table: np.ndarray, sliding: np.ndarray, eps: float) -> tuple[float, float, str]:
    """peak from each break-away: the largest torque held in the stuck stretch before a slip
    (a noisy speed shows the slip a few samples late, the held torque peaks at the break;
    extrapolated half a sample on, the break's mean place between two samples) over
    mu(0)*cgeo*fn there."""
    stuck = ~sliding
    ends = np.flatnonzero(stuck[1:-1] & stuck[:-2] & sliding[2:]) + 1
    if len(ends) == 0:
        return (
            0.0,
            0.0,
            (
                f"no break-away in the data: '{plan.comp}' never sticks and slides again, and peak acts only then"
            ),
        )
    mu0 = float(basis(np.zeros(1), table[:, 0], plan.extrapolation)[0] @ table[:, 1])
    ratios = []
    for end in ends:
        begin = end
        while begin > 0 and stuck[begin - 1]:
            begin -= 1
        if end - begin + 1 < MIN_STICK or _passing(plan.w[begin : end + 1], eps):
            continue
        held = np.abs(plan.tau[begin : end + 1]) / (
            mu0 * plan.cgeo * np.maximum(plan.fn[begin : end + 1], 1e-300)
        )
        k = int(np.argmax(held))
        ratios.append(held[k] + (0.5 * (held[k] - held[k - 1]) if k > 0 else 0.0))
    if not ratios:
        return (
            0.0,
            0.0,
            f"no break-away in the data: '{plan.comp}' never stays stuck and slides again, and peak acts only then",
        )
    values = np.array(ratios)
    se = float(np.std(values, ddof=1) / np.sqrt(len(values))) if len(values) > 1 else float("nan")
    return float(np.mean(values)), se, ""
