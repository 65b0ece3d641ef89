"""``Result``: the trajectories of one run, by MSL variable name, and the event log.

It knows nothing of the engine: it is built from the plain dict the engine returns (or
from arrays), so it can be tested, saved and compared without the compiled module.
"""

from __future__ import annotations

import difflib
import fnmatch
import math
import operator
import os
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from stiction import _deps
from stiction.errors import UsageError
from stiction.results.io import csv as csvio
from stiction.results.io import formats as resultio
from stiction.results.modes import MODE_NAMES, mode_name

if TYPE_CHECKING:
    import pandas
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from stiction.model.runinfo import Experiment, Initialization, RunInfo
    from stiction.results.audit import EnergyAudit

__all__ = ["MODE_NAMES", "Event", "Result", "mode_name"]

# Signal kinds worth showing first in a summary, most telling first.
# ``first("J.w <= 0")``: a variable, a comparison and a number, as ``time_of`` takes them
_COMPARISON = re.compile(r"\s*(\S+?)\s*(<=|>=|==|!=|<|>)\s*(\S+)\s*")
_OPS: dict[str, Callable[[Any, float], Any]] = {
    "<=": operator.le,
    ">=": operator.ge,
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    ">": operator.gt,
}
_MAIN_SUFFIXES = ("w", "v", "w_rel", "mode", "tau", "phi", "s", "phi_rel", "T", "y")


class Event(NamedTuple):
    """One mode change of one component at an event instant, and why it happened."""

    time: float
    component: str
    old_mode: int
    new_mode: int
    cause: str

    @property
    def old(self) -> str:
        """The mode before, by name (``"sliding forward"``)."""
        return mode_name(self.old_mode)

    @property
    def new(self) -> str:
        """The mode after, by name (``"stuck"``)."""
        return mode_name(self.new_mode)

    def __str__(self) -> str:
        return f"t = {self.time:.9g} s  {self.component}: {self.old} → {self.new}  ({self.cause})"


def _with_source(event: Event, sources: list[str]) -> Event:
    """``time event`` → ``time event of press (Step)``."""
    if not sources:
        return event
    cause = event.cause.replace("time event", f"time event of {', '.join(sources)}", 1)
    return event._replace(cause=cause)


class _RawEvents:
    """The engine's events of a run, asked for when iterated (``Result.events``)."""

    def __init__(self, raw: Any) -> None:
        self._raw = raw

    def __iter__(self) -> Iterator[Sequence[Any]]:
        return iter(self._raw.events)


