"""Users' own classes, flattened: a ``model Driveline … end Driveline;`` of the same file used
as a component ``Driveline front(clutchPeak=1.2)`` becomes its components, named
``front.clutch`` as Modelica tools name them (the engine's component names are dotted paths),
with the class's parameters put in as the expressions they are bound to (a modifier of the
instance, else the class's default), its connectors as nodes of connection sets
(``CONNECTOR_KINDS``), its ``connect`` equations renamed, and ``extends`` of another such
class merged in. Its variables are the flattened ones: ``front.clutch.w_rel``.

Only what such a class may hold is read: parameters, MSL components, connectors, variables
with a binding, instances of other such classes and ``connect``. Other equations are refused
by the parser; anything else here is refused at its place, the construct named.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from stiction.expressions.ast import Array, BinOp, Call, IfExpr, Literal, Matrix, Ref, Unary
from stiction.expressions.lexer import ModelicaError, Pos
from stiction.modelica.ast import ClassDef, Connect, Declaration, Modification
from stiction.modelica.names import CONNECTOR_KINDS, Scope, is_icon

__all__ = ["Flat", "flatten", "rewrite"]

_PARAMETER = ("parameter", "constant")
_ATTRIBUTES_KEPT = frozenset(("unit", "displayUnit", "quantity"))


def rewrite(expr: Any, fn: Callable[[Ref], Any]) -> Any:
    """A copy of ``expr`` with each name replaced by ``fn(ref)`` (None keeps it)."""
    if isinstance(expr, Ref):
        out = fn(expr)
        return expr if out is None else out
    if isinstance(expr, Literal) or expr is None:
        return expr
    if isinstance(expr, BinOp):
        return dataclasses.replace(expr, left=rewrite(expr.left, fn), right=rewrite(expr.right, fn))
    if isinstance(expr, Unary):
        return dataclasses.replace(expr, operand=rewrite(expr.operand, fn))
    if isinstance(expr, IfExpr):
        parts = (rewrite(e, fn) for e in (expr.cond, expr.then, expr.other))
        return dataclasses.replace(expr, **dict(zip(("cond", "then", "other"), parts, strict=True)))
    if isinstance(expr, Array):
        return dataclasses.replace(expr, items=[rewrite(e, fn) for e in expr.items])
    if isinstance(expr, Matrix):
        return dataclasses.replace(expr, rows=[[rewrite(e, fn) for e in row] for row in expr.rows])
    if isinstance(expr, Call):
        kwargs = {k: rewrite(v, fn) for k, v in expr.kwargs.items()}
        return dataclasses.replace(expr, args=[rewrite(a, fn) for a in expr.args], kwargs=kwargs)
    return expr


@dataclass
class Flat:
    """The flattened model: one class of MSL components, its interface connectors (flat name
    -> kind and place) and the errors found."""

    cls: ClassDef
    connectors: dict[str, tuple[str, Pos]] = field(default_factory=dict)
    errors: list[ModelicaError] = field(default_factory=list)


@dataclass
class _Body:
    """A class with its ``extends`` merged: each member with the scope its names resolve in."""

    decls: list[tuple[Declaration, Scope]]
    connects: list[tuple[Connect, Scope]]


@dataclass
class _Instance:
    """A user class instantiated under ``flat`` (a flat name; "" for the model itself)."""

    cls_name: str
    flat: str
    params: dict[str, tuple[Declaration, Scope]]
    given: dict[str, Any]  # parameter -> expression already in the flat namespace
    values: dict[str, Any] = field(default_factory=dict)
    evaluating: list[str] = field(default_factory=list)
    members: dict[str, str] = field(default_factory=dict)  # name -> "component", "instance", …


class _Flattener:
    def __init__(self, classes: dict[str, tuple[ClassDef, Scope]]) -> None:
        self.classes = classes  # qualified name of each class of the file -> (class, its scope)
        self.out: list[Declaration] = []
        self.connects: list[Connect] = []
        self.connectors: dict[str, tuple[str, Pos]] = {}
        self.instances: dict[str, _Instance] = {}
        self.errors: list[ModelicaError] = []
        self.extends: list[tuple[str, Pos]] = []

    # --- classes ------------------------------------------------------------------------
    def user_class(self, decl: Declaration, scope: Scope) -> str | None:
        try:
            full = scope.resolve(decl.type_name, decl.type_pos)
        except ModelicaError:
            return None  # the converter reports it
        found = self.classes.get(full)
        return full if found is not None and found[0].kind != "package" else None

    def body(self, full: str, pos: Pos, stack: tuple[str, ...]) -> _Body:
        """The members of class ``full``, its user-class bases' first."""
        if full in stack:
            raise ModelicaError(pos, f"class '{full}' contains or extends itself")
        cls, scope = self.classes[full]
        decls: list[tuple[Declaration, Scope]] = []
        connects: list[tuple[Connect, Scope]] = []
        for (name, epos), args in zip(cls.extends, cls.extends_args or [[]] * len(cls.extends), strict=True):
            try:
                base = scope.resolve(name, epos)
            except ModelicaError as exc:
                self.errors.append(exc)
                continue
            if is_icon(base):
                continue
            if base not in self.classes or self.classes[base][0].kind == "package":
                if not stack:
                    self.extends.append((name, epos))  # the converter refuses it, located
                else:
                    self.errors.append(
                        ModelicaError(
                            epos,
                            f"unsupported 'extends {name}' in class '{cls.name}'; "
                            "only Modelica.Icons.* and classes of this file",
                        )
                    )
                continue
            inner = self.body(base, epos, (*stack, full))
            given = {m.name: m for m in args}
            for decl, dscope in inner.decls:
                mod = given.pop(decl.name, None)
                if mod is not None:
                    if decl.prefix not in _PARAMETER or mod.value is None:
                        self.errors.append(
                            ModelicaError(
                                mod.pos,
                                f"'extends {name}({mod.name}=…)': only "
                                "parameters of the base class can be modified here",
                            )
                        )
                    else:
                        decl = dataclasses.replace(decl, binding=mod.value)
                        dscope = scope
                decls.append((decl, dscope))
            for mod in given.values():
                self.errors.append(ModelicaError(mod.pos, f"'{mod.name}' is no parameter of class '{name}'"))
            connects.extend(inner.connects)
        decls.extend((d, scope) for d in cls.declarations)
        connects.extend((c, scope) for c in cls.connects)
        return _Body(decls, connects)

    # --- instances ----------------------------------------------------------------------
    def instance(
        self,
        full: str,
        flat: str,
        mods: list[Modification],
        ctx: _Instance | None,
        pos: Pos,
        stack: tuple[str, ...],
    ) -> None:
        """Class ``full`` under the flat name ``flat``, modified by ``mods`` (in flat names
        already), inside ``ctx`` (None for the model itself)."""
        body = self.body(full, pos, stack)
        inst = _Instance(full, flat, {}, {})
        self.instances[flat] = inst
        for decl, scope in body.decls:
            if decl.refused:
                continue
            if decl.prefix in _PARAMETER and self.user_class(decl, scope) is None and ctx is not None:
                inst.params[decl.name] = (decl, scope)
                inst.members[decl.name] = "parameter"
            elif self.user_class(decl, scope) is not None:
                inst.members[decl.name] = "instance"
            else:
                inst.members[decl.name] = "component"
        extra: dict[str, list[Modification]] = {}
        for mod in mods:
            what = inst.members.get(mod.name)
            if what == "parameter" and mod.value is not None:
                bad = [a for a in mod.args or [] if a.name not in _ATTRIBUTES_KEPT]
                if bad:
                    self.errors.append(
                        ModelicaError(
                            bad[0].pos,
                            f"unsupported attribute '{bad[0].name}' of parameter '{flat}.{mod.name}'",
                        )
                    )
                inst.given[mod.name] = mod.value  # flat already
            elif what in ("component", "instance") and mod.args is not None and mod.value is None:
                extra[mod.name] = mod.args
            else:
                known = ", ".join(n for n, w in inst.members.items() if w == "parameter") or "none"
                self.errors.append(
                    ModelicaError(
                        mod.pos,
                        f"unknown modifier '{mod.name}' of class '{full.rsplit('.', 1)[-1]}' "
                        f"'{flat}' (parameters: {known}; a component is modified as 'name(k=…)')",
                    )
                )
        for decl, scope in body.decls:
            if decl.refused or decl.name in inst.params:
                continue
            try:
                self.member(inst, decl, scope, extra.pop(decl.name, []), (*stack, full))
            except ModelicaError as exc:
                self.errors.append(exc)
        for conn, scope in body.connects:
            try:
                a, b = (self.end(e, inst, scope) for e in (conn.a, conn.b))
            except ModelicaError as exc:
                self.errors.append(exc)
                continue
            self.connects.append(Connect(a, b, conn.pos))

    def member(
        self,
        inst: _Instance,
        decl: Declaration,
        scope: Scope,
        extra: list[Modification],
        stack: tuple[str, ...],
    ) -> None:
        flat = self.join(inst.flat, decl.name)
        user = self.user_class(decl, scope)
        if user is not None:
            if decl.binding is not None:
                raise ModelicaError(decl.binding.pos, f"component '{flat}' cannot have a binding '= …'")
            mods = [self.modification(m, inst, scope) for m in decl.args]
            self.instance(user, flat, mods + extra, inst, decl.pos, stack)
            return
        try:
            full = scope.resolve(decl.type_name, decl.type_pos)
        except ModelicaError:
            full = decl.type_name
        if full in CONNECTOR_KINDS:
            self.connectors[flat] = (CONNECTOR_KINDS[full], decl.pos)
            return
        args = [self.modification(m, inst, scope) for m in decl.args]
        names = {m.name for m in extra}
        args = [m for m in args if m.name not in names] + extra
        binding = self.expr(decl.binding, inst, scope) if decl.binding is not None else None
        self.out.append(dataclasses.replace(decl, type_name=full, name=flat, args=args, binding=binding))

    def modification(
        self, mod: Modification, inst: _Instance | None, scope: Scope | None = None
    ) -> Modification:
        args = None if mod.args is None else [self.modification(a, inst, scope) for a in mod.args]
        value = None if mod.value is None else self.expr(mod.value, inst, scope)
        return dataclasses.replace(mod, args=args, value=value)

    # --- names --------------------------------------------------------------------------
    @staticmethod
    def join(prefix: str, name: str) -> str:
        return f"{prefix}.{name}" if prefix else name

    def expr(self, expr: Any, inst: _Instance | None, scope: Scope | None = None) -> Any:
        """``expr`` written in instance ``inst`` (None: the model itself), in flat names."""
        if inst is None:
            return expr
        return rewrite(expr, lambda ref: self.name(ref, inst, scope))

    def name(self, ref: Ref, inst: _Instance, scope: Scope | None) -> Any:
        parts = ref.name.split(".")
        if parts[0] in inst.params:
            if len(parts) > 1 or ref.subscripts:
                raise ModelicaError(ref.pos, f"'{ref.name}': a parameter has no members or subscripts")
            return self.parameter(inst, parts[0], ref.pos)
        if parts[0] in inst.members:
            return self.path(inst.flat, parts, ref)
        if scope is not None and inst.flat:  # a constant, written as the class's imports say
            try:
                return Ref(scope.resolve(ref.name, ref.pos, "name"), ref.pos, ref.subscripts)
            except ModelicaError:
                return None
        return None

    def path(self, flat: str, parts: list[str], ref: Ref) -> Any:
        """``front.sub.k`` -> the expression of parameter k of instance front.sub;
        ``front.clutch.w_rel`` -> the variable ``front.clutch.w_rel`` of component front.clutch."""
        for i, part in enumerate(parts):
            inner = self.join(flat, part)
            sub = self.instances.get(inner)
            if sub is None:
                return Ref(".".join([inner, *parts[i + 1 :]]), ref.pos, ref.subscripts)
            flat = inner
            rest = parts[i + 1 :]
            if len(rest) == 1 and rest[0] in sub.params:
                return self.parameter(sub, rest[0], ref.pos)
        return Ref(flat, ref.pos, ref.subscripts)

    def parameter(self, inst: _Instance, name: str, pos: Pos) -> Any:
        if name in inst.values:
            return copy.deepcopy(inst.values[name])
        if name in inst.given:
            value = inst.given[name]
        else:
            decl, scope = inst.params[name]
            if name in inst.evaluating:
                cycle = " -> ".join([*inst.evaluating[inst.evaluating.index(name) :], name])
                raise ModelicaError(decl.pos, f"cyclic parameter definition: {cycle}")
            if decl.binding is None:
                raise ModelicaError(
                    pos,
                    f"parameter '{self.join(inst.flat, name)}' has no value: "
                    f"give it one in the class or modify it ('{name}=…')",
                )
            inst.evaluating.append(name)
            try:
                value = self.expr(decl.binding, inst, scope)
            finally:
                inst.evaluating.pop()
        inst.values[name] = value
        return copy.deepcopy(value)

    def end(self, ref: Ref, inst: _Instance, scope: Scope) -> Ref:
        """A connect end in flat names: a component's port ``front.clutch.flange_a`` or a
        connector node ``front.flange_a``."""
        parts = ref.name.split(".")
        flat = inst.flat
        for i, part in enumerate(parts):
            name = self.join(flat, part)
            if name in self.connectors and i == len(parts) - 1:
                return Ref(name, ref.pos, ref.subscripts)
            if name not in self.instances:
                return Ref(".".join([name, *parts[i + 1 :]]), ref.pos, ref.subscripts)
            flat = name
        raise ModelicaError(ref.pos, f"connect to '{ref.name}': '{flat}' is a component, not a port")


def uses_classes(cls: ClassDef, scope: Scope, classes: dict[str, tuple[ClassDef, Scope]]) -> bool:
    """Whether the model needs flattening: an instance, a base class or a connector of the file's."""
    f = _Flattener(classes)
    for name, pos in cls.extends:
        try:
            if scope.resolve(name, pos) in classes:
                return True
        except ModelicaError:
            pass
    for decl in cls.declarations:
        if f.user_class(decl, scope) is not None:
            return True
        try:
            if scope.resolve(decl.type_name, decl.type_pos) in CONNECTOR_KINDS:
                return True
        except ModelicaError:
            pass
    return False


def flatten(full: str, classes: dict[str, tuple[ClassDef, Scope]]) -> Flat:
    """Model ``full`` with its users' classes flattened (see the module's docstring)."""
    cls, _ = classes[full]
    f = _Flattener(classes)
    f.instance(full, "", [], None, cls.pos, ())
    out = ClassDef(
        cls.kind,
        cls.name,
        cls.pos,
        cls.description,
        cls.imports,
        f.extends,
        [[] for _ in f.extends],
        f.out,
        f.connects,
        [],
        cls.annotation,
    )
    return Flat(out, f.connectors, f.errors)
