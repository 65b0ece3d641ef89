"""From a parsed ``.mo`` file to a ``Model``: choose the class, resolve names, evaluate
parameters, turn modifiers into component parameters, connections and the experiment.

Top-level parameters are evaluated (in any order, cycles refused) and their values put into
the components; variables with a binding become derived result columns (``Model.variables``).
Every refusal names the construct at its ``file:line:column``. The whole model is converted
and every error collected, with the parser's, into one ModelicaError listing them by place;
a name whose own error is reported (an unknown class, a parameter that cannot be evaluated, a
refused declaration) is not reported again where it is used.
"""

from __future__ import annotations

import functools
import re
from typing import TYPE_CHECKING, Any

from stiction.errors import ModelError
from stiction.expressions.ast import Literal, Ref
from stiction.expressions.evaluate import MSL_CONSTANTS as CONSTANTS
from stiction.expressions.evaluate import evaluate, python_value, unparse
from stiction.expressions.lexer import ModelicaError, Pos
from stiction.model.components import START_VARIABLES, Component, component_types
from stiction.model.modelfile import DECLARATION_KEYS
from stiction.model.names import PathIndex, owner
from stiction.model.parameters import is_expr, resolve_params
from stiction.modelica.ast import ClassDef, Declaration, Modification, StoredDefinition
from stiction.modelica.connections import ConnectionSets
from stiction.modelica.connections import Reported as _Reported
from stiction.modelica.flatten import flatten, rewrite, uses_classes
from stiction.modelica.names import (
    MSL_CLASSES,
    PARAMETER_RENAMES,
    TYPE_OF,
    WEAR_ANNOTATION,
    Scope,
    is_enumeration,
    is_icon,
    is_unit_type,
)
from stiction.modelica.nominal import PHI_NOMINAL, phi_nominal, positive_nominal, with_phi_nominal
from stiction.modelica.parser import SUPPORTED
from stiction.modelica.timetable import COMBI_PARAMETERS, combi_time_table
from stiction.modelica.value_check import always_valid, value_problems

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["IGNORED_MODIFIERS", "convert", "select_class"]

# Modifiers that choose states in Modelica and have no effect here (states are the node angles
# and speeds; `nominal`s scale their error control, `stiction.modelica.nominal`).
IGNORED_MODIFIERS = frozenset(("stateSelect",))
INTEGER_PARAMETERS = frozenset(("nperiod", "columns"))
_ATTRIBUTES = ("start", "fixed", "nominal", "stateSelect", "unit", "displayUnit", "quantity", "min", "max")
_EXPERIMENT = ("StartTime", "StopTime", "Interval", "Tolerance")
_TYPES = {"Real": (int, float), "Integer": (int,), "Boolean": (bool,), "String": (str,)}


def select_class(tree: StoredDefinition, wanted: str | None, source: str) -> tuple[ClassDef, str, list]:
    """The model to convert, its enclosing package path and the classes around it."""
    found: list[tuple[ClassDef, str, list[ClassDef]]] = []

    def walk(classes: list[ClassDef], prefix: str, outer: list[ClassDef]) -> None:
        for cls in classes:
            qualified = f"{prefix}.{cls.name}" if prefix else cls.name
            if cls.kind == "package":
                walk(cls.classes, qualified, [*outer, cls])
            else:
                found.append((cls, prefix, [*outer, cls]))

    walk(tree.classes, tree.within, [])
    if wanted is not None:
        matches = [f for f in found if wanted in (f[0].name, f"{f[1]}.{f[0].name}")]
        if not matches:
            names = ", ".join(c.name for c, _, _ in found) or "none"
            raise ModelicaError(Pos(source, 1, 1), f"no model '{wanted}' in the file (models: {names})")
        return matches[0]
    if len(found) != 1:
        names = ", ".join(c.name for c, _, _ in found) or "none"
        raise ModelicaError(
            Pos(source, 1, 1), f"the file holds several models ({names}); choose one with model="
        )
    return found[0]


