"""Writing a ``Model`` as a Modelica model: fully qualified MSL classes, modifiers, derived
variables, ``connect`` equations and the experiment annotation, in plain Modelica that
``Model.from_modelica`` (and any Modelica tool) reads back to the same model.

A hierarchical component name (``front.clutch``, from a user's class flattened on import) is
written as a quoted identifier, ``Clutch 'front.clutch'(…)``, and so are the references to it
(``'front.clutch'.flange_a``, ``'front.clutch'.w_rel``): valid Modelica, which the importer
reads back to the component ``front.clutch``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from stiction.errors import ModelError
from stiction.expressions.evaluate import format_literal
from stiction.model.catalogue import catalogue
from stiction.model.components import START_VARIABLES
from stiction.model.names import owner
from stiction.model.parameters import is_expr, is_table
from stiction.model.quantities import is_quantity, si_base
from stiction.modelica.names import FADE_CLASSES, FADE_PARAMETERS, MSL_CLASSES, WEAR_ANNOTATION
from stiction.modelica.timetable import COMBI_CLASS, time_table_modifiers

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["write_modelica"]

_ENUMS = {
    "reg": "Modelica.Mechanics.Rotational.Types.Regularization",
    "extrapolation": "Modelica.Blocks.Types.Extrapolation",
    "smoothness": "Modelica.Blocks.Types.Smoothness",
}
_EXPERIMENT = ("StartTime", "StopTime", "Interval", "Tolerance")
# a (dotted) name in an expression, not inside a number (1.5e3) or a quoted identifier
_DOTTED = re.compile(r"(?<![\w.'])[A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+")


def write_modelica(model: Model) -> str:
    """Modelica text of ``model``."""
    if not model.name.isidentifier():
        raise ModelError(f"model name '{model.name}' is not a Modelica identifier")
    if model.inputs:
        raise ModelError("a model with inputs (unconnected signal inputs) has no Modelica form here")
    lines = [f"model {model.name}"]
    for name, value in model.parameters.items():
        lines.append(f"  {_parameter(name, value, model.declarations.get(name, {}))};")
    for name, comp in model.components.items():
        lines.append(f"  {_declaration(model, name, comp.type, comp.params)};")
    for name, expression in model.variables.items():
        lines.append(f"  Real {name} = {_quoted_names(model, expression)};")
    lines.append("equation")
    for a, b in model.connections:
        lines.append(f"  connect({_end(model, a)}, {_end(model, b)});")
    experiment = [
        f"{k}={format_literal(float(model.experiment[k]))}" for k in _EXPERIMENT if k in model.experiment
    ]
    if "Solver" in model.experiment:
        experiment.append(f'__stiction_Solver="{model.experiment["Solver"]}"')
    if experiment:
        lines.append(f"  annotation(experiment({', '.join(experiment)}));")
    lines.append(f"end {model.name};")
    return "\n".join(lines) + "\n"


def _quoted(name: str) -> str:
    """A component's name as Modelica writes it: a dotted path quoted (``'front.clutch'``)."""
    return f"'{name}'" if "." in name else name


def _reference(model: Model, name: str) -> str:
    """A variable or port of a component, its component's path quoted where dotted."""
    comp = owner(name, model.components)
    return name if comp is None or "." not in comp else _quoted(comp) + name[len(comp) :]


def _quoted_names(model: Model, expression: str) -> str:
    """An expression with its references to dotted components quoted."""
    if not any("." in n for n in model.components):
        return expression
    return _DOTTED.sub(lambda m: _reference(model, m.group()), expression)


def _is_combi(model: Model, name: str) -> bool:
    """Whether a TimeTable needs MSL's CombiTimeTable: a file, an extrapolation, several
    columns or offsets; else MSL's one-column TimeTable says it."""
    comp = model.components[name]
    if comp.type != "TimeTable":
        return False
    table = comp.params.get("table")
    wide = isinstance(table, list) and any(isinstance(r, list) and len(r) > 2 for r in table)
    return (
        wide
        or isinstance(comp.params.get("offset"), list)
        or any(key in comp.params for key in ("file", "extrapolation", "columns"))
    )


def _end(model: Model, end: str) -> str:
    comp, _, port = end.rpartition(".")
    text = _reference(model, end)
    return f"{text}[1]" if _is_combi(model, comp) and port == "y" else text


