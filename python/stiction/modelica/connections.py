"""``connect`` equations as Modelica reads them: connection sets.

A flange or heat port joined to others makes them one node. Signals too form sets: a chain
``connect(feedback.u2, clutch.f_normalized); connect(ramp.y, clutch.f_normalized);`` is legal
when exactly one output drives the set, and each input of it is then fed by that output. A set
with two outputs, or inputs and none, is refused at its first ``connect``, the ports named.
The connectors of a user's class (``flatten.CONNECTOR_KINDS``) are nodes of sets too: what is
joined through them is connected directly. A connection between two ports of components that
Modelica's own rules accept is kept as written, in its place, so plain models stay as they were.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from stiction.errors import ModelError
from stiction.expressions.ast import Literal, Ref
from stiction.expressions.lexer import ModelicaError, Pos
from stiction.model.components import table_1ds_ports, time_table_ports
from stiction.model.names import owner
from stiction.model.parameters import resolve_params

if TYPE_CHECKING:
    from stiction.model.components import Component

__all__ = ["ConnectionSets", "Reported"]

_JOINED = ("flange", "translational flange", "heat port")  # kinds of port that connect to their own kind
_NO_PORT = (None, None)
# MSL's conditional connectors: the port exists when its flag is true (false by default). The
# adaptors' w and a depend on two flags at once: the engine checks those.
_CONDITIONAL = frozenset(("useSupport", "useHeatPort"))


def _family(kind: str | None) -> str | None:
    return "signal" if kind in ("signal input", "signal output") else kind


class _Sets:
    """Union-find over port names."""

    def __init__(self) -> None:
        self.parent: dict[str, str] = {}

    def find(self, x: str) -> str:
        parent = self.parent.setdefault(x, x)
        while parent != x:
            self.parent[x] = self.parent.setdefault(parent, parent)
            x, parent = parent, self.parent[parent]
        return x

    def union(self, a: str, b: str) -> None:
        self.parent[self.find(a)] = self.find(b)


class ConnectionSets:
    """The converter's connection handling (a mixin of ``convert._Converter``: it uses the
    model, its components, errors and the connectors of the flattened classes)."""

    model: Any
    errors: list[ModelicaError]
    reported: set[str]
    unchecked: set[str]
    values: dict[str, Any]
    components: dict[str, tuple[str, Any]]
    connectors: dict[str, tuple[str, Pos]]

    def init_connections(self) -> None:
        self.connected: set[frozenset[str]] = set()
        self.fed: dict[str, str] = {}  # signal input -> the output connected to it
        self.kinds: dict[str, str | None] = {}
        self.sets = _Sets()  # every edge
        self.direct = _Sets()  # the edges kept as written
        self.first: dict[str, tuple[int, Pos]] = {}  # a set's root -> its earliest connect
        self.deferred = False  # an edge only a connection set resolves

    def connect(self, conn: Any) -> None:
        """A connection, checked as the engine checks it (each end a port of its component,
        the kinds matching), refused at its ``connect``."""
        ends = []
        for ref in (conn.a, conn.b):
            try:
                ends.append(self.port(ref))
            except ModelicaError as exc:
                self.errors.append(exc)
            except Reported:
                pass
        if len(ends) < 2:
            return
        (a, ka), (b, kb) = ends
        key = frozenset((a, b))
        if a == b:
            problem: str | None = "a port cannot be connected to itself"
        elif key in self.connected:
            problem = "already connected"
        elif ka == kb and ka in _JOINED or ka is None or kb is None:  # the common case first
            problem = None
        else:
            problem = self.kinds_problem(a, ka, b, kb)
        if problem is not None:
            self.errors.append(ModelicaError(conn.pos, f"connect({a}, {b}): {problem}"))
            return
        self.connected.add(key)
        self.kinds[a], self.kinds[b] = ka, kb
        here = (len(self.connected), conn.pos)  # connects come in order: the count orders them
        earliest = min(
            self.first.get(self.sets.find(a), here), self.first.get(self.sets.find(b), here), key=_index
        )
        self.sets.union(a, b)
        self.first[self.sets.find(a)] = earliest
        virtual = a in self.connectors or b in self.connectors
        if virtual or ka == kb == "signal input":
            self.deferred = True  # resolved with its set, in finish_connections
            return
        self.direct.union(a, b)
        self.model.connections.append((a, b))  # ports checked above (Model.connect is O(n) per call)

    def kinds_problem(self, a: str, ka: str, b: str, kb: str) -> str | None:
        """Why Modelica (or the engine) refuses to connect these two ports, or None."""
        if {ka, kb} == {"flange", "translational flange"}:  # the engine's words
            return (
                f"cannot connect the {'rotational ' if ka == 'flange' else ''}{ka} '{a}' to the "
                f"{'rotational ' if kb == 'flange' else ''}{kb} '{b}': an angle and a position are "
                "joined only through a component that converts rotation into translation "
                "(IdealRollingWheel, IdealGearR2T)"
            )
        if _family(ka) != _family(kb):
            return f"cannot connect a {ka} ('{a}') to a {kb} ('{b}')"
        if ka == "signal output" and kb == "signal input":
            out, inp = a, b
        elif ka == "signal input" and kb == "signal output":
            out, inp = b, a
        elif ka == kb == "signal output" and a not in self.connectors and b not in self.connectors:
            return "connects two signal outputs"
        else:
            return None  # a chain of inputs, or a class's connector: its set decides
        if a in self.connectors or b in self.connectors:
            return None
        if self.fed.setdefault(inp, out) != out:
            return f"signal input '{inp}' is already connected to another output"
        return None

    def finish_connections(self) -> None:
        """Resolve the sets that chains of inputs or a class's connectors make."""
        if not self.deferred:
            return
        members: dict[str, list[str]] = {}
        for end in self.kinds:
            members.setdefault(self.sets.find(end), []).append(end)
        for root, ends in members.items():
            real = [e for e in ends if e not in self.connectors]
            kinds = {_family(self.kinds[e]) for e in ends}
            if "signal" in kinds:
                self.signal_set(root, real)
            elif len({self.direct.find(e) for e in real}) > 1:
                groups: dict[str, str] = {}
                for e in real:
                    groups.setdefault(self.direct.find(e), e)
                first, *others = groups.values()
                for other in others:
                    self.model.connections.append((first, other))

    def signal_set(self, root: str, real: list[str]) -> None:
        outputs = [e for e in real if self.kinds[e] == "signal output"]
        inputs = [e for e in real if self.kinds[e] == "signal input"]
        pos = self.first[root][1]
        names = ", ".join(real)
        if len(outputs) > 1:
            self.errors.append(
                ModelicaError(
                    pos,
                    f"connection set of {names}: {len(outputs)} signal outputs drive it "
                    f"({', '.join(outputs)}); exactly one may",
                )
            )
            return
        if not outputs:
            if inputs:
                self.errors.append(
                    ModelicaError(
                        pos,
                        f"connection set of {names}: signal inputs with no output driving them; "
                        "connect one output (y) to the set",
                    )
                )
            return
        out = outputs[0]
        for inp in inputs:
            if self.fed.setdefault(inp, out) == out and (out, inp) not in self.model.connections:
                self.model.connections.append((out, inp))

    def port(self, ref: Ref) -> tuple[str, str | None]:
        """The port a connect names and its kind (None without the engine's catalogue)."""
        from stiction.modelica.convert import _port_kinds

        if ref.name in self.connectors:
            return ref.name, self.connectors[ref.name][0]
        comp = owner(ref.name, self.components) or ref.name.partition(".")[0]
        port = ref.name[len(comp) + 1 :]
        if comp in self.reported:
            raise Reported
        component = self.model.components.get(comp)
        if component is None:
            raise ModelicaError(ref.pos, f"connect to '{ref.name}': no component '{comp}' in the model")
        ports = _port_kinds().get(component.type)
        if ports is not None and component.type == "CombiTable1Ds":  # outputs follow columns
            out = ports["y[1]"]
            ports = {p: ports.get(p, out) for p in table_1ds_ports(component.params)}
        element = _element(ref, port)
        if ports is not None and element in ports:  # an array connector's element: Move's u[1]
            return f"{comp}.{element}", ports[element][0]
        kind, flag = ports.get(port, _NO_PORT) if ports is not None else (None, None)
        if ports is not None and kind is None or not port or "." in port:
            raise ModelicaError(
                ref.pos,
                f"connect to '{ref.name}': {component.type} '{comp}' has no port "
                f"'{port}' (ports: {', '.join(ports or [])})",
            )
        if flag in _CONDITIONAL and not self.enabled(comp, component, flag):
            raise ModelicaError(
                ref.pos,
                f"connect to '{ref.name}': {component.type} '{comp}' has no port '{port}' "
                f"(set {flag} = true to enable it)",
            )
        if self.components[comp][0] == "CombiTimeTable" and port == "y":
            return _table_output(ref, comp, component), kind
        if ref.subscripts:
            raise ModelicaError(ref.pos, f"connect to '{ref.name}[…]': array connectors are not supported")
        return ref.name, kind

    def enabled(self, comp: str, component: Component, flag: str) -> bool:
        """Whether the Boolean ``flag`` of a component (a value or an expression over the
        top-level parameters) is true; a value that cannot be told counts as true."""
        value = component.params.get(flag)
        if value is None:
            return comp in self.unchecked  # false by default, unless its modifier was refused
        if type(value) is bool:
            return value
        try:
            value = resolve_params(comp, {flag: value}, self.values)[flag]
        except ModelError:
            return True
        return value is not False


