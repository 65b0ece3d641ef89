"""Plots of results with matplotlib, imported only when a plot is asked for.

Figures are built with the object-oriented API (no pyplot), so plotting never switches
the user's backend and works headless: saving a PNG goes through Agg. Axes show MSL's
display units (``displayUnit``): temperatures in degC, angles in deg.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from stiction import _deps
from stiction.model.quantities import in_display_unit
from stiction.results.io.csv import is_integer_signal
from stiction.results.modes import mode_name

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from stiction.results.result import Result

__all__ = ["plot_result"]

MODE_LEVELS = (-1, 0, 1, 2)


def _label(result: Result, name: str) -> str:
    """``brake.tau [N.m]``: the name with its unit (its display unit), when it has one."""
    unit = in_display_unit(0.0, result.unit(name))[1]
    return f"{name} [{unit}]" if unit else name


def _shown(result: Result, name: str) -> Any:
    """A variable's values in MSL's display unit: temperatures in degC, angles in deg."""
    return in_display_unit(result[name], result.unit(name))[0]


def plot_result(
    result: Result,
    groups: Sequence[Sequence[str]],
    path: str | os.PathLike[str] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Draw each group on its own axes (all on ``ax`` if given); save to ``path``."""
    Figure = _deps.figure.Figure
    MaxNLocator = _deps.ticker.MaxNLocator

    if not groups:
        raise ValueError("nothing to plot: name at least one signal")
    t = result.time
    if ax is not None:
        parent = ax.figure
        while not isinstance(parent, Figure):  # a SubFigure: save the whole figure
            parent = parent.figure
        fig = parent
        axes = [ax] * len(groups)
    else:
        fig = Figure(figsize=(8.0, 0.6 + 2.2 * max(len(groups), 1)), layout="constrained")
        axes = list(fig.subplots(max(len(groups), 1), 1, sharex=True, squeeze=False)[:, 0])
    for axis, group in zip(axes, groups, strict=False):
        for name in group:
            # Event rows repeat the time (left, then right value): jumps are vertical.
            axis.plot(t, _shown(result, name), label=_label(result, name), linewidth=1.2)
        axis.grid(True, alpha=0.3)
        if all(n.endswith(".mode") for n in group):  # friction modes: named levels
            axis.set_yticks(list(MODE_LEVELS), [mode_name(m) for m in MODE_LEVELS])
        elif all(is_integer_signal(n) for n in group):  # flags: whole-number ticks
            axis.yaxis.set_major_locator(MaxNLocator(integer=True))
        if len(group) == 1 and ax is None:
            axis.set_ylabel(_label(result, group[0]))
        else:
            axis.legend(loc="best", fontsize="small")
    axes[-1].set_xlabel("time [s]")
    if result.name and ax is None:
        fig.suptitle(result.name)
    if path is not None:
        fig.savefig(os.fspath(path), dpi=120)  # format from the suffix; PNG by default
    return fig
