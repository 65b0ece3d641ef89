"""A dynamometer run's report: the per-stop table, the samples behind it, files and plots.

Columns of ``DynoReport.stops`` (one row per stop, in schedule order):

- ``index`` (1, 2, … over the schedule), ``section``, ``kind``, ``stop`` (1, 2, … in its section);
- ``v_initial``, ``v_final``: the schedule's speeds (km/h or rad/s, as the schedule writes them);
- ``pressure`` [bar] (NaN without ``fn_per_bar``), ``fn``: the clamp force [N];
- ``T_initial``, ``T_peak``, ``T_final`` [°C]: the brake temperature at the stop's start, its
  highest value at the samples and the end, at the end;
- ``mu_mean``: the mean friction coefficient over the stop between 10 % and 80 % of its speed
  drop, weighted by sliding distance: ``∫tau dphi / (cgeo·fn·Δphi)`` over that window, the
  torque work taken from the dyno inertia's kinetic energy between the two exact instants,
  ``J·(w_10² − w_80²)/2`` (exact while the brake is the one torque on the inertia);
- ``mu_min``, ``mu_max``: the extremes of the measured ``|tau|/(cgeo·fn)`` at the 15 samples
  between 10 % and 80 % of the speed drop (every 5 %);
- ``time`` [s]: the stop's duration; ``energy`` [J]: ``J·(w0² − w1²)/2``;
- ``cooling_time`` [s]: the cooling before the stop; ``t_start``: the stop's simulation time;
- with target decelerations in the schedule (none of these otherwise): ``decel`` (the target,
  NaN for a pressure stop), ``decel_mean`` (over 10–80 % of the speed drop), ``pressure_max``
  [bar] (the highest applied) and ``missed`` (the controller at ``p_max`` in that window);
  ``pressure`` and ``fn`` are then the time means over the stop (control.py);
- ``wear`` [m³]: the growth of the brake's worn volume ``<brake>.wearVolume`` over the stop,
  when the brake has a ``wear`` record (docs/wear.md); ``thickness`` [m]: the pad thickness
  left at the stop's end, when the record gives the pad (``A``, ``thickness``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from stiction import _deps

__all__ = ["DynoReport"]


@dataclass
class DynoReport:
    """The result of ``st.dyno``: ``stops`` (a pandas DataFrame, one row per stop),
    ``samples`` (mu and temperature at 10 %, 15 %, … 80 % of each stop's speed drop) and
    ``timing``: wall-clock seconds spent in ``stops``, ``cooling`` and ``setup``.

    ``worn_out`` is ``None``, or, when the pad wore down to its ``thickness_min`` and ended the
    run, the stop it happened in: ``index``, ``section``, ``stop`` (as in the table, which holds
    the stops done before it) and the engine's ``message`` (element, instant, worn volume)."""

    stops: Any
    samples: Any
    timing: dict[str, float] = field(default_factory=dict)
    name: str = "dyno"
    worn_out: dict[str, Any] | None = None

    @property
    def completed(self) -> bool:
        """Whether every stop of the schedule ran (no pad wore out)."""
        return self.worn_out is None

    @property
    def missed(self) -> Any:
        """The rows of the stops whose target deceleration the controller could not reach
        (the pressure at ``p_max``); none in a schedule without ``decel``."""
        return self.stops[self.stops["missed"]] if "missed" in self.stops else self.stops.iloc[:0]

    def summary(self) -> str:
        """One line: the stops done, how many missed their target deceleration, and the stop
        that wore the pad out if one did."""
        text = f"{len(self)} stops"
        if len(missed := self.missed):
            text += (
                f"; {len(missed)} missed their target deceleration (at p_max): index {missed['index'].min()}"
            )
            text += f"–{missed['index'].max()}" if len(missed) > 1 else ""
        if self.worn_out:
            w = self.worn_out
            text += (
                f"; the pad wore out in stop {w['index']} (section '{w['section']}', stop {w['stop']}): "
                f"{w['message']}"
            )
        return text

    def __len__(self) -> int:
        return len(self.stops)

    def section(self, name: str) -> Any:
        """The rows of one section."""
        return self.stops[self.stops["section"] == name]

    def write(self, folder: str | os.PathLike[str], plots: bool = True) -> list[Path]:
        """Write ``stops.parquet``, ``stops.csv``, ``samples.parquet``, (unless
        ``plots=False``) the plots and, when the pad wore out, ``worn_out.txt`` (the
        ``summary``) into ``folder``; returns the files written."""
        out = Path(folder)
        out.mkdir(parents=True, exist_ok=True)
        files = [out / "stops.parquet", out / "stops.csv", out / "samples.parquet"]
        self.stops.to_parquet(files[0], index=False)
        self.stops.to_csv(files[1], index=False)
        self.samples.to_parquet(files[2], index=False)
        if plots:
            from stiction.dynamometer.plots import plot_report

            files.append(plot_report(self, out / "dyno.png"))
        if self.worn_out:
            files.append(out / "worn_out.txt")
            files[-1].write_text(self.summary() + "\n", encoding="utf-8")
        return files

    @staticmethod
    def read_stops(folder: str | os.PathLike[str], fmt: str = "parquet") -> Any:
        """The per-stop table a ``write`` left in ``folder`` (``fmt`` "parquet" or "csv")."""
        pd = _deps.pandas
        path = Path(folder) / f"stops.{fmt}"
        if fmt == "csv":
            table = pd.read_csv(path)
            for column in ("section", "kind"):
                table[column] = table[column].astype("string")
            return table
        return _deps.parquet.read_table(path).to_pandas()

    def plot(self, path: str | os.PathLike[str] | None = None) -> Any:
        """The report's figure (mu per stop by section, temperatures, mu over temperature,
        fade and recovery); saved to ``path`` when given."""
        from stiction.dynamometer.plots import plot_report, report_figure

        return plot_report(self, path) if path is not None else report_figure(self)

    def __repr__(self) -> str:
        worn = f", pad worn out in stop {self.worn_out['index']}" if self.worn_out else ""
        return (
            f"<DynoReport {self.name!r}: {len(self)} stops, {self.stops['section'].nunique()} sections{worn}>"
        )
