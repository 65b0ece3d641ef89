"""The output-error problem: residuals of the model's outputs against the data, and their
Jacobian as finite differences whose columns are variants of the compiled model, run in
parallel on the sweep machinery. Each variant is an exact simulation (events located as in
any run), so a difference steps across events as the model does, never through a smoothed one."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from stiction.errors import ModelError, SimulationError
from stiction.fitting.data import Measured
from stiction.fitting.params import Param, apply
from stiction.model.model import Model, numbers_read
from stiction.model.parameters import evaluate_parameters, expand_parameters
from stiction.sweeps.runner import run_batch

__all__ = ["Problem"]

#: the relative finite-difference step: well above the runs' tolerance (1e-8 in a fit), well
#: below the parameters' own scale
STEP = 1e-4
#: a fit runs at this tolerance at least, so that differences are not the integrator's noise
TOLERANCE = 1e-8


class Problem:
    """Residuals and Jacobian of one fit (see the module docstring); counts its model runs."""

    def __init__(
        self,
        model: Model,
        params: list[Param],
        measured: Measured,
        weights: Mapping[str, Any] | None,
        workers: int | None,
    ) -> None:
        self.model, self.params, self.measured, self.workers = model, params, measured, workers
        if float(model.experiment.get("Tolerance", 1e-6)) > TOLERANCE:
            model.experiment["Tolerance"] = TOLERANCE
        self.compiled = model.compile()
        self.outputs = list(measured.outputs)
        self.compiled._core.check_plan([], self.outputs)  # a name not in the model, before any run
        self.compiled.check_overrides(self._expand(apply(model, params, [q.start for q in params])))
        self.grid = np.asarray(self.compiled._core.grid(), dtype=float)
        t = measured.time
        self.on_grid = len(self.grid) == len(t) and np.allclose(
            self.grid, t, rtol=0, atol=1e-9 * max(1.0, abs(t[-1]))
        )
        self.scales = _scales(measured, weights)
        self.data = np.concatenate([measured.outputs[o] * self.scales[o] for o in self.outputs])
        self.runs = 0
        self._last: tuple[np.ndarray, np.ndarray] | None = None
        self._last_jac: tuple[np.ndarray, np.ndarray] | None = None

    def _expand(self, overrides: dict[str, Any]) -> dict[str, Any]:
        m = self.model
        if not m.parameters:
            return overrides
        out = expand_parameters(m.parameters, m.components, overrides)
        top = {k: v for k, v in overrides.items() if k in m.parameters}
        if top and m.variables:
            out |= numbers_read(m.variables, evaluate_parameters({**m.parameters, **top}))
        return out

    def predict(self, points: np.ndarray) -> np.ndarray:
        """The scaled model outputs (one row per parameter vector of ``points``)."""
        variants = [self._expand(apply(self.model, self.params, x)) for x in points]
        _, trajectories, errors, _ = run_batch(self.compiled, variants, [], self.outputs, self.workers)
        self.runs += len(variants)
        for x, error in zip(points, errors, strict=True):
            if error is not None:
                shown = ", ".join(f"{p.label} = {v:.6g}" for p, v in zip(self.params, x, strict=True))
                raise SimulationError(f"fit: the model failed at {shown}: {error}")
        rows = []
        for k in range(len(points)):
            parts = []
            for o, traj in zip(self.outputs, trajectories, strict=True):
                y = traj[k] if self.on_grid else np.interp(self.measured.time, self.grid, traj[k])
                parts.append(y * self.scales[o])
            rows.append(np.concatenate(parts))
        return np.array(rows)

    def residual(self, x: np.ndarray) -> np.ndarray:
        """Scaled model minus scaled data at ``x``."""
        if self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1]
        r = self.predict(np.asarray([x]))[0] - self.data
        self._last = (np.array(x, dtype=float), r)
        return r

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """Forward differences, all columns in one parallel batch (a step near the upper
        bound goes down instead); the last one is kept (asked again at the same point, free)."""
        if self._last_jac is not None and np.array_equal(self._last_jac[0], x):
            return self._last_jac[1]
        r0 = self.residual(x)
        steps = np.array([_step(p, v) for p, v in zip(self.params, x, strict=True)])
        points = np.repeat(np.asarray([x], dtype=float), len(x), axis=0)
        points[np.diag_indices(len(x))] += steps
        shifted = self.predict(points) - self.data
        jac = ((shifted - r0) / steps[:, None]).T
        self._last_jac = (np.array(x, dtype=float), jac)
        return jac


def _step(p: Param, v: float) -> float:
    h = STEP * max(abs(v), 1e-2 * (p.high - p.low))
    return -h if v + h > p.high else h


def _scales(measured: Measured, weights: Mapping[str, Any] | None) -> dict[str, Any]:
    """Each output's weight: given, or one over its largest magnitude (so outputs of other
    units weigh alike and a noise proportional to each signal's size weighs each sample alike)."""
    out = {}
    weights = dict(weights or {})
    for name in weights:
        if name not in measured.outputs:
            raise ModelError(
                f"fit weights: '{name}' is not one of the outputs ({', '.join(measured.outputs)})"
            )
    for name, y in measured.outputs.items():
        if name in weights:
            w = np.asarray(weights[name], dtype=float)
            if w.ndim not in (0, 1) or (w.ndim == 1 and len(w) != len(y)) or np.any(w < 0):
                raise ModelError(f"fit weights: '{name}' must be a number or one per sample, all >= 0")
            out[name] = w
        else:
            size = float(np.max(np.abs(y)))
            out[name] = 1.0 / size if size > 0 else 1.0
    return out
