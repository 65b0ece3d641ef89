"""Hierarchical names: a component's name is a dotted path of identifiers (``front.clutch``,
as Modelica tools flatten a user's class); its ports and parameters are one more segment
(``front.clutch.flange_a``, ``front.clutch.peak``), its variables one or more
(``front.clutch.flange_a.tau``). The engine reads them the same way (``model/names.rs``)."""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

__all__ = ["COMPONENT_NAME", "IDENTIFIER", "PathIndex", "owner", "split_last"]

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


class PathIndex:
    """The dotted heads of a model's component names (``front`` of ``front.clutch``), to refuse
    a name that starts another component's path or that another's name starts: with ``front``
    beside ``front.clutch``, ``front.clutch.w`` would name a variable of both. Kept as names
    are added; rebuilt when the components were changed directly."""

    def __init__(self) -> None:
        self.count = 0
        self.heads: dict[str, str] = {}  # head -> a component whose path it starts

    @staticmethod
    def heads_of(name: str) -> list[str]:
        if "." not in name:  # most names: no path, nothing to split
            return []
        parts = name.split(".")
        return [".".join(parts[:k]) for k in range(1, len(parts))]

    def clash(self, name: str, components: Mapping[str, object]) -> str | None:
        """A component of ``components`` whose path ``name`` starts or that starts ``name``'s."""
        seen = self.heads.get(name)
        if seen is not None and seen not in components or self.count != len(components):
            self.heads = {h: other for other in components for h in self.heads_of(other)}
            self.count = len(components)
        return self.heads.get(name) or next((h for h in self.heads_of(name) if h in components), None)

    def refusal(self, name: str, components: Mapping[str, object]) -> str | None:
        """Why ``name`` cannot be added to ``components`` (not a path of identifiers, a path
        clash), or None; a name that passes is recorded."""
        if not COMPONENT_NAME.fullmatch(name):
            return f"component name '{name}' is not an identifier or a path of them ('front.clutch')"
        other = self.clash(name, components)
        if other is not None:
            return (
                f"component '{name}': the name and component '{other}' start the same path: their "
                "variables would be ambiguous; rename one"
            )
        self.added(name)
        return None

    def added(self, name: str) -> None:
        """Record ``name``, just added to the components."""
        self.heads.update(dict.fromkeys(self.heads_of(name), name))
        self.count += 1
