"""A virtual brake dynamometer: a schedule of stops run on a brake model (``st.dyno``).

``st.dyno(model, schedule)`` rigs the model (its brake pressed through ``f_normalized``, an
inertia it stops), runs every stop of the schedule in one ``Simulation`` advanced and re-driven
stop by stop (the thermal and wear state carried on), and returns a ``DynoReport``. The schedule
format, the stop's sequence and the report's definitions: docs/dyno.md.
"""

from __future__ import annotations

import os

from stiction.dynamometer.report import DynoReport
from stiction.dynamometer.rig import rig_model
from stiction.dynamometer.runner import run_schedule
from stiction.dynamometer.schedule import (
    LEVELS,
    Rig,
    Schedule,
    ScheduleError,
    Section,
    load_schedule,
    loads_schedule,
)
from stiction.model.model import Model

__all__ = [
    "LEVELS",
    "DynoReport",
    "Rig",
    "Schedule",
    "ScheduleError",
    "Section",
    "dyno",
    "load_schedule",
    "loads_schedule",
]


def dyno(
    model: Model | str | os.PathLike[str],
    schedule: Schedule | str | os.PathLike[str],
    progress: bool = True,
) -> DynoReport:
    """Run a dynamometer schedule on a brake model.

    Parameters
    ----------
    model
        The brake model: a ``Model``, or the path of a ``.toml`` or ``.mo`` file.
    schedule
        A ``Schedule``, or the path of a schedule file (TOML; see docs/dyno.md).
    progress
        Show a progress bar (tqdm) over the stops.

    Returns
    -------
    DynoReport
        One row per stop (``stops``), the samples behind them, the wall-clock time it took.
        A pad worn down to its ``thickness_min`` ends the run cleanly: the report holds the
        stops done and ``worn_out`` names the stop that wore the pad out.

    Raises
    ------
    ScheduleError
        A schedule that cannot run on the model, naming the section and the line.
    """
    if not isinstance(model, Model):
        model = Model.load(model)  # a .mo file too
    if not isinstance(schedule, Schedule):
        schedule = load_schedule(schedule)
    stops, samples, timing, worn_out = run_schedule(rig_model(model, schedule), schedule, progress)
    return DynoReport(stops=stops, samples=samples, timing=timing, name=model.name, worn_out=worn_out)
