"""``Model``: components and connections, checked as they are added, and run.

The model is plain data (it serialises to the TOML model file and back). Checks that
need the engine's catalogue of types, parameters and ports run when the compiled module
is present; everything else (names, connection syntax) is checked here regardless.
Simulation hands the TOML text to the engine, so a model built in Python and one loaded
from a file run identically.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import gc
import os
import re
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stiction.errors import ModelError
from stiction.model import modelfile
from stiction.model.components import (
    FACTORIES,
    Component,
    component_types,
    table_1ds_ports,
    time_table_ports,
)
from stiction.model.loaded import LAZY_FIELDS, LoadedFile, load_file, named_text
from stiction.model.names import COMPONENT_NAME, IDENTIFIER, PathIndex, split_last
from stiction.model.parameters import is_expr
from stiction.model.runinfo import RunInfo

if TYPE_CHECKING:
    from stiction.results.result import Result
    from stiction.run.compiled import CompiledModel
    from stiction.run.simulation import Simulation

__all__ = ["Model"]

# a name in an expression: dotted ones (J1.w) are result variables, plain ones may be parameters
_NAME = re.compile(r"(?<![\w.])[A-Za-z_]\w*(?![\w.])")


def _did_you_mean(word: str, choices: list[str]) -> str:
    close = difflib.get_close_matches(word, choices, n=3)
    return f" (did you mean {', '.join(repr(c) for c in close)}?)" if close else ""


@functools.cache
def _port_kind(type_name: str, port: str) -> str | None:
    """A port's kind from the engine's catalogue (None for an unknown type or port)."""
    from stiction.model.catalogue import catalogue

    try:
        info = catalogue().get(type_name)
    except ModuleNotFoundError:  # a source tree without the compiled engine
        return None
    return next((p.kind for p in info.ports if p.name == port), None) if info else None


@functools.cache
def _names_of(type_name: str, what: str) -> frozenset[str]:
    """A known type's parameter or port names (``what``) as a set (the catalogue lists them)."""
    known = component_types() or {}
    return frozenset(known.get(type_name, {}).get(what, []))


@functools.lru_cache(maxsize=4096)
def _expression_key(text: str) -> str:
    """An expression as its syntax tree writes it back (``2 * T`` and ``2*T`` alike); text
    that is no expression stays as it is."""
    from stiction.expressions.evaluate import unparse
    from stiction.expressions.lexer import ModelicaError
    from stiction.expressions.parser import parse_expression

    try:
        return unparse(parse_expression(text))
    except ModelicaError:
        return text


def _meaning(value: Any, expressions: bool = False) -> Any:
    """``value`` as models compare by meaning: numbers by value (0 == 0.0, as Python has it),
    parameter expressions (``st.expr``; with ``expressions`` every text) by their syntax."""
    if isinstance(value, str):
        return _expression_key(value) if expressions else value
    if is_expr(value):
        return {"expr": _expression_key(value["expr"])}
    if isinstance(value, Component):
        return (value.type, _meaning(value.params))
    if isinstance(value, Mapping):
        return {k: _meaning(v, expressions) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_meaning(v, expressions) for v in value]
    return value


def _same_params(raw: dict[str, Any], held: dict[str, Any]) -> bool:
    """A component's parameters as the file has them (``raw``) are those it holds, type for
    type, each one the engine text holds as written (``_same``; the common case, numbers
    and Booleans, without a call per value)."""
    if raw != held:
        return False
    for key, value in raw.items():
        kind = type(value)
        if kind is not type(held[key]):
            return False
        if kind not in (bool, int, float, str) and not (_plain_value(value) and _same(value, held[key])):
            return False
    return True


def _same(a: Any, b: Any) -> bool:
    """Equal and of the same types throughout (``1`` and ``1.0`` are written differently,
    and the engine may read them differently); numbers, text and lists of them only."""
    kind = type(a)
    if kind is not type(b):
        return False
    if kind in (bool, int, float, str):
        return a == b
    if kind is list:
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return False


def _plain_value(value: Any) -> bool:
    """A parameter the engine text holds as written: no expression (``{ expr = … }``, a start
    value's table) and no table cell that is text (an expression there too)."""
    kind = type(value)
    if kind in (bool, int, float, str):
        return True
    return kind is list and all(type(v) in (int, float) or _plain_row(v) for v in value)