def convert(tree: StoredDefinition, wanted: str | None, source: str, base_dir: str) -> Model:
    """Build the Model of class ``wanted`` (or the only one) of a parsed file; raise one
    ModelicaError listing every error of the file (the parser's refusals included)."""
    try:
        cls, enclosing, chain = select_class(tree, wanted, source)
    except ModelicaError as exc:
        raise ModelicaError.of([*tree.refused, exc]) from None
    local = {c.name: f"{enclosing}.{c.name}" if enclosing else c.name for c in _all_classes(tree.classes)}
    imports = [imp for c in chain for imp in c.imports]
    scope = Scope(enclosing, imports, local)
    classes = _class_table(tree, local)
    flat_errors: list[ModelicaError] = []
    connectors: dict[str, tuple[str, Pos]] = {}
    if uses_classes(cls, scope, classes):  # users' classes: flattened to MSL components
        qualified = f"{enclosing}.{cls.name}" if enclosing else cls.name
        flat = flatten(qualified, classes)
        cls, connectors, flat_errors = flat.cls, flat.connectors, flat.errors
    converter = _Converter(cls, scope, base_dir, connectors)
    model = converter.run()
    errors = [*tree.refused, *flat_errors, *converter.errors]
    if errors:
        raise ModelicaError.of(errors)
    return model


def _class_table(tree: StoredDefinition, local: dict[str, str]) -> dict[str, tuple[ClassDef, Scope]]:
    """Every class of the file by qualified name, with the scope its names resolve in."""
    table: dict[str, tuple[ClassDef, Scope]] = {}

    def walk(classes: list[ClassDef], prefix: str, outer: list[ClassDef]) -> None:
        for cls in classes:
            qualified = f"{prefix}.{cls.name}" if prefix else cls.name
            chain = [*outer, cls]
            table[qualified] = (cls, Scope(prefix, [i for c in chain for i in c.imports], local))
            walk(cls.classes, qualified, chain)

    walk(tree.classes, tree.within, [])
    return table


def _all_classes(classes: list[ClassDef]) -> list[ClassDef]:
    out = []
    for c in classes:
        out.append(c)
        out.extend(_all_classes(c.classes))
    return out


