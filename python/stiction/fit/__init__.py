"""Friction from measurements: ``fit`` identifies parameters (brake and clutch tables, peak,
any sweepable number) from measured traces; ``FitResult`` holds the estimates, their
uncertainty and the fitted model.

``st.fit(...)`` is called as a function, and ``stiction.fit`` is also this package (importing
a submodule binds the package's name on ``stiction``): so the package itself is callable and
calling it is calling ``stiction.fit.api.fit``.
"""

import sys
import types
from typing import Any

from stiction.fit.api import fit
from stiction.fit.result import FitResult

__all__ = ["FitResult", "fit"]


class _CallablePackage(types.ModuleType):
    """This package, callable as ``fit`` (see the module docstring)."""

    def __call__(self, *args: Any, **kwargs: Any) -> FitResult:
        return fit(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
