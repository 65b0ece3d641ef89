"""A co-simulation slave for the cut tests: one FMU instance through FMPy's FMI 2.0 API."""

from __future__ import annotations

from pathlib import Path

import fmpy
from fmpy.fmi2 import FMU2Slave


class Slave:
    """One FMU instance through FMPy's FMI 2.0 co-simulation API."""

    def __init__(self, fmu: Path, name: str, stop: float) -> None:
        md = fmpy.read_model_description(fmu)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=fmpy.extract(fmu),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=0.0, stopTime=stop)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def set(self, values: dict[str, float]) -> None:
        self.fmu.setReal([self.vr[n] for n in values], list(values.values()))

    def get(self, *names: str) -> list[float]:
        return self.fmu.getReal([self.vr[n] for n in names])

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()