class _Converter(ConnectionSets):
    """One model's conversion. Each step raises ModelicaError at the construct it refuses
    (or _Reported for a name already refused); ``run`` collects them in ``errors`` and goes on
    with the next declaration, modifier, connection or variable."""

    def __init__(
        self, cls: ClassDef, scope: Scope, base_dir: str, connectors: dict[str, tuple[str, Pos]] | None = None
    ) -> None:
        from stiction.model.model import Model

        self.cls = cls
        self.scope = scope
        self.model = Model(cls.name, base_dir=base_dir)
        self.params: dict[str, Declaration] = {}
        self.values: dict[str, Any] = {}
        self.evaluating: list[str] = []
        self.components: dict[str, tuple[str, Declaration]] = {}
        self.paths = PathIndex()  # a quoted 'front.clutch' beside front: refused, placed
        self.variables: list[Declaration] = []
        self.positions: dict[tuple[str, str], Pos] = {}  # (component, parameter) -> modifier
        self.connectors = connectors or {}  # a user class's interface: flat name -> kind, place
        self.init_connections()
        self.inlining: list[str] = []  # cross references being put in (a cycle is refused)
        self.errors: list[ModelicaError] = []
        self.reported: set[str] = set()  # declarations with an error: their uses are not checked
        self.unchecked: set[str] = set()  # components with a refused value: not the engine's to check

    def run(self) -> Model:
        """The model; what is wrong is in ``errors`` (the model is then incomplete)."""
        errors = self.errors
        for name, pos in self.cls.extends:
            try:
                if not is_icon(self.scope.resolve(name, pos)):
                    raise ModelicaError(
                        pos, f"unsupported 'extends {name}'; only Modelica.Icons.* is ignored"
                    )
            except ModelicaError as exc:
                errors.append(exc)
        for decl in self.cls.declarations:
            try:
                self.classify(decl)
            except ModelicaError as exc:
                errors.append(exc)
                self.reported.add(decl.name)
        for name in self.params:
            if name in self.reported:
                continue
            try:
                self.parameter(name)
            except ModelicaError as exc:
                errors.append(exc)
                self.reported.update(self.evaluating)  # each waits for the one that failed
            except _Reported:
                self.reported.update(self.evaluating)
            self.evaluating.clear()
        parameters = self.model.parameters
        self.model.parameters = {n: parameters[n] for n in self.params if n in parameters}  # declared order
        for name, (stype, decl) in self.components.items():
            self.component(name, stype, decl)
        for conn in self.cls.connects:
            self.connect(conn)
        self.finish_connections()
        for decl in self.variables:
            try:
                self.variable(decl)
            except ModelicaError as exc:
                errors.append(exc)
                self.reported.add(decl.name)
            except _Reported:
                self.reported.add(decl.name)
        self.experiment()
        self.engine_check()
        return self.model

    # --- declarations -------------------------------------------------------------------
    def classify(self, decl: Declaration) -> None:
        if decl.name in self.params or decl.name in self.components:
            raise ModelicaError(decl.pos, f"'{decl.name}' is declared twice")
        if decl.refused:  # the parser reported it
            self.reported.add(decl.name)
            return
        full = self.scope.resolve(decl.type_name, decl.type_pos)
        if full in _TYPES or is_unit_type(full):
            decl.type_name = full
            if decl.prefix in ("parameter", "constant"):
                self.params[decl.name] = decl
            elif decl.prefix == "input":
                raise ModelicaError(decl.pos, f"unsupported top-level input '{decl.name}'; {SUPPORTED}")
            elif decl.binding is None:
                raise ModelicaError(
                    decl.pos,
                    f"variable '{decl.name}' has no binding; equations other than connect(…) are not "
                    "supported, so declare it as 'Real x = expression;'",
                )
            else:
                self.variables.append(decl)
        elif full in TYPE_OF:
            if (problem := self.paths.refusal(decl.name, self.components)) is not None:
                raise ModelicaError(decl.pos, problem)
            self.components[decl.name] = (TYPE_OF[full], decl)
        elif full.startswith("Modelica."):
            known = ", ".join(sorted(t.split(".")[-1] for t in TYPE_OF))
            raise ModelicaError(
                decl.type_pos,
                f"unknown MSL class '{full}' (component '{decl.name}'); stiction implements {known}",
            )
        else:
            raise ModelicaError(
                decl.type_pos,
                f"component '{decl.name}' of class '{decl.type_name}': only MSL components and "
                "models/blocks of this file can be instantiated (not a package)",
            )

    def parameter(self, name: str) -> Any:
        if name in self.values:
            return self.values[name]
        decl = self.params[name]
        if name in self.evaluating:
            cycle = " -> ".join([*self.evaluating[self.evaluating.index(name) :], name])
            raise ModelicaError(decl.pos, f"cyclic parameter definition: {cycle}")
        if decl.binding is None:
            raise ModelicaError(decl.pos, f"parameter '{name}' has no value (write '{name} = …')")
        self.evaluating.append(name)
        value = python_value(self.expression(decl.binding))
        self.evaluating.pop()
        self.check_declared(decl, value)
        self.values[name] = value
        integer = decl.type_name == "Integer"
        self.model.parameters[name] = self.kept(decl.binding, value if integer else _real(value, name))
        declared = self.declared(decl)
        if declared:
            self.model.declarations[name] = declared
        return value

    def declared(self, decl: Declaration) -> dict[str, Any]:
        """What the declaration says beyond the value, for export: its SI type, its
        description and its attributes (bounds as numbers, units as text)."""
        info: dict[str, Any] = {"type": decl.type_name} if is_unit_type(decl.type_name) else {}
        for mod in decl.args:
            if mod.name not in DECLARATION_KEYS:  # stateSelect says nothing a model file keeps
                continue
            value = self.expression(mod.value)
            info[mod.name] = value if isinstance(value, str) else _real(python_value(value), decl.name)
        if decl.description:
            info["description"] = decl.description
        return info

    def kept(self, expr: Any, value: Any) -> Any:
        """What the model keeps of a binding: the value of a literal (or of an expression over
        constants only), else the expression text over top-level parameters, if that text
        evaluates to the same value without the file's imports."""
        if isinstance(expr, Literal) or not _refers_to(expr, set(self.params)):
            return value
        text = unparse(expr)
        try:  # the parameters it uses are evaluated already (they were needed for `value`)
            again = resolve_params("check", {"x": {"expr": text}}, self.values)["x"]
        except ModelError:
            return value
        return text if again == value else value

    def check_declared(self, decl: Declaration, value: Any) -> None:
        base = "Real" if is_unit_type(decl.type_name) else decl.type_name
        wanted = _TYPES[base]
        if isinstance(value, bool) and base != "Boolean" or not isinstance(value, wanted):
            raise ModelicaError(
                decl.binding.pos if decl.binding else decl.pos,
                f"type mismatch: parameter '{decl.name}' is {base} but its value is {value!r}",
            )
        self.check_attributes(decl.name, value, decl.args)

    def check_attributes(self, name: str, value: Any, attributes: list[Modification]) -> None:
        """Attributes of a parameter: min/max checked, unit/displayUnit/… accepted."""
        for mod in attributes:
            if mod.name not in _ATTRIBUTES or mod.name in ("start", "fixed") or mod.value is None:
                raise ModelicaError(mod.pos, f"unknown attribute '{mod.name}' of parameter '{name}'")
            bound = self.expression(mod.value) if mod.name in ("min", "max") else None
            if mod.name == "min" and value < bound or mod.name == "max" and value > bound:
                raise ModelicaError(
                    mod.pos, f"parameter '{name}' = {value!r} violates its {mod.name} = {bound!r}"
                )

    def expression(self, expr: Any) -> Any:
        if type(expr) is Literal:  # most values (J=1, fixed=true): no evaluator needed
            return expr.value
        return evaluate(expr, self.lookup, self.scope.resolve)

    def lookup(self, ref: Ref) -> Any:
        if ref.subscripts:
            raise ModelicaError(ref.pos, f"subscripted name '{ref.name}[…]' is not supported in a parameter")
        if ref.name in self.params:
            if ref.name in self.reported:
                raise _Reported
            return self.parameter(ref.name)
        head = ref.name.rpartition(".")[0]
        if head in self.components:  # `offset=-torqueLoad.tau_constant`
            return self.expression(self.cross(ref))
        full = ref.name
        if "." in ref.name or ref.name in self.scope.aliases or self.scope.wildcards:
            try:  # `import Modelica.Constants.pi;` then `pi`
                full = self.scope.resolve(ref.name, ref.pos, "name")
            except ModelicaError:
                if "." in ref.name:
                    raise
        if full in CONSTANTS:
            return CONSTANTS[full]
        if is_enumeration(full):
            return full.rsplit(".", 1)[-1]
        what = "a component or variable" if owner(ref.name, self.components) else "undefined"
        raise ModelicaError(
            ref.pos, f"'{ref.name}' is {what}; parameter values may use parameters and constants"
        )

    def cross(self, ref: Ref) -> Any:
        """What ``comp.param`` of another component stands for: its modifier's expression
        (names in it put in too) or the parameter's default."""
        comp, _, key = ref.name.rpartition(".")
        if ref.subscripts:
            raise ModelicaError(ref.pos, f"subscripted name '{ref.name}[…]' is not supported here")
        stype, decl = self.components[comp]
        if comp in self.reported:
            raise _Reported
        name = PARAMETER_RENAMES.get(stype, {})
        for mod in decl.args:
            if name.get(mod.name, mod.name) == key and mod.value is not None:
                if ref.name in self.inlining:
                    cycle = " -> ".join(n for n in [*self.inlining, ref.name])
                    raise ModelicaError(ref.pos, f"cyclic reference between components: {cycle}")
                self.inlining.append(ref.name)
                try:
                    return self.inline(mod.value)
                finally:
                    self.inlining.pop()
        known = _catalogue() or {}
        info = known.get(stype, {})
        if key not in info.get("parameters", []) and known:
            raise ModelicaError(
                ref.pos,
                f"'{ref.name}': {MSL_CLASSES.get(stype, stype)} '{comp}' has no "
                f"parameter '{key}' (parameters: {', '.join(info.get('parameters', []))})",
            )
        default = _default(stype, key)
        if default is None:
            raise ModelicaError(
                ref.pos,
                f"'{ref.name}' has no value: '{comp}' does not set '{key}' and it has no default",
            )
        return Literal(default, ref.pos)

    def inline(self, expr: Any) -> Any:
        """``expr`` with each reference to another component's parameter replaced by what it
        stands for, so the result keeps expressions over the model's parameters."""
        if type(expr) is Literal:
            return expr

        def other(ref: Ref) -> Any:
            head = ref.name.rpartition(".")[0]
            return self.cross(ref) if head in self.components else None

        return rewrite(expr, other)

    # --- components -----------------------------------------------------------------------
    def component(self, name: str, stype: str, decl: Declaration) -> None:
        """The component ``name``; a refused modifier is reported and left out, and the
        component is then not checked by the engine (its ports still are, by connections)."""
        errors, before = self.errors, len(self.errors)
        if decl.binding is not None:
            errors.append(ModelicaError(decl.binding.pos, f"component '{name}' cannot have a binding '= …'"))
        params = {}
        for mod in decl.args:
            try:
                key, value = self.modifier(name, stype, mod)
            except ModelicaError as exc:
                errors.append(exc)
                continue
            except _Reported:
                self.unchecked.add(name)
                continue
            if key is not None:
                params[key] = value
                self.positions[(name, key)] = mod.pos
        for mod in decl.annotation:
            if mod.name == WEAR_ANNOTATION:
                params["wear"] = {  # `kind`: the record's `model`, a keyword in Modelica
                    "model" if sub.name == "kind" else sub.name: python_value(self.expression(sub.value))
                    for sub in mod.args or []
                    if sub.value is not None
                }
        if PHI_NOMINAL in params:
            with_phi_nominal(params, params.pop(PHI_NOMINAL))
        if stype == "CombiTimeTable":
            try:
                stype, params = combi_time_table(name, decl, params)
            except ModelicaError as exc:
                errors.append(exc)
                stype, params = "TimeTable", {}
        while True:
            try:
                self.model.components[name] = Component(stype, params)
                break
            except ModelError as exc:  # a value out of its range: placed at its modifier
                param = re.search(r"parameter '(\w+)'", str(exc))
                pos = self.positions.get((name, param.group(1))) if param else None
                message = str(exc).replace(f"{stype}: ", f"component '{name}' ({stype}): ", 1)
                errors.append(ModelicaError(pos or decl.type_pos, message))
                if param is None or param.group(1) not in params:
                    self.model.components[name] = Component(stype)  # for its ports
                    break
                del params[param.group(1)]  # and the next value out of its range, if any
        if len(errors) > before:
            self.unchecked.add(name)

    def modifier(self, comp: str, stype: str, mod: Modification) -> tuple[str | None, Any]:
        key = PARAMETER_RENAMES.get(stype, {}).get(mod.name, mod.name)
        if key in IGNORED_MODIFIERS:
            return None, None
        allowed = _parameters_of(stype)
        if key == PHI_NOMINAL and allowed is not None and "phi_rel" in allowed and mod.value is not None:
            return key, phi_nominal(self.expression(self.inline(mod.value)), mod.pos, f"{comp}.{key}")
        if allowed is not None and key not in allowed:
            raise ModelicaError(
                mod.pos,
                f"unknown modifier '{mod.name}' of {MSL_CLASSES.get(stype, stype)} '{comp}' "
                f"(parameters: {', '.join(allowed)})",
            )
        if mod.value is not None:
            mod.value = self.inline(mod.value)
        if mod.args is None or (mod.value is not None and key not in START_VARIABLES):
            if mod.value is None:
                raise ModelicaError(mod.pos, f"modifier '{mod.name}' of '{comp}' has no value")
            value = _real(python_value(self.expression(mod.value)), key)
            if mod.args:
                self.check_attributes(f"{comp}.{mod.name}", value, mod.args)
            if type(mod.value) is Literal:
                return key, value
            kept = self.kept(mod.value, value)
            return key, {"expr": kept} if isinstance(kept, str) and kept != value else value
        if key not in START_VARIABLES:
            raise ModelicaError(
                mod.pos, f"'{mod.name}' of '{comp}' is a parameter: give it a value, not attributes"
            )
        if mod.value is not None:
            raise ModelicaError(mod.value.pos, f"a binding of variable '{comp}.{mod.name}' is not supported")
        return key, self.start_value(comp, mod)

    def start_value(self, comp: str, mod: Modification) -> Any:
        attrs: dict[str, Any] = {}
        for sub in mod.args or []:
            if sub.name not in _ATTRIBUTES or sub.value is None:
                raise ModelicaError(sub.pos, f"unknown attribute '{sub.name}' of '{comp}.{mod.name}'")
            if sub.name in ("start", "fixed"):
                sub.value = self.inline(sub.value)
                value = _real(python_value(self.expression(sub.value)), mod.name)
                kept = self.kept(sub.value, value)  # `start = w0` stays an expression over w0
                attrs[sub.name] = {"expr": kept} if isinstance(kept, str) and kept != value else value
            elif sub.name == "nominal":
                value = python_value(self.expression(self.inline(sub.value)))
                attrs["nominal"] = positive_nominal(value, sub.pos, f"{comp}.{mod.name}")
        if (
            "nominal" not in attrs
            and attrs.get("fixed") is True
            and (isinstance(attrs.get("start"), float) or is_expr(attrs.get("start")))
        ):
            return attrs["start"]  # the model file's short form of a fixed start value
        return attrs

    # --- variables, experiment ----------------------------------------------------------
    def variable(self, decl: Declaration) -> None:
        """A derived variable: its binding over result variables and top-level parameters
        (kept by name, so a sweep of a parameter changes it too)."""
        from stiction.modelica.derived import check_expression

        assert decl.binding is not None
        if self.reported and _refers_to(decl.binding, self.reported):
            raise _Reported
        check_expression(decl.binding, self.model, self.scope.resolve, set(self.params))
        self.model.variables[decl.name] = unparse(decl.binding)

    def experiment(self) -> None:
        for mod in self.cls.annotation:
            if mod.name != "experiment":
                continue
            for sub in mod.args or []:
                try:
                    self.setting(sub)
                except ModelicaError as exc:
                    self.errors.append(exc)
                except _Reported:
                    pass

    def setting(self, sub: Modification) -> None:
        """One setting of the experiment annotation."""
        if sub.name == "__stiction_Solver" and sub.value is not None:
            self.model.experiment["Solver"] = python_value(self.expression(sub.value))
        if sub.name in _EXPERIMENT and sub.value is not None:
            value = python_value(self.expression(sub.value))
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ModelicaError(sub.pos, f"experiment {sub.name} must be a number, got {value!r}")
            self.model.experiment[sub.name] = float(value)

    def engine_check(self) -> None:
        """Let the engine check each component's values (ranges, table shapes, kinds) and
        place a complaint at its modifier. Components are checked unconnected, in batches, once
        per distinct type and parameters: checking the assembled model costs seconds for
        thousands of components, and the connections were checked above."""
        distinct: dict[tuple[str, str], tuple[str, str, dict[str, Any]]] = {}
        for name, comp in self.model.components.items():
            if name in self.unchecked:  # a value of it is refused: the engine would say it again
                continue
            try:
                params = resolve_params(name, comp.params, self.values)
            except ModelError:
                if self.errors:
                    continue  # an expression over a refused parameter
                raise
            key = {k: v for k, v in params.items() if not always_valid(comp.type, k, v)}
            distinct.setdefault((comp.type, repr(key)), (name, comp.type, params))
        for name, message in value_problems(list(distinct.values()), str(self.model.base_dir)):
            param = re.search(r"parameter '(\w+)'", message)
            pos = self.positions.get((name, param.group(1))) if param else None
            self.errors.append(ModelicaError(pos or self.components[name][1].type_pos, message))


