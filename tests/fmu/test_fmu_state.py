"""Serialized FMU states (FMI 2.0 and 3.0), checked with FMPy: a state saved mid-run continues
bit for bit as the uninterrupted run, restored in the instance that saved it, in a new
instance from its serialized bytes and after ``reset``; bad bytes give an error status and a
logged message, and the instance stays usable."""

from __future__ import annotations

from collections.abc import Callable
from ctypes import byref
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Slave
from fmpy.logging import addLoggerProxy
from paths import REPO

import stiction as st

ROOT = REPO
COUPLED = ROOT / "examples" / "msl" / "CoupledClutches.toml"
FLYWHEEL = ROOT / "examples" / "braked_flywheel.toml"
CLUTCH_OUT = ["J1.w", "J2.w", "J3.w", "J4.w", "J1.phi", "clutch1.mode"]
FLY_OUT = ["flywheel.w", "flywheel.phi"]
FORCE = "brake.f_normalized"


def flywheel_with_input() -> st.Model:
    """The braked flywheel with its press ramp removed and the brake force a model input."""
    m = st.Model.load(FLYWHEEL)
    del m.components["press"]
    m.connections = [c for c in m.connections if "press.y" not in c]
    m.input(FORCE, start=0.0)
    return m


def force(t: float) -> float:
    """The brake force the host drives: a ramp from 0.5 s that holds at 1 from 1.5 s."""
    return float(np.clip(t - 0.5, 0.0, 1.0))


# FMPy's logger proxy forwards every FMI 2.0 message to the logger registered last: the
# loggers it was given must outlive the test run, or a later message calls a freed one
_LOGGERS: list[fmi2CallbackFunctions] = []


def fmi2_callbacks(messages: list[str]) -> fmi2CallbackFunctions:
    """FMI 2.0 callbacks whose logger appends each message to ``messages`` (kept alive)."""
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(lambda *a: messages.append(a[4].decode()))
    addLoggerProxy(byref(callbacks))
    _LOGGERS.append(callbacks)
    return callbacks


class Runner:
    """One FMPy slave of either FMI version, with a logger that keeps the messages."""

    def __init__(self, fmu: Path, version: int) -> None:
        self.version = version
        md = fmpy.read_model_description(fmu)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.messages: list[str] = []
        args = {"guid": md.guid, "unzipDirectory": fmpy.extract(fmu)}
        args["modelIdentifier"] = md.coSimulation.modelIdentifier
        if version == 2:
            self.callbacks = fmi2_callbacks(self.messages)
            self.slave = FMU2Slave(**args)
            self.slave.instantiate(callbacks=self.callbacks)
        else:
            self.slave = FMU3Slave(**args)
            self.slave.instantiate(
                logMessage=lambda env, status, cat, msg: self.messages.append(msg.decode())
            )

    def start(self, stop: float) -> None:
        if self.version == 2:
            self.slave.setupExperiment(startTime=0.0, stopTime=stop)
            self.slave.enterInitializationMode()
        else:
            self.slave.enterInitializationMode(startTime=0.0, stopTime=stop)
        self.slave.exitInitializationMode()

    def get(self, names: list[str]) -> list[float]:
        get = self.slave.getReal if self.version == 2 else self.slave.getFloat64
        return get([self.vr[n] for n in names])

    def set(self, name: str, value: float) -> None:
        set_ = self.slave.setReal if self.version == 2 else self.slave.setFloat64
        set_([self.vr[name]], [value])

    def save(self) -> object:
        return self.slave.getFMUstate() if self.version == 2 else self.slave.getFMUState()

    def restore(self, state: object) -> None:
        (self.slave.setFMUstate if self.version == 2 else self.slave.setFMUState)(state)

    def serialize(self, state: object) -> bytes:
        return (self.slave.serializeFMUstate if self.version == 2 else self.slave.serializeFMUState)(state)

    def deserialize(self, data: bytes) -> object:
        return (self.slave.deSerializeFMUstate if self.version == 2 else self.slave.deserializeFMUState)(data)

    def free_state(self, state: object) -> None:
        (self.slave.freeFMUstate if self.version == 2 else self.slave.freeFMUState)(state)

    def run(
        self, k: int, steps: int, h: float, outputs: list[str], drive: Callable[[float], float] | None
    ) -> np.ndarray:
        """Steps k … steps-1 of length h (the inputs driven at each point); the outputs after each."""
        rows = []
        for j in range(k, steps):
            if drive is not None:
                self.set(FORCE, drive(j * h))
            self.slave.doStep(j * h, h)
            rows.append(self.get(outputs))
        return np.array(rows)


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def version(request: pytest.FixtureRequest) -> int:
    return request.param


