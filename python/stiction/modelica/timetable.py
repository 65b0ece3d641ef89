"""MSL ``CombiTimeTable`` ⇄ stiction ``TimeTable``.

A ``CombiTimeTable`` with an inline table and linear segments is a ``TimeTable``: import reads
it as one. With one output column ``table.y[1]`` is ``table.y``; with several, ``table.y[i]``
is the TimeTable's port ``y[i]``. Export writes a ``TimeTable`` as a ``CombiTimeTable`` (a
file-backed one with its table inlined, as MSL tools want the data in the model).
"""

from __future__ import annotations

from typing import Any

from stiction.expressions.lexer import ModelicaError
from stiction.modelica.ast import Declaration

__all__ = ["COMBI_CLASS", "COMBI_PARAMETERS", "combi_time_table", "time_table_modifiers"]

COMBI_CLASS = "Modelica.Blocks.Sources.CombiTimeTable"
COMBI_PARAMETERS = ("table", "columns", "smoothness", "extrapolation", "offset", "startTime", "tableOnFile")


def combi_time_table(name: str, decl: Declaration, params: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    """The TimeTable parameters of a CombiTimeTable declaration; refuses what differs."""

    def refuse(key: str, why: str) -> ModelicaError:
        pos = next((m.pos for m in decl.args if m.name == key), decl.pos)
        return ModelicaError(pos, f"CombiTimeTable '{name}': {why}")

    if params.get("tableOnFile", False):
        raise refuse("tableOnFile", "tables read from a .mat/.txt file are not supported; inline the table")
    if params.get("smoothness", "LinearSegments") != "LinearSegments":
        raise refuse("smoothness", "only smoothness = LinearSegments is supported")
    if "table" not in params:
        raise refuse("table", "missing 'table'")
    widths = {len(row) for row in params["table"] if isinstance(row, list)}
    if len(widths) > 1:
        raise refuse("table", f"rows of different lengths {sorted(widths)}")
    width = widths.pop() if widths else 2
    if width < 2:
        raise refuse("table", "a table needs a time column and at least one value column")
    out: dict[str, Any] = {"table": params["table"]}
    columns = params.get("columns", list(range(2, width + 1)))
    if not isinstance(columns, list) or not columns:
        raise refuse("columns", "columns must be an array of column indices {2, …}")
    for c in columns:
        if not isinstance(c, (int, float)) or c != int(c) or not 2 <= c <= width:
            raise refuse("columns", f"column {c} is not a value column of the table (2 to {width})")
    if columns != list(range(2, width + 1)):
        out["columns"] = [int(c) for c in columns]
    extrapolation = params.get("extrapolation", "LastTwoPoints")
    if extrapolation not in ("LastTwoPoints", "HoldLastPoint"):
        raise refuse("extrapolation", "extrapolation must be LastTwoPoints or HoldLastPoint")
    if extrapolation != "LastTwoPoints":
        out["extrapolation"] = extrapolation
    offset = params.get("offset", [0.0])
    if not isinstance(offset, list) or len(offset) not in (1, len(columns)):
        raise refuse(
            "offset",
            f"offset must have one value or one per output column ({len(columns)}), got {offset}",
        )
    if any(o != 0 for o in offset):
        out["offset"] = float(offset[0]) if len(offset) == 1 else [float(o) for o in offset]
    if "startTime" in params:
        out["startTime"] = params["startTime"]
    return "TimeTable", out


def time_table_modifiers(params: dict[str, Any], table: list[list[float]]) -> dict[str, Any]:
    """CombiTimeTable modifiers for a TimeTable whose rows are ``table``."""
    out: dict[str, Any] = {"table": table}
    if "columns" in params:
        out["columns"] = params["columns"]
    if "extrapolation" in params:
        out["extrapolation"] = params["extrapolation"]
    if "offset" in params:
        offset = params["offset"]
        out["offset"] = offset if isinstance(offset, list) else [offset]
    if "startTime" in params:
        out["startTime"] = params["startTime"]
    return out