def _refers_to(expr: Any, names: set[str]) -> bool:
    """Whether an expression mentions one of ``names``."""
    if isinstance(expr, Ref):
        return expr.name in names or expr.name.partition(".")[0] in names
    children = [getattr(expr, f, None) for f in ("left", "right", "operand", "cond", "then", "other")]
    children += list(getattr(expr, "args", None) or []) + list(getattr(expr, "items", None) or [])
    children += [item for row in getattr(expr, "rows", None) or [] for item in row]
    return any(_refers_to(c, names) for c in children if c is not None and not isinstance(c, (str, dict)))


def _real(value: Any, key: str) -> Any:
    """Modelica's ``J=1`` sets a Real parameter to 1.0; only Integer parameters keep ints."""
    if isinstance(value, list):
        return [_real(v, key) for v in value]
    if type(value) is int and key not in INTEGER_PARAMETERS:
        return float(value)
    return value


def _parameters_of(stype: str) -> list[str] | None:
    if stype == "CombiTimeTable":
        return list(COMBI_PARAMETERS)
    known = _catalogue()
    return None if known is None else known.get(stype, {}).get("parameters", [])


def _default(stype: str, key: str) -> bool | int | float | str | None:
    """A scalar default of parameter ``key`` of ``stype`` from the catalogue, or None."""
    if _catalogue() is None:
        return None
    from stiction.model.catalogue import catalogue

    info = catalogue().get(stype)
    for p in info.parameters if info is not None else []:
        if p.name == key and not p.required and isinstance(p.default, (bool, int, float, str)):
            return p.default
    return None


@functools.cache
def _port_kinds() -> dict[str, dict[str, tuple[str | None, str | None]]]:
    """Per component type, each port's kind (``flange``, ``signal input``, ``signal
    output``, ``heat port``) and the Boolean parameter enabling it, if any; empty without
    the compiled engine."""
    if _catalogue() is None:
        return {}
    from stiction.model.catalogue import catalogue

    return {name: {p.name: (p.kind, p.enabled_by) for p in info.ports} for name, info in catalogue().items()}


def _catalogue() -> dict[str, dict[str, list[str]]] | None:
    return component_types()
