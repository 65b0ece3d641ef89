"""The model-error type, shared by the compiled core and the Python layer.

The real ``ModelError`` lives in the compiled module ``stiction._core`` so that errors
raised in Rust and in Python are one class. When the compiled module is not built
(pure-Python tests of the CSV and comparison code), a stand-in with the same base class
is used instead.
"""

from __future__ import annotations

__all__ = ["ModelError", "core_available"]

try:
    from ._core import ModelError
except ModuleNotFoundError as exc:  # only "not built"; a broken build must still fail loudly
    if exc.name != f"{__package__}._core":
        raise

    class ModelError(ValueError):  # type: ignore[no-redef]
        """A model is invalid; the message names the component and parameter or port."""

    _CORE = False
else:
    _CORE = True


def core_available() -> bool:
    """Tell whether the compiled engine is importable (true in any installation)."""
    return _CORE
