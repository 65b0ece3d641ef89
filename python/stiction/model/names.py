"""Hierarchical names: a component's name is a dotted path of identifiers (``front.clutch``,
as Modelica tools flatten a user's class); its ports and parameters are one more segment
(``front.clutch.flange_a``, ``front.clutch.peak``), its variables one or more
(``front.clutch.flange_a.tau``). The engine reads them the same way (``model/names.rs``)."""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["COMPONENT_NAME", "IDENTIFIER", "owner", "prefix_clash", "split_last"]

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
COMPONENT_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*")


def split_last(name: str) -> tuple[str, str]:
    """``(component, last)``: ``name`` split at its last dot (a port, a parameter or a start
    value is the last segment; a table cell ``mu_pos[1,2]`` has no dot); ``(name, "")``
    without one, as ``str.partition`` has it."""
    head, dot, last = name.rpartition(".")
    return (head, last) if dot else (name, "")


def owner(variable: str, components: Iterable[str]) -> str | None:
    """The component a variable belongs to: the longest of ``components`` that is
    ``variable`` or a dotted prefix of it (``front.clutch`` for ``front.clutch.flange_a.tau``)."""
    best: str | None = None
    for name in components:
        if (variable == name or variable.startswith(name + ".")) and (best is None or len(name) > len(best)):
            best = name
    return best


def prefix_clash(name: str, components: Iterable[str]) -> str | None:
    """A component whose name starts ``name``'s path or whose path ``name`` starts (``front``
    and ``front.clutch``: ``front.clutch.w`` would name a variable of both); None if none."""
    for other in components:
        if other.startswith(name + ".") or name.startswith(other + "."):
            return other
    return None
