"""What the data say about the estimates: standard errors, 95 % intervals and correlations from
the Jacobian at the solution, and which parameters the data cannot identify, with why."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from stiction import _deps

__all__ = ["Uncertainty", "silent_columns", "uncertainty"]

#: a parameter whose column of the scaled Jacobian is this small against the largest one does
#: not move the outputs; singular values this small against the largest make a combination the
#: data cannot tell apart
ZERO_COLUMN = 1e-9
SINGULAR = 1e-7


@dataclass
class Uncertainty:
    """Standard errors, intervals, correlations and the unidentifiable parameters' reasons."""

    stderr: dict[str, float | None]
    intervals: dict[str, tuple[float, float] | None]
    correlation: np.ndarray
    unidentifiable: dict[str, str]
    sigma: float
    dof: int


def silent_columns(jac: np.ndarray) -> np.ndarray:
    """Which columns (parameters) of ``jac`` the outputs do not change with: a norm at most
    ``ZERO_COLUMN`` of the largest (all of them when every norm is 0)."""
    norms = np.linalg.norm(jac, axis=0)
    return norms <= ZERO_COLUMN * float(norms.max()) if norms.size else norms > 0


def _reasons(labels: list[str], jac: np.ndarray, hints: Mapping[str, str], singular: float) -> dict[str, str]:
    norms = np.linalg.norm(jac, axis=0)
    reasons: dict[str, str] = {}
    for label, silent in zip(labels, silent_columns(jac), strict=True):
        if silent:
            reasons[label] = "the fitted outputs do not change with it (zero sensitivity)"
            if label.endswith(".peak"):
                comp = label.removesuffix(".peak")
                reasons[label] += (
                    f": '{comp}' never sticks and breaks away in the data, and peak acts only then"
                )
            elif label in hints:
                reasons[label] += ": " + hints[label]
    keep = [i for i, label in enumerate(labels) if label not in reasons]
    if len(keep) > 1:
        scaled = jac[:, keep] / norms[keep]
        _, s, vt = np.linalg.svd(scaled, full_matrices=False)
        for k in np.flatnonzero(s < singular * s[0]):
            involved = [labels[keep[i]] for i in np.flatnonzero(np.abs(vt[k]) > 0.1)]
            for label in involved:
                others = [o for o in involved if o != label]
                reasons[label] = "the data cannot tell its effect apart from " + ", ".join(others)
    return reasons


def uncertainty(
    labels: list[str],
    x: np.ndarray,
    jac: np.ndarray,
    residual: np.ndarray,
    hints: Mapping[str, str] | None = None,
    singular: float = SINGULAR,
) -> Uncertainty:
    """Linearised statistics of a least-squares estimate: s² (JᵀJ)⁻¹ over the identifiable
    parameters, Student-t 95 % intervals with m − n degrees of freedom. ``hints``: why a
    parameter may not act (a table point the data may not reach), told with zero sensitivity;
    ``singular``: the relative singular value below which a combination is not identified
    (larger for a finite-difference Jacobian than for an exact one)."""
    t_dist = _deps.scipy_stats.t

    reasons = _reasons(labels, jac, hints or {}, singular)
    keep = [i for i, label in enumerate(labels) if label not in reasons]
    dof = max(len(residual) - len(keep), 1)
    sigma2 = float(residual @ residual) / dof
    n = len(labels)
    cov = np.full((n, n), np.nan)
    if keep:
        sub = jac[:, keep]
        cov[np.ix_(keep, keep)] = sigma2 * np.linalg.pinv(sub.T @ sub)
    stderr: dict[str, float | None] = {}
    intervals: dict[str, tuple[float, float] | None] = {}
    q = float(t_dist.ppf(0.975, dof))
    for i, label in enumerate(labels):
        if label in reasons:
            stderr[label], intervals[label] = None, None
            continue
        se = float(np.sqrt(max(cov[i, i], 0.0)))
        stderr[label] = se
        intervals[label] = (float(x[i] - q * se), float(x[i] + q * se))
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    return Uncertainty(stderr, intervals, corr, reasons, float(np.sqrt(sigma2)), dof)