def _plain_row(row: Any) -> bool:
    return type(row) is list and all(type(v) in (int, float) for v in row)


def numbers_read(variables: Mapping[str, str], values: Mapping[str, Any]) -> dict[str, float]:
    """The top-level parameters the derived variables read by name, with their ``values``:
    the engine text's ``[parameters]``, which a run or a sweep that varies one sets."""
    if not variables:
        return {}
    names = {n for text in variables.values() for n in _NAME.findall(text)}
    return {k: float(v) for k, v in values.items() if k in names and isinstance(v, (int, float, bool))}


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """The cyclic garbage collector paused (and resumed if it ran before): building a model
    of thousands of components makes tens of thousands of containers, none of them garbage,
    and the collections they set off were a tenth of loading a ladder of 1000 inertias."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


class Model:
    """A drivetrain: named components, connections of their ports, an experiment."""

    # A model file loaded as it stands and compiled, its objects not made yet (see
    # stiction/model/loaded.py); None for every other model, and once they are made.
    _lazy: LoadedFile | None = None

    def __init__(self, name: str, base_dir: str | os.PathLike[str] = ".") -> None:
        if not isinstance(name, str) or not name:
            raise ModelError(f"model name must be a non-empty string, got {name!r}")
        self.name = name
        self.components: dict[str, Component] = {}
        self.connections: list[tuple[str, str]] = []
        self._pairs: set[frozenset[str]] = set()
        self._paths = PathIndex()  # refuses `front` beside `front.clutch`
        self.experiment: dict[str, Any] = {}
        # Signal inputs left unconnected on purpose, set while the model runs: port -> start.
        self.inputs: dict[str, float] = {}
        # Relative file names in parameters (a TimeTable CSV …) are relative to this.
        self.base_dir = Path(base_dir)
        # The compiled form of the model text it was made from (see `compile`).
        self._compiled: tuple[tuple[str, str], CompiledModel] | None = None
        # A loaded file's text, base folder and the engine's compile of it (see `_adopt_text`).
        self._parsed: tuple[str, str, Any] | None = None
        # The engine text and the parameter values of the model as it was (see `_text_key`).
        self._derived: tuple[str, str, dict[str, float] | None] | None = None
        # Derived variables: result columns computed from the run, name -> Modelica expression
        # over result variables ("gear.flange_a.tau*der(gear.flange_a.phi)").
        self.variables: dict[str, str] = {}
        # Top-level parameters: name -> number, Boolean or expression text over the others;
        # components refer to them with {"expr": "T2"} (see stiction/parameters.py).
        self.parameters: dict[str, Any] = {}
        # What a top-level parameter's Modelica declaration says beyond its value (type,
        # description, unit, min…): kept through import and export, never read by the engine.
        self.declarations: dict[str, dict[str, Any]] = {}

    # --- building ---------------------------------------------------------------------
    def add(self, name: str, component: Component) -> Model:
        """Add a component under a unique name; returns the model. A name is an identifier or
        a path of them, ``"front.clutch"`` (as Modelica tools name a part of a user's class)."""
        if not isinstance(name, str) or not COMPONENT_NAME.fullmatch(name):
            raise ModelError(
                f"component name {name!r} is not a valid identifier (letters, digits, '_') "
                "or a path of them (front.clutch)"
            )
        if not isinstance(component, Component):
            raise ModelError(
                f"component '{name}': expected a Component such as st.Inertia(J=1.0), got {component!r}"
            )
        if name in self.components:
            raise ModelError(f"component '{name}': a component of that name already exists")
        known = component_types()
        if known is not None:
            if component.type not in known:
                raise ModelError(
                    f"component '{name}' ({component.type}): unknown component type"
                    f"{_did_you_mean(component.type, list(known))}"
                )
            allowed_set = _names_of(component.type, "parameters")
            for param in component.params:
                if param not in allowed_set:
                    allowed = known[component.type].get("parameters", [])
                    raise ModelError(
                        f"component '{name}' ({component.type}): parameter '{param}': "
                        f"unknown parameter{_did_you_mean(param, allowed)}"
                    )
        problem = self._paths.refusal(name, self.components)
        if problem is not None:
            raise ModelError(problem)
        self.components[name] = component
        return self

    def _check_end(self, end: str) -> tuple[str, str]:
        """Refuse an end that names no port of a component of this model; else its
        component's type and its port."""
        if not isinstance(end, str) or "." not in end:
            raise ModelError(f'connection end {end!r} must be "component.port"')
        comp_name, port = split_last(end)
        if comp_name not in self.components:
            raise ModelError(
                f"connection end '{end}': unknown component '{comp_name}'"
                f"{_did_you_mean(comp_name, list(self.components))}"
            )
        if not port:
            raise ModelError(f"connection end '{end}': missing port name after '.'")
        known = component_types()
        comp_type = self.components[comp_name].type
        if known is not None and comp_type in known:
            ports = known[comp_type].get("ports", [])
            if comp_type == "TimeTable":  # its outputs follow its columns
                ports = time_table_ports(self.components[comp_name].params)
            elif comp_type == "CombiTable1Ds":  # so do these
                ports = table_1ds_ports(self.components[comp_name].params)
            elif port in _names_of(comp_type, "ports"):  # a set: thousands of ends in a big model
                return comp_type, port
            if port not in ports:
                raise ModelError(
                    f"component '{comp_name}' ({comp_type}): port '{port}': "
                    f"unknown port{_did_you_mean(port, ports)}; "
                    f"ports are {', '.join(ports) or 'none'}"
                )
        return comp_type, port

    def connect(self, a: str, b: str) -> Model:
        """Connect two ports given as "component.port"; returns the model."""
        ends = self._check_end(a), self._check_end(b)
        if a == b:
            raise ModelError(f"connection '{a}' - '{b}': a port cannot be connected to itself")
        self._check_domains(a, b, ends)
        if self._connected(a, b):
            raise ModelError(f"connection '{a}' - '{b}': already connected")
        self.connections.append((a, b))
        self._pairs.add(frozenset((a, b)))
        return self

    @staticmethod
    def _check_domains(a: str, b: str, ends: tuple[tuple[str, str], tuple[str, str]]) -> None:
        """Refuse an angle joined to a position here, where the connect is written (the engine
        refuses it too, at check; its words); ``ends``: each end's component type and port."""
        ka, kb = _port_kind(*ends[0]), _port_kind(*ends[1])
        if ka != kb and {ka, kb} == {"flange", "translational flange"}:
            rot = lambda kind: "rotational " if kind == "flange" else ""
            raise ModelError(
                f"connection {a} — {b}: cannot connect the {rot(ka)}{ka} '{a}' to the {rot(kb)}{kb} "
                f"'{b}': an angle and a position are joined only through a component that converts "
                "rotation into translation (IdealRollingWheel, IdealGearR2T)"
            )

    def _connected(self, a: str, b: str) -> bool:
        """Whether a-b is in ``connections``, through a set (linear cost to build a model); the
        set is rebuilt when the public list was changed directly, and a hit is confirmed."""
        if len(self._pairs) != len(self.connections):
            self._pairs = {frozenset(pair) for pair in self.connections}
        if frozenset((a, b)) not in self._pairs:
            return False
        return (a, b) in self.connections or (b, a) in self.connections

    def set(self, name: str, value: Any) -> Model:
        """Change one parameter, ``m.set("brake.fn_max", 1800.0)``; returns the model.

        A quantity with a unit is converted to the parameter's unit (``"20 kN"`` → 20000.0 N).

        The name and the value get the checks a component gets when the model is read:
        unknown names (with suggestions), types, ranges and table shapes — now, not at the
        next run. On an error the model is left unchanged.
        """
        comp_name, param = split_last(name)
        if comp_name not in self.components or not param:
            raise ModelError(
                f"set '{name}': expected 'component.parameter' with a component of this model"
                f"{_did_you_mean(comp_name, list(self.components))}"
            )
        old = self.components[comp_name]
        params = {**old.params, param: value}
        try:  # "20 kN" is converted here, to the parameter's unit
            new = FACTORIES[old.type](**params) if old.type in FACTORIES else Component(old.type, params)
        except ModelError as exc:
            detail = str(exc).removeprefix(f"{old.type}: ")
            raise ModelError(f"component '{comp_name}' ({old.type}): {detail}") from None
        known = component_types()
        allowed = known[old.type]["parameters"] if known and old.type in known else [param]
        if param not in allowed:
            raise ModelError(
                f"component '{comp_name}' ({old.type}): parameter '{param}': "
                f"unknown parameter{_did_you_mean(param, allowed)}"
            )
        from stiction import _core
        from stiction.model.parameters import evaluate_parameters, resolve_params

        values = resolve_params(comp_name, new.params, evaluate_parameters(self.parameters))
        text = modelfile.dumps(self.name, {}, [(comp_name, new.type, values)], [], {})
        _core.check_parameters(text, str(self.base_dir))
        self.components[comp_name] = new
        return self

    def check_name(self, name: str, context: str) -> None:
        """Raise ``ModelError`` (naming ``context``, e.g. "sweep") unless ``name`` is what a run
        may override: an experiment setting, a top-level parameter, or a component's parameter
        or start value (``clutch1.fn_max``, ``J1.w``), with suggestions for a near miss."""
        if name in modelfile.EXPERIMENT_KEYS or name in self.parameters:
            return
        comp_name, param = split_last(name)
        if comp_name not in self.components or not param:
            raise ModelError(
                f"{context} '{name}': not an experiment setting, a top-level parameter or "
                f"'component.parameter' of this model"
                + _did_you_mean(
                    name if not param else comp_name, [*modelfile.EXPERIMENT_KEYS, *self.parameters]
                )
                + (_did_you_mean(comp_name, list(self.components)) if param else "")
            )
        comp_type = self.components[comp_name].type
        known = component_types()
        allowed = known[comp_type]["parameters"] if known and comp_type in known else [param]
        if param not in allowed:
            raise ModelError(
                f"{context} '{name}': component '{comp_name}' ({comp_type}): parameter '{param}': "
                f"unknown parameter{_did_you_mean(param, allowed)}"
            )

    def input(self, port: str, start: float = 0.0) -> Model:
        """Declare an unconnected signal input ("brake.f_normalized") an input of the model.

        Its value is ``start`` until a ``Simulation`` (or an FMU host) sets it; a jump is an
        event at that instant. An unconnected input that is not declared stays an error.
        """
        self._check_end(port)
        if isinstance(start, bool) or not isinstance(start, (int, float)):
            raise ModelError(f"input '{port}': start must be a number, got {start!r}")
        if any(port in pair for pair in self.connections):
            raise ModelError(f"input '{port}': the port is connected; a model input is left unconnected")
        self.inputs[port] = float(start)
        return self

    def __getitem__(self, name: str) -> Component:
        return self.components[name]

    if not TYPE_CHECKING:  # hidden from type checkers, which would take any name through it

        def __getattr__(self, name: str) -> Any:
            # only attributes that are missing come here: a loaded file's objects, made now
            if name in LAZY_FIELDS and self.__dict__.get("_lazy") is not None:
                self._materialize()
                return self.__dict__[name]
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _as_loaded(self) -> LoadedFile | None:
        """The file this model was loaded from lazily, while the model still says what the
        file does (nothing made yet, nothing set in its place, the same name); else None."""
        lazy = self._lazy
        if lazy is None or self.name != lazy.name or not LAZY_FIELDS.isdisjoint(self.__dict__):
            return None
        return lazy

    def _materialize(self) -> None:
        """Make a lazily loaded file's components, connections and the rest, as loading it in
        Python would have; an attribute set meanwhile stays as set. While the model still says
        what the file does, the file stays its engine text (no writing it anew to run it)."""
        lazy = self.__dict__.get("_lazy")
        if lazy is None:
            return
        untouched = self._as_loaded() is not None
        with gc_paused():  # an error here (none expected: the engine took the file) leaves it lazy
            built = type(self)._from_data(lazy.data(), self.base_dir, lazy.default_name)
        del self._lazy
        own = self.__dict__
        for field in LAZY_FIELDS:
            own.setdefault(field, built.__dict__[field])
        key = self._text_key() if untouched else None
        if key is not None:
            self._derived = (key, lazy.engine_text, None)

    def __getstate__(self) -> dict[str, Any]:
        # a pickle holds the objects (made now if need be), not the engine's compile of the file
        self._materialize()
        return {**self.__dict__, "_parsed": None}

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Model):
            return NotImplemented
        return (
            self.name == other.name
            and _meaning(self.components) == _meaning(other.components)
            and self.connections == other.connections
            and self.experiment == other.experiment
            and self.inputs == other.inputs
            and _meaning(self.variables, expressions=True) == _meaning(other.variables, expressions=True)
            and _meaning(self.parameters, expressions=True) == _meaning(other.parameters, expressions=True)
            and self.declarations == other.declarations
        )

    __hash__ = None  # type: ignore[assignment]  # mutable

    def __repr__(self) -> str:
        lazy = self._as_loaded()
        if lazy is not None:
            components, connections = lazy.counts
            return f"<Model {self.name!r}: {components} components, {connections} connections>"
        return (
            f"<Model {self.name!r}: {len(self.components)} components, {len(self.connections)} connections>"
        )

    def variable(self, name: str, expression: str) -> Model:
        """Add a derived variable: a result column computed from the run by a Modelica
        expression over result variables, e.g. ``"J1.w - J2.w"`` or ``"J.w*der(J.phi)"``."""
        from stiction.expressions.parser import parse_expression

        if not isinstance(name, str) or not IDENTIFIER.fullmatch(name):
            raise ModelError(f"variable name {name!r} is not a valid identifier")
        if name in self.components or name in self.variables:
            raise ModelError(f"variable '{name}': the name is already used")
        parse_expression(expression, f"variable '{name}'")
        self.variables[name] = expression
        return self

    # --- files ------------------------------------------------------------------------
    def to_toml(self) -> str:
        """The model as model-file text (what ``save`` writes)."""
        return modelfile.dumps(
            self.name,
            self.experiment,
            ((n, c.type, c.params) for n, c in self.components.items()),
            self.connections,
            self.inputs,
            self.variables,
            self.parameters,
            self.declarations,
        )

    def engine_toml(self) -> str:
        """The model-file text the engine reads: parameter expressions evaluated; derived
        variables as written, with the values of the top-level parameters they read (the
        engine computes them as result variables)."""
        return self._derived_of(values=False)[0]

    def _text_key(self) -> str | None:
        """A fingerprint of everything the engine text and the parameter values depend on:
        the ``repr`` of plain data, exact for numbers, and far cheaper than writing the text
        (a run of a small model spent most of its Python time writing it, twice). None when a
        value's ``repr`` may not show all of it (an object, a summarized array)."""
        comps = [(n, c.type, c.params) for n, c in self.components.items()]
        parts = (self.name, self.experiment, comps, self.connections, self.inputs, self.parameters)
        key = repr((*parts, self.variables))
        return None if "<" in key or "..." in key else key

    def _text_and_values(self) -> tuple[str, dict[str, float]]:
        text, values = self._derived_of(values=True)
        assert values is not None
        return text, values

    def _derived_of(self, values: bool) -> tuple[str, dict[str, float] | None]:
        """The engine text and, if ``values``, the parameter values, kept while the model's
        fingerprint is unchanged; the values only when asked for (``check`` needs none, and
        they import the Modelica converter's table of start variables)."""
        with gc_paused():
            return self._derived_unpaused(values)

    def _derived_unpaused(self, values: bool) -> tuple[str, dict[str, float] | None]:
        lazy = self._as_loaded()
        if lazy is not None:  # a loaded file, untouched: its text
            return lazy.engine_text, (lazy.parameter_values() if values else None)
        key = self._text_key()
        cached = self._derived if key is not None and self._derived and self._derived[0] == key else None
        text = cached[1] if cached else self._write_engine_toml()
        known = cached[2] if cached else None
        if values and known is None:
            known = self._parameter_values()
        self._derived = None if key is None else (key, text, known)
        return text, known

    def _write_engine_toml(self) -> str:
        from stiction.model.parameters import evaluate_parameters, resolve_params

        values = evaluate_parameters(self.parameters)
        return modelfile.dumps(
            self.name,
            self.experiment,
            ((n, c.type, resolve_params(n, c.params, values)) for n, c in self.components.items()),
            self.connections,
            self.inputs,
            self.variables,
            numbers_read(self.variables, values),
        )

    @classmethod
    def from_modelica(
        cls,
        source: str | os.PathLike[str],
        model: str | None = None,
    ) -> Model:
        """Read a Modelica model (a ``.mo`` path or its text); ``model`` picks one of several.

        The subset MSL-style models use is read (see docs/modelica.md); anything else raises
        ``ModelError`` starting with ``file:line:column``.
        """
        from stiction.modelica import read_modelica

        return read_modelica(source, model)

    def to_modelica(self, path: str | os.PathLike[str] | None = None) -> str:
        """The model as Modelica text with fully qualified MSL classes; written to ``path``
        if given. ``Model.from_modelica`` reads it back to the same model."""
        from stiction.modelica.export import write_modelica

        text = write_modelica(self)
        if path is not None:
            Path(path).write_text(text, encoding="utf-8")
        return text

    def to_fmu(
        self,
        path: str | os.PathLike[str],
        fmi_version: int = 2,
        outputs: list[str] | None = None,
    ) -> Path:
        """Write the model as an FMI Co-Simulation FMU (see ``stiction.fmu``): its declared
        inputs are the FMU's inputs, ``outputs`` (default: the states) its outputs, the
        components' Real parameters its parameters by MSL name."""
        from stiction.fmu.export import export_fmu

        return export_fmu(self, path, fmi_version, outputs)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the model file; relative file parameters stay relative to it."""
        Path(path).write_text(self.to_toml(), encoding="utf-8")

    @classmethod
    def loads(
        cls,
        text: str,
        base_dir: str | os.PathLike[str] = ".",
        *,
        source: str = "model",
        default_name: str = "model",
    ) -> Model:
        """Build a model from model-file text, checked as if built in Python."""
        lazy, doc, parsed = load_file(cls, text, base_dir, source, default_name)
        if lazy is not None:  # compiled, and so checked; its objects are made when first read
            return lazy
        with gc_paused():
            if parsed is not None:
                # compiled while the objects are made; kept if the text is the engine text
                from stiction.run.compiled import Precompiled

                parsed = Precompiled(parsed)
            data = modelfile.parse(text, source, doc)
            model = cls._from_data(data, base_dir, default_name)
            model._adopt_text(text, data, parsed)
            return model

    def _adopt_text(self, text: str, data: modelfile.ModelData, parsed: Any = None) -> None:
        """Keep the file's own ``text`` as the engine text when it says what writing the model
        would (no top-level parameters or declarations, every parameter as the component
        holds it, type for type): a model loaded and run unchanged is not written back (a
        ladder of 1000 inertias spent 40 ms on it). A change to the model changes its
        fingerprint, and the text is written anew."""
        if data.parameters or data.declarations:
            return
        comps = self.components
        if any(not _same_params(params, comps[name].params) for name, _, params in data.components):
            return
        if data.name is None:  # the engine text names the model
            text = named_text(self.name, text)
        key = self._text_key()
        if key is not None:
            self._derived = (key, text, None)
            if parsed is not None:  # the engine's compile of the same parse (`Precompiled`)
                self._parsed = (text, str(self.base_dir), parsed)

    @classmethod
    def _from_data(
        cls, data: modelfile.ModelData, base_dir: str | os.PathLike[str], default_name: str
    ) -> Model:
        model = cls(data.name or default_name, base_dir=base_dir)
        model.experiment.update(data.experiment)
        for comp_name, comp_type, params in data.components:
            make = FACTORIES.get(comp_type)
            try:
                comp = make(**params) if make else Component(comp_type, params)
            except ModelError as exc:
                detail = str(exc).removeprefix(f"{comp_type}: ")
                raise ModelError(f"component '{comp_name}' ({comp_type}): {detail}") from None
            model.add(comp_name, comp)
        for a, b in data.connections:
            model.connect(a, b)
        for port, start in data.inputs.items():
            model.input(port, start)
        for var_name, expression in data.variables.items():
            model.variable(var_name, expression)
        model.parameters.update(data.parameters)
        model.declarations.update(data.declarations)
        return model

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Model:
        """Read a model file (TOML, or Modelica when it ends in ``.mo``, as ``from_modelica``);
        its folder becomes the base of relative file names."""
        path = Path(path)
        if path.suffix == ".mo":
            return cls.from_modelica(path)
        text = path.read_text(encoding="utf-8")
        try:
            return cls.loads(
                text,
                base_dir=path.resolve().parent,
                source=str(path),
                default_name=path.stem,
            )
        except ModelError as exc:
            message = str(exc)
            if not message.startswith(str(path)):
                message = f"{path}: {message}"
            raise ModelError(message) from None

    # --- running ----------------------------------------------------------------------
    def simulation(self, Solver: str | None = None, **experiment: float) -> Simulation:
        """A resumable run of the model (``advance_to``, ``set_input``, ``get`` …).

        Keyword arguments (``StopTime=2.0``, ``Solver="bdf"`` …) override the experiment.
        """
        from stiction.run.simulation import Simulation

        return Simulation(self, Solver, **experiment)

    def run_info(self) -> RunInfo:
        """The experiment and initialization a run of this model would use, without running."""
        return RunInfo(self.engine_toml(), str(self.base_dir), {}, None, self.types())

    def check(self) -> None:
        """Let the engine validate the whole model without running it."""
        from stiction import _core

        _core.check(self.engine_toml(), str(self.base_dir))

    def compile(self) -> CompiledModel:
        """The model compiled for repeated runs; reused while the model is unchanged.

        Any change to the model, through any API, changes its text and so compiles anew.
        """
        return self._compile(self.engine_toml())

    def _compile(self, text: str) -> CompiledModel:
        from stiction.run.compiled import CompiledModel

        key = (text, str(self.base_dir))
        if self._compiled is None or self._compiled[0] != key:
            parsed, self._parsed = self._parsed, None
            engine = parsed[2] if parsed is not None and parsed[:2] == key else None
            self._compiled = (key, CompiledModel(key[0], self.base_dir, self.name, parsed=engine))
        return self._compiled[1]

    def simulate(
        self,
        StartTime: float | None = None,  # MSL experiment names, hence capitalised
        StopTime: float | None = None,
        Interval: float | None = None,
        Tolerance: float | None = None,
        Solver: str | None = None,
        params: Mapping[str, Any] | None = None,
        record: str = "states",
    ) -> Result:
        """Run the model; arguments override its experiment settings for this run.

        ``record="states"`` (the default) records the states; every other variable is computed
        from them when first read (``r.data`` computes all of them at once, on every core).
        ``record="all"`` computes every variable while the run goes on, on the other cores, so
        that ``r.data`` is at hand when the run returns: less time from start to every
        variable on a machine of two cores or more. The values are the same, bit for bit.

        ``Solver`` is "auto" (the default: tsit45, changing to esdirk34 once the run is stiff),
        "tsit45", "bdf" or "esdirk34". ``params`` overrides parameters and start values by name for this run (``{"clutch1.fn_max": 30,
        "J1.w": 5}``); the model itself is unchanged. The result reports the experiment used
        (``r.experiment``, with the settings left at defaults) and the initialization
        (``r.initialization``, of the model without ``params``).
        """
        from stiction.run.simulate import simulate

        return simulate(self, StartTime, StopTime, Interval, Tolerance, Solver, params, record)

    def types(self) -> dict[str, str]:
        """Component name → type name (``{"brake": "Brake"}``)."""
        return {name: c.type for name, c in self.components.items()}

    def parameter_values(self) -> dict[str, float]:
        """Scalar parameters as ``component.parameter -> value`` (Booleans as 0/1), top-level
        ones by their name, as a Modelica result's data_1 holds them; start values are
        trajectories, not here."""
        return dict(self._text_and_values()[1])

    def _parameter_values(self) -> dict[str, float]:
        return parameter_values(self.parameters, {n: c.params for n, c in self.components.items()})


def parameter_values(
    parameters: Mapping[str, Any], components: Mapping[str, Mapping[str, Any]]
) -> dict[str, float]:
    """Scalar parameters as ``component.parameter -> value`` (see ``Model.parameter_values``)
    of the top-level ``parameters`` and each component's parameters, by component name."""
    from stiction.model.components import START_VARIABLES
    from stiction.model.parameters import evaluate_parameters, resolve_params

    top = evaluate_parameters(parameters)
    values = {k: float(v) for k, v in top.items() if isinstance(v, (bool, int, float))}
    for comp_name, params in components.items():
        for key, value in resolve_params(comp_name, params, top).items():
            if key not in START_VARIABLES and isinstance(value, (bool, int, float)):
                values[f"{comp_name}.{key}"] = float(value)
    return values
