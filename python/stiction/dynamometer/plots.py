"""The plots a brake engineer reads a dyno run from, with matplotlib (loaded on first use):
mu per stop coloured by section, temperatures per stop, mu over temperature, and the fade
section with its recovery.

Drawn for speed (a schedule's report should not wait on its figure): the Agg canvas set
explicitly (no pyplot, no backend search), one scatter and one line collection per panel with a
colour per point rather than an artist per section or per stop, the legend from proxy handles at
a fixed place (``loc="best"`` searches the data), and fixed margins instead of a layout engine
(constrained layout measures every tick label twice: about a third of the figure's time).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stiction import _deps

if TYPE_CHECKING:
    from stiction.dynamometer.report import DynoReport

__all__ = ["plot_report", "report_figure"]


def _by_section(report: DynoReport) -> list[tuple[str, Any]]:
    stops = report.stops
    names = list(dict.fromkeys(stops["section"]))
    return [(name, stops[stops["section"] == name]) for name in names]


def _colours(report: DynoReport) -> tuple[list[str], dict[str, Any], list[Any]]:
    """The section names in order, a colour per section (the ``C0`` … ``C9`` cycle, ``tab20``
    beyond ten sections, so that no two share one) and each stop's colour."""
    names = list(dict.fromkeys(report.stops["section"]))
    if len(names) <= 10:
        colour = {name: f"C{k}" for k, name in enumerate(names)}
    else:
        table = _deps.matplotlib.colormaps["tab20"].colors
        colour = {name: table[k % len(table)] for k, name in enumerate(names)}
    return names, colour, [colour[name] for name in report.stops["section"]]


def report_figure(report: DynoReport) -> Any:
    """A figure of four panels (a ``matplotlib.figure.Figure`` on an Agg canvas, no pyplot
    state)."""
    fig = _deps.figure.Figure(figsize=(12, 8))
    _deps.backend_agg.FigureCanvasAgg(fig)
    fig.subplots_adjust(left=0.06, right=0.93, bottom=0.07, top=0.95, wspace=0.3, hspace=0.3)
    ax_mu, ax_t, ax_mt, ax_fade = fig.subplots(2, 2).ravel()
    stops, samples = report.stops, report.samples
    names, colour, colours = _colours(report)
    index = stops["index"].to_numpy()
    ax_mu.vlines(index, stops["mu_min"], stops["mu_max"], colors=colours, lw=0.6)
    ax_mu.scatter(index, stops["mu_mean"], s=9, c=colours)
    ax_t.scatter(index, stops["T_initial"], s=9, c=colours, marker="v")
    ax_t.scatter(index, stops["T_peak"], s=9, c=colours, marker="^")
    ax_mt.plot(samples["T"], samples["mu"], ",", color="0.6", zorder=0)
    ax_mt.scatter(stops["T_initial"], stops["mu_mean"], s=9, c=colours)
    proxies = [_deps.lines.Line2D([], [], ls="", marker="o", ms=3, color=colour[name]) for name in names]
    ax_mu.legend(proxies, names, fontsize="x-small", ncols=3, loc="lower left")
    ax_mu.set(xlabel="stop", ylabel="mu (mean 10–80 %, bar: min–max)", title="friction per stop")
    ax_t.set(xlabel="stop", ylabel="brake temperature [°C]", title="initial (▽) and peak (△)")
    ax_mt.set(xlabel="brake temperature [°C]", ylabel="mu", title="mu over temperature")
    # the sections named fade or recovery (else the last two), with their peak temperatures
    fade = [(n, r) for n, r in _by_section(report) if "fade" in n.lower() or "recover" in n.lower()]
    twin = ax_fade.twinx()
    for name, rows in fade or _by_section(report)[-2:]:
        ax_fade.plot(rows["index"], rows["mu_mean"], "o-", ms=3, label=name, color=colour[name])
        twin.plot(rows["index"], rows["T_peak"], ":", color=colour[name])
    ax_fade.legend(fontsize="small", loc="lower left")
    twin.set_ylabel("peak temperature [°C] (dotted)")
    ax_fade.set(xlabel="stop", ylabel="mu", title="fade and recovery")
    return fig


def plot_report(report: DynoReport, path: str | os.PathLike[str]) -> Path:
    """Save the report's figure to ``path`` (PNG, SVG, PDF by suffix); returns the path."""
    fig = report_figure(report)
    fig.savefig(path, dpi=100)
    return Path(path)
