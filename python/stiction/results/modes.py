"""Names of MSL's friction modes, for event logs, summaries and plot axes."""

from __future__ import annotations

__all__ = ["MODE_NAMES", "mode_name"]

MODE_NAMES = {-1: "sliding backward", 0: "stuck", 1: "sliding forward", 2: "free", 3: "unknown"}
"""MSL's friction modes (``Backward``, ``Stuck``, ``Forward``, ``Free``, ``Unknown``); 3
(Unknown) is only the value before initialization, the ``old_mode`` of the first events."""


def mode_name(mode: int) -> str:
    """``"sliding forward"`` for 1 and so on (see ``MODE_NAMES``)."""
    return MODE_NAMES.get(int(mode), f"mode {mode}")
