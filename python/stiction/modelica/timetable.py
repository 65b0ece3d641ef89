"""MSL ``CombiTimeTable`` ⇄ stiction ``TimeTable``.

A ``CombiTimeTable`` with an inline table, one output column and linear segments is a
``TimeTable``: import reads it as one (``table.y[1]`` is ``table.y``), and export writes a
file-backed ``TimeTable`` as a ``CombiTimeTable`` with its table inlined, as MSL tools want
the data in the model.
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
    if params.get("columns", [2]) != [2]:
        raise refuse("columns", "only columns = {2} (one output) is supported")
    if params.get("smoothness", "LinearSegments") != "LinearSegments":
        raise refuse("smoothness", "only smoothness = LinearSegments is supported")
    if "table" not in params:
        raise refuse("table", "missing 'table'")
    widths = {len(row) for row in params["table"] if isinstance(row, list)}
    if widths and max(widths) > 2:
        raise refuse("table", f"only one output column is supported, the table has {max(widths) - 1}")
    out: dict[str, Any] = {"table": params["table"]}
    extrapolation = params.get("extrapolation", "LastTwoPoints")
    if extrapolation not in ("LastTwoPoints", "HoldLastPoint"):
        raise refuse("extrapolation", "extrapolation must be LastTwoPoints or HoldLastPoint")
    if extrapolation != "LastTwoPoints":
        out["extrapolation"] = extrapolation
    offset = params.get("offset", [0.0])
    if not isinstance(offset, list) or len(offset) != 1:
        raise refuse("offset", "offset must be a one-element array {o}")
    if offset != [0.0] and offset != [0]:
        out["offset"] = float(offset[0])
    if "startTime" in params:
        out["startTime"] = params["startTime"]
    return "TimeTable", out


def time_table_modifiers(params: dict[str, Any], table: list[list[float]]) -> dict[str, Any]:
    """CombiTimeTable modifiers for a file-backed TimeTable whose rows are ``table``."""
    out: dict[str, Any] = {"table": table}
    if "extrapolation" in params:
        out["extrapolation"] = params["extrapolation"]
    if "offset" in params:
        out["offset"] = [params["offset"]]
    if "startTime" in params:
        out["startTime"] = params["startTime"]
    return out
