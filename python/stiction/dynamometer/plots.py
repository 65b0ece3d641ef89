"""The plots a brake engineer reads a dyno run from, with matplotlib (loaded on first use):
mu per stop coloured by section, temperatures per stop, mu over temperature, and the fade
section with its recovery."""

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


def report_figure(report: DynoReport) -> Any:
    """A figure of four panels (a ``matplotlib.figure.Figure``, no pyplot state)."""
    fig = _deps.figure.Figure(figsize=(12, 8), layout="constrained")
    ax_mu, ax_t, ax_mt, ax_fade = fig.subplots(2, 2).ravel()
    for k, (name, rows) in enumerate(_by_section(report)):
        c = f"C{k % 10}"
        ax_mu.plot(rows["index"], rows["mu_mean"], "o", ms=3, color=c, label=name)
        ax_mu.vlines(rows["index"], rows["mu_min"], rows["mu_max"], color=c, lw=0.6)
        ax_t.plot(rows["index"], rows["T_initial"], "v", ms=3, color=c)
        ax_t.plot(rows["index"], rows["T_peak"], "^", ms=3, color=c)
        ax_mt.plot(rows["T_initial"], rows["mu_mean"], "o", ms=3, color=c)
    samples = report.samples
    ax_mt.plot(samples["T"], samples["mu"], ",", color="0.6", zorder=0)
    ax_mu.set(xlabel="stop", ylabel="mu (mean 10–80 %, bar: min–max)", title="friction per stop")
    ax_mu.legend(fontsize="x-small", ncols=3, loc="best")
    ax_t.set(xlabel="stop", ylabel="brake temperature [°C]", title="initial (▽) and peak (△)")
    ax_mt.set(xlabel="brake temperature [°C]", ylabel="mu", title="mu over temperature")
    # the sections named fade or recovery (else the last two), with their peak temperatures
    fade = [(n, r) for n, r in _by_section(report) if "fade" in n.lower() or "recover" in n.lower()]
    twin = ax_fade.twinx()
    for name, rows in fade or _by_section(report)[-2:]:
        line = ax_fade.plot(rows["index"], rows["mu_mean"], "o-", ms=3, label=name)[0]
        twin.plot(rows["index"], rows["T_peak"], ":", color=line.get_color())
    ax_fade.legend(fontsize="small")
    twin.set_ylabel("peak temperature [°C] (dotted)")
    ax_fade.set(xlabel="stop", ylabel="mu", title="fade and recovery")
    return fig


def plot_report(report: DynoReport, path: str | os.PathLike[str]) -> Path:
    """Save the report's figure to ``path`` (PNG, SVG, PDF by suffix); returns the path."""
    fig = report_figure(report)
    fig.savefig(path, dpi=110)
    return Path(path)