def _index(first: tuple[int, Pos]) -> int:
    return first[0]


class Reported(Exception):
    """A name whose own error is reported already: what uses it is not checked again."""


def _element(ref: Ref, port: str) -> str | None:
    """``u[1]`` for a connect to ``move.u[1]`` (one literal index), else None."""
    if len(ref.subscripts) == 1 and isinstance(ref.subscripts[0], Literal):
        return f"{port}[{ref.subscripts[0].value}]"
    return None


def _table_output(ref: Ref, comp: str, component: Component) -> str:
    """The TimeTable port a connect to a CombiTimeTable's ``y[i]`` names: ``y`` for a table of
    one output, ``y[i]`` for one of several."""
    count = len(time_table_ports(component.params))
    if not ref.subscripts and count == 1:
        return f"{comp}.y"
    index = (
        ref.subscripts[0].value
        if len(ref.subscripts) == 1 and isinstance(ref.subscripts[0], Literal)
        else None
    )
    if type(index) is not int or not 1 <= index <= count:
        raise ModelicaError(
            ref.pos,
            f"connect to '{ref.name}': CombiTimeTable '{comp}' has outputs y[1] to y[{count}]; "
            "connect one of them by a literal index",
        )
    return f"{comp}.y" if count == 1 else f"{comp}.y[{index}]"
