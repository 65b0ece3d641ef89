"""Friction from measurements: ``fit`` identifies parameters (brake and clutch tables, peak,
any sweepable number) from measured traces; ``FitResult`` holds the estimates, their
uncertainty and the fitted model."""

from stiction.fit.fit import fit
from stiction.fit.result import FitResult

__all__ = ["FitResult", "fit"]