CASES = {
    "clutches": (lambda: st.Model.load(COUPLED), CLUTCH_OUT, 1.5, 0.01, 70, None),
    "flywheel": (flywheel_with_input, FLY_OUT, 3.0, 0.01, 100, force),
}


@pytest.mark.parametrize("case", CASES)
def test_a_serialized_state_continues_bit_for_bit(tmp_path: Path, version: int, case: str) -> None:
    make, outputs, stop, h, mid, drive = CASES[case]
    fmu = make().to_fmu(tmp_path / f"{case}.fmu", fmi_version=version, outputs=outputs)
    steps = round(stop / h)
    a = Runner(fmu, version)
    a.start(stop)
    a.run(0, mid, h, outputs, drive)
    saved = a.save()
    data = a.serialize(saved)
    assert data[:8] == b"STICFMUS"
    uninterrupted = a.run(mid, steps, h, outputs, drive)
    a.restore(saved)
    reference = a.run(mid, steps, h, outputs, drive)
    # the restored run is the uninterrupted one: the same values to the bit
    np.testing.assert_array_equal(reference, uninterrupted)

    b = Runner(fmu, version)  # a new instance, initialized with the defaults
    b.start(stop)
    state = b.deserialize(data)
    b.restore(state)
    if version == 3:
        assert b.get(["time"]) == [mid * h]
    np.testing.assert_array_equal(b.run(mid, steps, h, outputs, drive), reference)
    b.slave.reset()  # and after reset, not even initialized: the state carries its setup
    again = b.deserialize(data)
    b.restore(again)
    np.testing.assert_array_equal(b.run(mid, steps, h, outputs, drive), reference)
    assert b.serialize(again) == data  # the bytes of the restored state are the saved ones
    for runner, s in ((a, saved), (b, state), (b, again)):
        runner.free_state(s)
    for runner in (a, b):
        runner.slave.terminate()
        runner.slave.freeInstance()


def test_bad_bytes_give_an_error_and_the_instance_goes_on(tmp_path: Path, version: int) -> None:
    clutches = st.Model.load(COUPLED).to_fmu(tmp_path / "CC.fmu", fmi_version=version, outputs=CLUTCH_OUT)
    flywheel = flywheel_with_input().to_fmu(tmp_path / "Fly.fmu", fmi_version=version, outputs=FLY_OUT)
    other = Runner(flywheel, version)
    other.start(3.0)
    other.slave.doStep(0.0, 0.1)
    foreign = other.serialize(other.save())
    r = Runner(clutches, version)
    r.start(1.5)
    r.slave.doStep(0.0, 0.1)
    good = r.serialize(r.save())
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x10
    bad = {
        "truncated": (good[:-9], "checksum does not match"),
        "cut short": (good[:40], "checksum does not match"),
        "corrupted": (bytes(flipped), "checksum does not match"),
        "empty": (b"", "not a stiction FMU state"),
        "not a state": (b"x" * 200, "not a stiction FMU state"),
        "another model": (foreign, "saved by another model"),
    }
    for name, (data, message) in bad.items():
        with pytest.raises(FMICallException):
            r.deserialize(data)
        assert message in r.messages[-1], (name, r.messages[-1])
    r.slave.doStep(0.1, 0.1)  # the instance is unharmed
    assert r.get(["J1.w"])[0] == pytest.approx(float(np.interp(0.2, *_reference("J1.w"))), abs=1e-5)


def _reference(name: str) -> tuple[np.ndarray, np.ndarray]:
    ref = st.Model.load(COUPLED).simulate()
    return ref.time, ref[name]
