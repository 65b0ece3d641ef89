"""``FitResult``: the estimates and what the data say about them, the fitted model, plots."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps
from stiction.model.model import Model

if TYPE_CHECKING:
    import pandas

__all__ = ["FitResult"]


@dataclass
class FitResult:
    """The outcome of ``st.fit``.

    ``estimates``, ``stderr`` and ``intervals`` (95 %) are dicts by parameter name (a table's
    cells as ``name[i,j]``, 1-based); a parameter the data cannot identify has None in all
    three and its reason in ``unidentifiable``. ``correlation`` is the estimates' correlation
    matrix (NaN for the unidentifiable), ``residuals`` the data minus the fitted model per
    output (a DataFrame with ``time``), ``model`` the model with the estimates set (ready to
    simulate, save, export), ``runs`` the model runs the fit took, ``method`` the path taken
    ("linear" or "output-error").
    """

    estimates: dict[str, float | None]
    stderr: dict[str, float | None]
    intervals: dict[str, tuple[float, float] | None]
    correlation: np.ndarray
    unidentifiable: dict[str, str]
    model: Model
    method: str
    runs: int
    time: np.ndarray
    measured: dict[str, np.ndarray]
    fitted: dict[str, np.ndarray]
    sigma: float
    starts: dict[str, float] = field(default_factory=dict)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    message: str = ""

    @property
    def names(self) -> list[str]:
        """The estimated parameters' names, in order."""
        return list(self.estimates)

    @property
    def residuals(self) -> pandas.DataFrame:
        """Measured minus fitted, one column per output, with ``time``."""
        pd = _deps.pandas

        return pd.DataFrame(
            {"time": self.time, **{k: self.measured[k] - self.fitted[k] for k in self.measured}}
        )

    @property
    def correlation_table(self) -> pandas.DataFrame:
        """The correlation matrix labelled by parameter name."""
        pd = _deps.pandas

        return pd.DataFrame(self.correlation, index=self.names, columns=self.names)

    @property
    def table(self) -> pandas.DataFrame:
        """One row per parameter: estimate, stderr, 95 % interval, start, bounds, note."""
        pd = _deps.pandas

        rows = []
        for name, value in self.estimates.items():
            interval = self.intervals[name] or (None, None)
            low, high = self.bounds.get(name, (None, None))
            note = self.unidentifiable.get(name, "")
            if not note and value is not None and low is not None and (value <= low or value >= high):
                note = "at a bound"
            rows.append(
                {
                    "parameter": name,
                    "estimate": value,
                    "stderr": self.stderr[name],
                    "low95": interval[0],
                    "high95": interval[1],
                    "start": self.starts.get(name),
                    "lower": low,
                    "upper": high,
                    "note": note,
                }
            )
        return pd.DataFrame(rows)

    def report(self) -> str:
        """A plain-text summary: the method, runs, residual size, each estimate with its
        interval, the unidentifiable ones with their reason, strong correlations."""
        lines = [
            f"fit ({self.method}): {len(self.estimates)} parameters, {self.runs} model runs, residual sd {self.sigma:.4g} (scaled)"
        ]
        if self.message:
            lines.append(f"  {self.message}")
        width = max(len(n) for n in self.estimates)
        for name, value in self.estimates.items():
            if value is None:
                lines.append(f"  {name:<{width}}  not identifiable: {self.unidentifiable[name]}")
                continue
            se, (lo, hi) = self.stderr[name] or 0.0, self.intervals[name] or (value, value)
            lines.append(f"  {name:<{width}}  {value:.6g} ± {se:.3g}  (95 %: {lo:.6g} … {hi:.6g})")
        n = len(self.names)
        for i in range(n):
            for j in range(i + 1, n):
                c = self.correlation[i, j]
                if np.isfinite(c) and abs(c) > 0.9:
                    lines.append(f"  correlated: {self.names[i]} and {self.names[j]} ({c:+.3f})")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"<FitResult {self.method}: {', '.join(f'{k}={v:.4g}' if v is not None else f'{k}=?' for k, v in self.estimates.items())}>"

    def plot(self, axes: Any = None) -> Any:
        """Measured against fitted for each output (top row), the residuals below."""
        plt = _deps.pyplot

        outputs = list(self.measured)
        if axes is None:
            _, axes = plt.subplots(2, len(outputs), sharex=True, squeeze=False, figsize=(5 * len(outputs), 5))
        for k, name in enumerate(outputs):
            top, bottom = axes[0][k], axes[1][k]
            top.plot(self.time, self.measured[name], ".", ms=2, label="measured")
            top.plot(self.time, self.fitted[name], "-", label="fitted")
            top.set_title(name)
            top.legend()
            bottom.plot(self.time, self.measured[name] - self.fitted[name], ".", ms=2)
            bottom.set_xlabel("time [s]")
            bottom.set_ylabel("residual")
        return axes