def _declaration(model: Model, name: str, ctype: str, params: dict[str, Any]) -> str:
    if ctype not in MSL_CLASSES:
        raise ModelError(f"component '{name}' ({ctype}): no MSL class to export it as")
    cls = MSL_CLASSES[ctype]
    if ctype in FADE_CLASSES and any(key in params for key in FADE_PARAMETERS):
        cls = FADE_CLASSES[ctype]  # beyond the MSL (docs/fade.md)
    if _is_combi(model, name):
        cls, params = COMBI_CLASS, time_table_modifiers(params, _table_rows(model, name, params))
    wear = params.get("wear")
    params = {k: v for k, v in params.items() if k != "wear"}
    starts = _start_variables(ctype)
    mods = [_modifier(key, value, key in starts) for key, value in params.items()]
    text = f"{cls} {_quoted(name)}({', '.join(mods)})" if mods else f"{cls} {_quoted(name)}"
    return text + _wear_annotation(wear) if wear else text


def _wear_annotation(wear: Mapping[str, Any]) -> str:
    """A friction element's wear record as stiction's own annotation, which other tools
    ignore: `` annotation(__stiction_wear(kind="energy", alpha=2e-13))`` (docs/wear.md; the
    record's `model` is `kind` there, `model` being a Modelica keyword)."""
    args = ", ".join(f"{'kind' if k == 'model' else k}={format_literal(v)}" for k, v in wear.items())
    return f" annotation({WEAR_ANNOTATION}({args}))"


def _parameter(name: str, value: Any, declared: Mapping[str, Any]) -> str:
    """``parameter Type name(attributes) = value "description"``, as it was declared."""
    if not name.isidentifier():
        raise ModelError(f"parameter name '{name}' is not a Modelica identifier")
    if isinstance(value, list):
        raise ModelError(f"parameter '{name}': array parameters have no Modelica export here")
    kind = "Boolean" if isinstance(value, bool) else "Integer" if isinstance(value, int) else "Real"
    kind = declared.get("type", kind)
    attrs = [
        f"{key}={format_literal(v)}" for key, v in declared.items() if key not in ("type", "description")
    ]
    if isinstance(value, str) and is_quantity(value):  # "60 rpm": Modelica has the SI number
        value = si_base(value, f"parameter '{name}'")
    text = value if isinstance(value, str) else format_literal(value)
    line = (
        f"parameter {kind} {name}({', '.join(attrs)}) = {text}"
        if attrs
        else f"parameter {kind} {name} = {text}"
    )
    description = declared.get("description")
    return f"{line} {format_literal(description)}" if description else line


def _start_variables(ctype: str) -> frozenset[str]:
    """The names of ``ctype`` that are start values (``J.w``), not parameters: a
    ``FixedTemperature``'s ``T`` is a parameter, a ``HeatCapacitor``'s the start of a state."""
    info = catalogue().get(ctype)
    if info is None:
        return START_VARIABLES
    parameters = {p.name for p in info.parameters if "start value" not in p.kind}
    return START_VARIABLES - parameters


def _modifier(key: str, value: Any, is_start: bool) -> str:
    """One modification: a start value as ``w(start=…, fixed=…)``, a parameter as ``k=…``."""
    if is_start and is_expr(value):
        return f"{key}(start={value['expr']}, fixed=true)"
    if is_expr(value):
        return f"{key}={value['expr']}"
    if key in _ENUMS and isinstance(value, str):
        return f"{key}={_ENUMS[key]}.{value}"
    if is_start and isinstance(value, dict):
        attrs = ", ".join(f"{k}={v['expr'] if is_expr(v) else format_literal(v)}" for k, v in value.items())
        return f"{key}({attrs})"
    if is_start and isinstance(value, (int, float)) and not isinstance(value, bool):
        return f"{key}(start={format_literal(float(value))}, fixed=true)"
    if is_table(value):  # a cell may be an expression over parameters: [0, mu0; 100, 0.9 * mu0]
        rows = (", ".join(c if isinstance(c, str) else format_literal(c) for c in row) for row in value)
        return f"{key}=[{'; '.join(rows)}]"
    try:
        return f"{key}={format_literal(value)}"
    except ValueError as exc:
        raise ModelError(f"parameter '{key}': {exc}") from None


def _table_rows(model: Model, name: str, params: dict[str, Any]) -> list[list[float]]:
    if "table" in params:
        return params["table"]
    from stiction.results.io.csv import read_csv

    path = model.base_dir / str(params["file"])
    try:
        _, data = read_csv(path)
    except (OSError, ValueError) as exc:
        raise ModelError(f"component '{name}' (TimeTable): cannot inline '{path}': {exc}") from None
    return data.tolist()
