"""The rig: the user's brake model made ready for the dynamometer.

The dyno drives the brake's ``f_normalized`` as a model input (declared here unless the model
declared it), stops either an inertia of the model or its own ``dyno_inertia`` joined to the
flange the schedule names, and reads the brake temperature variable. A schedule with drags
also gets the motor that holds the speed (``_add_motor``). Whatever it needs that the
model lacks is refused here, by name, before anything runs.
"""

from __future__ import annotations

from dataclasses import dataclass

from stiction.dynamometer.schedule import Rig, Schedule, ScheduleError
from stiction.errors import ModelError
from stiction.model.components import Component
from stiction.model.model import Model

__all__ = ["DYNO_COUPLING", "DYNO_INERTIA", "DYNO_MOTOR", "DYNO_SPEED", "Rigged", "rig_model"]

DYNO_INERTIA = "dyno_inertia"
DYNO_MOTOR, DYNO_COUPLING, DYNO_SPEED = "dyno_motor", "dyno_coupling", "dyno_speed"
ZERO_C = 273.15


@dataclass(frozen=True)
class Rigged:
    """The model as the dyno runs it and the names it drives and reads."""

    model: Model
    inertia: str  # the Inertia component the brake stops
    J: float
    pressure_input: str  # "<brake>.f_normalized"
    fn_max: float
    cgeo: float
    temperature: str
    ambients: list[str]  # FixedTemperature components: the ends of cooling paths
    motor: bool = False  # a Speed source and a coupling clutch hold the speed in drags


def rig_model(model: Model, schedule: Schedule) -> Rigged:
    """A copy of ``model`` ready for ``schedule``'s rig; ``ScheduleError`` naming what is
    missing (the brake, the inertia, a pressure input the model already drives)."""
    rig: Rig = schedule.rig
    where = f"{schedule.source}: [dyno] (line {rig.line})"
    rigged = Model.loads(model.to_toml(), base_dir=model.base_dir, default_name=model.name)
    comps = rigged.components
    if rig.brake not in comps:
        raise ScheduleError(f"{where}: brake '{rig.brake}' is not a component of model '{model.name}'")
    port = f"{rig.brake}.f_normalized"
    if port not in rigged.inputs:
        if any(port in pair for pair in rigged.connections):
            raise ScheduleError(
                f"{where}: the dyno drives {port}, which the model connects; leave it unconnected "
                "or declare it an input"
            )
        rigged.input(port, 0.0)
    values = rigged.parameter_values()
    fn_max = values.get(f"{rig.brake}.fn_max")
    if fn_max is None or fn_max <= 0:
        raise ScheduleError(f"{where}: brake '{rig.brake}' has no positive fn_max to press it with")
    if rig.inertia is not None:
        inertia = rig.inertia
        if inertia not in comps or comps[inertia].type != "Inertia":
            raise ScheduleError(f"{where}: inertia '{inertia}' is not an Inertia of model '{model.name}'")
        J = values.get(f"{inertia}.J")
        if J is None:
            raise ScheduleError(f"{where}: inertia '{inertia}': J is not a number")
    else:
        assert rig.flange is not None and rig.J is not None  # the schedule checked it
        inertia, J = DYNO_INERTIA, rig.J
        if DYNO_INERTIA in comps:
            raise ScheduleError(f"{where}: the model has a component '{DYNO_INERTIA}', the dyno's name")
        rigged.add(DYNO_INERTIA, Component("Inertia", {"J": J}))
        try:
            rigged.connect(f"{DYNO_INERTIA}.flange_a", rig.flange)
        except ModelError as exc:  # the model's words on the flange
            raise ScheduleError(f"{where}: flange '{rig.flange}': {exc}") from None
    ambients = [name for name, c in comps.items() if c.type == "FixedTemperature"]
    motor = any(section.kind == "drags" for section in schedule.sections)
    if motor:
        _add_motor(rigged, inertia, where)
    return Rigged(
        model=rigged,
        inertia=inertia,
        J=float(J),
        pressure_input=port,
        fn_max=float(fn_max),
        cgeo=float(values.get(f"{rig.brake}.cgeo", 1.0)),
        temperature=rig.temperature or f"{rig.brake}.heatPort.T",
        ambients=ambients,
        motor=motor,
    )


def _add_motor(model: Model, inertia: str, where: str) -> None:
    """The motor that holds the speed in a drag: a ``Speed`` source following its reference
    exactly (a ``Constant`` whose ``k`` the dyno sets, a parameter event: a model input's
    derivative is unknown, a constant's is 0) and a coupling ``Clutch`` to the inertia's free
    flange, open (``f_normalized = 0``, no torque) except during a drag, where it locks."""
    for name in (DYNO_MOTOR, DYNO_COUPLING, DYNO_SPEED):
        if name in model.components:
            raise ScheduleError(f"{where}: the model has a component '{name}', the dyno's name")
    used = {end for pair in model.connections for end in pair}
    free = [f"{inertia}.{f}" for f in ("flange_b", "flange_a") if f"{inertia}.{f}" not in used]
    if not free:
        raise ScheduleError(f"{where}: drags need a free flange on inertia '{inertia}' for the dyno's motor")
    model.add(DYNO_SPEED, Component("Constant", {"k": 0.0}))
    model.add(DYNO_MOTOR, Component("Speed", {"exact": True}))
    model.connect(f"{DYNO_SPEED}.y", f"{DYNO_MOTOR}.w_ref")
    model.add(
        DYNO_COUPLING, Component("Clutch", {"fn_max": 1e9, "mu_pos": [[0.0, 1.0]], "cgeo": 1.0, "peak": 1.0})
    )
    model.connect(f"{DYNO_MOTOR}.flange", f"{DYNO_COUPLING}.flange_a")
    model.connect(f"{DYNO_COUPLING}.flange_b", free[0])
    model.input(f"{DYNO_COUPLING}.f_normalized", 0.0)
