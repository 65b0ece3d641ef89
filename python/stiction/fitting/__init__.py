"""Friction from measurements: ``fit`` identifies parameters (brake and clutch tables, peak,
any sweepable number) from measured traces; ``FitResult`` holds the estimates, their
uncertainty and the fitted model.

The package is ``fitting``, not ``fit``: importing a subpackage binds its name on ``stiction``,
which would replace the public function ``st.fit`` (as ``expressions`` leaves ``st.expr`` be).
"""

from stiction.fitting.api import fit
from stiction.fitting.result import FitResult

__all__ = ["FitResult", "fit"]