class Result:
    """Trajectories on the output grid and both sides of each event, with statistics."""

    def __init__(
        self,
        names: Sequence[str] | None,
        data: Any = None,
        events: Iterable[Sequence[Any]] = (),
        stats: Mapping[str, float | int] | None = None,
        name: str = "",
        source: Any = None,
        info: RunInfo | None = None,
    ) -> None:
        """``data`` is the full table, or None when a ``source`` (the engine's raw result,
        with ``names``, ``column(name)``, ``table()`` and ``rows``) computes variables on
        demand; ``names`` None: the source's, listed when first read. ``info`` reports the
        run's experiment and initialization."""
        self._source = source
        self._names: list[str] | None = None
        if names is not None or source is None:
            self.names = names if names is not None else []
        self._data: np.ndarray | None = None
        self._columns: dict[str, np.ndarray] = {}
        if data is not None or source is None:
            table = np.asarray(data, dtype=np.float64)
            if table.ndim != 2 or table.shape[1] != len(self.names):
                raise ValueError(f"data shape {table.shape} does not match {len(self.names)} names")
            self._data = table
        self._raw_events: Iterable[Sequence[Any]] | None = events  # made Events when first read
        self._events: list[Event] = []
        self._events_named = False
        self.stats: dict[str, float | int] = dict(stats or {})
        self.name = name
        self._info = info
        self._index_of: dict[str, int] | None = None
        # Parameter values (name -> value) of the run, written to data_1 of a .mat result;
        # or what computes them when first read (a run of thousands of components).
        self._parameters: dict[str, float] | Callable[[], dict[str, float]] = {}

    @classmethod
    def from_core(cls, raw: Any, name: str = "", info: RunInfo | None = None) -> Result:
        """Wrap the engine's raw result; variables are computed when first read (the model's
        derived variables too: the engine has them as result variables); ``info`` answers
        ``experiment`` and ``initialization``."""
        # names and events listed when first read: a ladder of 1000 elements has 28 000 names
        result = cls(None, None, _RawEvents(raw), raw.stats, name=name, source=raw, info=info)
        suspects = getattr(raw, "delivering", ())
        if suspects:  # the engine saw a loss power below the event band: audit the run
            from stiction.results.audit import warn_if_delivering

            warn_if_delivering(result, suspects)
        return result

    @property
    def names(self) -> list[str]:
        """Every variable's name, ``time`` first (one column of ``data`` each)."""
        if self._names is None:
            self._names = list(map(str, self._source.names))
        return self._names

    @names.setter
    def names(self, names: Sequence[str]) -> None:
        listed = list(map(str, names))
        if not listed or listed[0] != "time":
            raise ValueError("the first signal must be 'time'")
        self._names = listed
        self._index_of = None

    @property
    def parameters(self) -> dict[str, float]:
        """Parameter values (name → value) of the run, as data_1 of a .mat result holds them."""
        if callable(self._parameters):
            self._parameters = self._parameters()
        return self._parameters

    @parameters.setter
    def parameters(self, values: dict[str, float] | Callable[[], dict[str, float]]) -> None:
        """A mapping, or a function computing it when first read."""
        self._parameters = values if callable(values) else dict(values)

    @property
    def _index(self) -> dict[str, int]:
        """The column of each name, built at the first lookup: a model of thousands of
        components has tens of thousands of names, and a run nobody reads pays nothing."""
        if self._index_of is None:
            self._index_of = {n: i for i, n in enumerate(self.names)}
        return self._index_of

    def metric(self, text: str) -> float:
        """A metric of this run, written as what it computes: ``final(J4.w)``, ``max(J1.w)``,
        ``min(…)``, ``integral(brake.lossPower)``, ``mean(…)``, ``time_of(clutch2.locked)``
        (or ``time_of(J1.w < 1)``), ``events(clutch1)``, ``events()``. A sweep computes the
        same value to the last bit."""
        if self._source is None:
            raise ValueError("metrics need a result of the engine (not one read from a file)")
        return float(self._source.metric(text))

    def audit(self) -> EnergyAudit:
        """The energy audit element by element (see ``stiction.audit``): for every component,
        the power entering at its flanges against its losses and stored energy, row by row;
        ``r.audit().worst`` is the element furthest from closing, ``r.audit().ok()`` whether
        all close and no passive element delivers net energy."""
        from stiction.results.audit import EnergyAudit

        if self._source is None:
            raise ValueError("the energy audit needs a result of the engine (not one read from a file)")
        span = float(self.time[-1] - self.time[0]) if len(self) else 0.0
        return EnergyAudit.from_core(self._source.audit(), span)

    @property
    def events(self) -> list[Event]:
        """Every mode change: time, component, old and new mode (``.old``/``.new`` by name),
        cause; a time event's cause names the components whose time event it was."""
        if self._raw_events is not None:
            self._events = [
                Event(float(t), str(c), int(a), int(b), str(why)) for t, c, a, b, why in self._raw_events
            ]
            self._raw_events = None
        if not self._events_named and self._info is not None:
            timed = [e for e in self._events if e.cause.startswith("time event")]
            sources = self._info.time_event_sources([e.time for e in timed]) if timed else []
            named = {id(e): s for e, s in zip(timed, sources, strict=True)}
            self._events = [_with_source(e, named.get(id(e), [])) for e in self._events]
        self._events_named = True
        return self._events

    @property
    def experiment(self) -> Experiment | None:
        """The experiment the run used, saying which settings were defaults (None if unknown)."""
        return self._info.experiment if self._info else None

    @property
    def initialization(self) -> Initialization | None:
        """Every start value: fixed, guessed (kept) or computed, with its initial value."""
        return self._info.initialization if self._info else None

    @property
    def data(self) -> np.ndarray:
        """All variables, one column per name (computed on first use)."""
        if self._data is None:
            self._data = np.asarray(self._source.table(), dtype=np.float64)
        return self._data

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Result:
        """Read a result file by its extension: CSV (ours or an MSL reference), a Dymola or
        OpenModelica ``.mat`` result, or Parquet. Events and statistics are not in files."""
        names, data, parameters = resultio.read(path)
        result = cls(names, data, name=Path(path).stem)
        result.parameters = parameters
        return result

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str]) -> Result:
        """Read a result or MSL reference CSV (kept for old code; ``load`` reads every format)."""
        names, data = csvio.read_csv(path)
        return cls(names, data)

    # --- access -----------------------------------------------------------------------
    def __getitem__(self, name: str) -> np.ndarray:
        try:
            if self._data is not None:
                return self._data[:, self._index[name]]
            if name in self._columns:
                return self._columns[name]
            # by name to the engine (KeyError if unknown): a result of 28 000 names lists
            # them only when a column of the table is read
            if not self._source.is_direct(name):
                # the engine computes every variable for the first algebraic one: keep its
                # table, so that every later column is a view, not a copy each
                try:
                    return self.data[:, self._index[name]]
                except UsageError:
                    pass  # every variable at once does not fit in memory: this one alone
            # an angle, speed, mode, flag, the kinetic energy, or a variable that needs the
            # mode solve in few rows (a clutch's torque): computed alone, no table
            self._columns[name] = np.asarray(self._source.column(name), dtype=np.float64)
            return self._columns[name]
        except KeyError:
            close = difflib.get_close_matches(name, self.names, n=5, cutoff=0.5)
            hint = f"; did you mean {', '.join(repr(c) for c in close)}?" if close else ""
            raise KeyError(f"no signal {name!r} in the result{hint}") from None

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __len__(self) -> int:
        if self._data is None:
            return int(self._source.rows)
        return int(self._data.shape[0])

    def __repr__(self) -> str:
        label = f" {self.name!r}" if self.name else ""
        return f"<Result{label}: {len(self.names) - 1} signals, {len(self)} rows, {len(self.events)} events>"

    @property
    def time(self) -> np.ndarray:
        """The time column (event instants appear twice: left then right value)."""
        return self["time"]

    def unit(self, name: str) -> str:
        """The unit of a variable (``"N.m"`` for ``brake.tau``; "" if unknown or none)."""
        if name == "time":
            return "s"
        return self._info.unit(name) if self._info else ""

    # --- analysis ---------------------------------------------------------------------
    def energy(self, component: str, cumulative: bool = False) -> Any:
        """Energy dissipated by one component [J]: the integral of its ``lossPower``.

        The total (a float), or with ``cumulative=True`` its course over ``time``. Exact for
        a loss power linear between rows; event rows (a repeated time) add nothing.
        """
        name = f"{component}.lossPower"
        if name not in self:
            lossy = sorted({n.removesuffix(".lossPower") for n in self.names if n.endswith(".lossPower")})
            raise KeyError(f"{component!r} has no lossPower; components that dissipate: {', '.join(lossy)}")
        t, p = self.time, self[name]
        steps = np.concatenate(([0.0], 0.5 * (p[1:] + p[:-1]) * np.diff(t)))
        course = np.cumsum(steps)
        return course if cumulative else float(course[-1])

    def first(self, name: str, condition: Callable[[np.ndarray], np.ndarray] | None = None) -> float | None:
        """The first time a signal is true (nonzero), or meets ``condition``; None if never.

        ``r.first("clutch2.locked")``; ``r.first("J.w", lambda w: w < 1.0)``; or a comparison
        written out, as ``time_of`` in metrics takes it: ``r.first("J.w <= 0")``.

        A speed a locked element holds — its own relative speed (``brake.w``, ``clutch.w_rel``)
        or a shaft it holds against ground (``J.w`` behind a locked brake) — reads 0 here while
        it is locked: a lock leaves the slip where the event band stopped it (about ±1e-10
        rad/s), so ``J.w <= 0`` would otherwise miss a lock from below and ``J.w > 0`` see one
        from above as moving. The columns themselves keep the integrated values. (A result
        read from a file has no modes to read: its values are taken as they are.)
        """
        if condition is None and name not in self:
            compared = _COMPARISON.fullmatch(name)
            if compared is not None and compared.group(1) in self:
                name, op, bound = compared.group(1), _OPS[compared.group(2)], float(compared.group(3))
                condition = lambda v: op(v, bound)
        values = self._held_as_zero(name)
        hit = np.asarray(condition(values) if condition else values != 0.0, dtype=bool)
        rows = np.flatnonzero(hit)
        return float(self.time[rows[0]]) if rows.size else None

    def _held_as_zero(self, name: str) -> np.ndarray:
        """The column, 0 on the rows where a locked element holds it (a speed; see ``first``)."""
        values = self[name]
        if self._source is None or len(values) != len(self.time):
            return values
        held = np.asarray(self._source.held_rows(name), dtype=bool)
        return np.where(held, 0.0, values) if held.any() else values

    def lock_times(self, component: str) -> list[float]:
        """The instants a friction element becomes locked (its ``locked`` rises; t0 counts).

        For a shaft (``"J"``, an Inertia, without a ``locked`` of its own): the instants a
        locked element starts holding it against ground (a brake on it locks), read from the
        modes, not from its speed (see ``first``)."""
        if f"{component}.locked" not in self and f"{component}.w" in self and self._source is not None:
            locked = np.asarray(self._source.held_rows(f"{component}.w"), dtype=bool)
        else:
            locked = self[f"{component}.locked"] != 0.0
        rises = np.flatnonzero(locked[1:] & ~locked[:-1]) + 1
        times = [float(self.time[i]) for i in rises]
        return ([float(self.time[0])] if locked.size and locked[0] else []) + times

    # --- export -----------------------------------------------------------------------
    def to_pandas(self, events: str = "all") -> pandas.DataFrame:
        """The trajectories as a DataFrame; ``df.attrs["units"]`` gives each column's unit.

        ``events="all"``: every row, ``time`` an ordinary column (an event instant has two
        rows, left and right value). ``"last"`` or ``"first"``: one row per instant (the value
        after, or before, each event), indexed by ``time`` — unique and increasing, so
        ``resample``, ``interpolate`` and ``np.gradient`` work.
        """
        pd = _deps.pandas

        if events not in ("all", "first", "last"):
            raise ValueError(f'events must be "all", "first" or "last", got {events!r}')
        df = pd.DataFrame(self.data, columns=self.names)
        if events != "all":
            df = df.drop_duplicates(subset="time", keep=events).set_index("time")
        df.attrs["units"] = {n: self.unit(n) for n in self.names}
        return df

    def select(self, outputs: Iterable[str] | None = None) -> list[str]:
        """The names ``outputs`` choose (exact names or globs such as ``J*.w``), ``time``
        first, in column order; all names for None. An unknown name raises KeyError."""
        if outputs is None:
            return list(self.names)
        chosen: set[str] = {"time"}
        for pattern in outputs:
            if any(ch in pattern for ch in "*?["):
                matched = fnmatch.filter(self.names, pattern)
                if not matched:
                    raise KeyError(f"no signal in the result matches {pattern!r}")
                chosen.update(matched)
            else:
                self[pattern]  # the helpful KeyError
                chosen.add(pattern)
        return [n for n in self.names if n in chosen]

    def _table(self, outputs: Iterable[str] | None) -> tuple[list[str], np.ndarray]:
        names = self.select(outputs)
        if names == self.names:
            return names, self.data
        return names, np.column_stack([self[n] for n in names])

    def save(self, path: str | os.PathLike[str], outputs: Iterable[str] | None = None) -> None:
        """Write the result in the format of the extension: ``.csv``, ``.mat`` or ``.parquet``."""
        resultio.result_format(path)
        names, data = self._table(outputs)
        resultio.write(path, names, data, self.parameters)

    def to_csv(self, path: str | os.PathLike[str], outputs: Iterable[str] | None = None) -> None:
        """Write an MSL-style CSV (quoted header, full precision, integer modes)."""
        names, data = self._table(outputs)
        resultio.write_csv(path, names, data)

    def to_mat(self, path: str | os.PathLike[str], outputs: Iterable[str] | None = None) -> None:
        """Write a Dymola/OpenModelica result file (MATLAB v4: Aclass, name, description,
        dataInfo, data_1 with the parameters, data_2 with the trajectories)."""
        names, data = self._table(outputs)
        resultio.write_mat(path, names, data, self.parameters)

    def to_parquet(self, path: str | os.PathLike[str], outputs: Iterable[str] | None = None) -> None:
        """Write the trajectories as a Parquet table (one float64 column per name; pyarrow)."""
        names, data = self._table(outputs)
        resultio.write_parquet(path, names, data)

    def plot(
        self,
        *names: str | Sequence[str],
        path: str | os.PathLike[str] | None = None,
        ax: Axes | None = None,
    ) -> Figure:
        """Plot signals against time, one axes per argument (a name or names)."""
        from stiction.results.plotting import plot_result

        groups = [[n] if isinstance(n, str) else list(n) for n in names] or self._default_groups()
        for group in groups:
            for n in group:
                self[n]  # raises the helpful KeyError before anything is drawn
        return plot_result(self, groups, path=path, ax=ax)

    # --- text -------------------------------------------------------------------------
    def main_signals(self, limit: int = 8) -> list[str]:
        """The most telling signals (speeds, modes, torques …), in column order."""

        def rank(name: str) -> int:
            suffix = name.rsplit(".", 1)[-1]
            return _MAIN_SUFFIXES.index(suffix) if suffix in _MAIN_SUFFIXES else len(_MAIN_SUFFIXES)

        candidates = [n for n in self.names[1:] if "." in n]
        chosen = set(sorted(candidates, key=rank)[:limit])
        return [n for n in self.names if n in chosen]

    def _default_groups(self) -> list[list[str]]:
        groups: dict[str, list[str]] = {}
        for n in self.main_signals():
            groups.setdefault(n.rsplit(".", 1)[-1], []).append(n)
        return list(groups.values())

    def summary(self) -> str:
        """Describe the run in a few lines: span, events, final values, statistics."""
        t = self.time
        span = f"t = {t[0]:g} … {t[-1]:g} s" if len(t) else "no rows"
        title = f"{self.name}: " if self.name else ""
        lines = [f"{title}{span}, {len(self)} rows, {len(self.events)} events"]
        if self._info is not None:
            lines.append(f"experiment: {self._info.experiment}")
            lines.append(f"start values: {self._info.initialization.counts()} (r.initialization)")
        main = self.main_signals()
        if main and len(t):
            lines.append("final values:")
            width = max(len(n) for n in main)
            for n in main:
                v = float(self[n][-1])
                text = str(int(v)) if csvio.is_integer_signal(n) and v.is_integer() else f"{v:.6g}"
                lines.append(f"  {n:<{width}}  {text}")
        if self.stats:
            parts = []
            for key, value in self.stats.items():
                shown = f"{value:.3g}" if isinstance(value, float) and not math.isnan(value) else value
                parts.append(f"{key}={shown}")
            lines.append("stats: " + ", ".join(parts))
        return "\n".join(lines)
