"""FMU export: a model as an FMI 2.0 or 3.0 Co-Simulation FMU that any FMI importer runs.

The FMU holds ``modelDescription.xml``, the runtime library (``crates/stiction-fmi``, a C-ABI
build of the engine: no Python in the importer's process) in ``binaries/<platform>/`` (this
platform's, and every other platform's that is built: ``make fmu-windows``) and, in
``resources/``, the model file and the table that maps value references to names. Inputs are
the model's declared inputs; outputs are the chosen variables; parameters are the Real and
Boolean parameters of the components with their MSL names, and the tables given in the model
(FMI 3.0: an array variable; FMI 2.0: one Real per element, ``brake.mu_pos[2,1]``). Those the
catalogue marks tunable (``Parameter.tunable``: a brake's ``fn_max``, a spring's ``c``, an
inertia's ``J``, a friction table) are ``variability="tunable"``: the host may set them between
two ``doStep`` calls too, an event at the communication point; the others are ``fixed``, set
before the end of initialization (the engine compiles them into the run). Boolean parameters that change a component's ports (``useSupport``, ``useHeatPort``, an
adaptor's ``use_w``) stay in the model file: they decide what the compiled model is. The start
values of the states (``J1.w``, a OneWayClutch's Boolean ``stuck``) are the FMI way: the
state's variable (an output if chosen, else a local one) has ``initial="exact"`` (fixed) or
``"approx"`` (a guess) and its start, settable before the end of initialization.
"""

from __future__ import annotations

import os
import platform
import re
import sys
import tomllib
import uuid
import zipfile
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from stiction.errors import ModelError, StictionError
from stiction.fmu import description as fmu_xml

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["export_fmu", "other_runtimes", "runtime_library"]

LIBRARY = {"linux": "libstiction_fmi.so", "darwin": "libstiction_fmi.dylib", "win32": "stiction_fmi.dll"}
# binaries/ folder names of FMI 2.0 and FMI 3.0, and the library suffix
PLATFORM = {
    "linux": ("linux64", "x86_64-linux", ".so"),
    "darwin": ("darwin64", "x86_64-darwin", ".dylib"),
    "win32": ("win64", "x86_64-windows", ".dll"),
}
# a TorqueToAngleAdaptor's use_w and use_a decide which of its signals exist (FMU outputs)
ADAPTOR_SIGNALS = {"use_w", "use_a"}
# variables whose values are states, by component type: the default outputs
STATES = {"Inertia": ("phi", "w"), "Translational.Mass": ("s", "v"), "HeatCapacitor": ("T",)}


@dataclass(frozen=True)
class FmuVariable:
    """One variable of the FMU, in value-reference order."""

    name: str
    #: input, output, parameter, independent (time, FMI 3.0), start or guess (a Real state's
    #: start value), boolean (a Boolean parameter), boolean-start (a Boolean state's start
    #: value), table (FMI 3.0: a table parameter as an array) or element (FMI 2.0: one of its
    #: elements, ``brake.mu_pos[2,1]``)
    kind: str
    start: float
    unit: str = ""
    description: str = ""
    #: a state with a start value (kind start: fixed, guess: not): also an FMU output?
    output: bool = False
    #: a table's rows and columns, and its values row after row (``start`` is unused)
    shape: tuple[int, int] | None = None
    values: tuple[float, ...] = ()
    #: a parameter the host may set in step mode too (``variability="tunable"``)
    tunable: bool = False

    @property
    def is_boolean(self) -> bool:
        """Whether the variable is an FMI Boolean (else Real / Float64)."""
        return self.kind in ("boolean", "boolean-start")

    def table_kind(self) -> str:
        """The kind as the variable table writes it (a table's shape follows its kind)."""
        return f"table:{self.shape[0]}x{self.shape[1]}" if self.kind == "table" and self.shape else self.kind

    def start_text(self) -> str:
        """The start value(s) as the variable table writes them."""
        return " ".join(repr(float(v)) for v in self.values) if self.kind == "table" else repr(self.start)


def runtime_library() -> Path:
    """The FMU runtime built for this platform: shipped in the package, or in the build tree.

    ``STICTION_FMI_LIBRARY`` names another build.
    """
    name = LIBRARY.get(sys.platform, "libstiction_fmi.so")
    candidates = [Path(os.environ["STICTION_FMI_LIBRARY"])] if "STICTION_FMI_LIBRARY" in os.environ else []
    package = Path(__file__).resolve().parents[1]  # python/stiction, where `make setup` puts it
    candidates += [package / name, package.parents[1] / "target" / "release" / name]
    for path in candidates:
        if path.is_file():
            return path
    raise StictionError(
        f"the FMU runtime ({name}) is not built: run `make setup` "
        "(or `cargo build --release -p stiction-fmi`)"
    )


# The Rust target of each platform's runtime: `make fmu-windows` cross-builds the Windows one.
RUST_TARGET = {
    "linux": "x86_64-unknown-linux-gnu",
    "darwin": "x86_64-apple-darwin",
    "win32": "x86_64-pc-windows-gnu",
}


def other_runtimes() -> dict[str, Path]:
    """Runtimes built for other platforms, by platform (``win32``): an FMU carries them beside
    this platform's, so one file runs on each. Found next to this platform's runtime in the
    package, or in the build tree (``target/<rust target>/release``, ``target/cross/...``)."""
    package = Path(__file__).resolve().parents[1]
    target = package.parents[1] / "target"
    found = {}
    for plat, name in LIBRARY.items():
        if plat == sys.platform:
            continue
        triple = RUST_TARGET[plat]
        for path in (
            package / name,
            target / triple / "release" / name,
            target / "cross" / triple / "release" / name,
        ):
            if path.is_file():
                found[plat] = path
                break
    return found


def _platform(fmi_version: int) -> tuple[str, str]:
    """The ``binaries/`` folder of this platform and its library suffix."""
    if sys.platform not in PLATFORM or platform.machine().lower() not in ("x86_64", "amd64"):
        raise StictionError(f"FMU export: no FMI platform name for {sys.platform}/{platform.machine()}")
    fmi2, fmi3, ext = PLATFORM[sys.platform]
    return (fmi2 if fmi_version == 2 else fmi3), ext


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _structural(info: object) -> set[str]:
    """The Boolean parameters that change a component's ports (``useSupport``,
    ``useHeatPort``, an adaptor's ``use_w``): the model is compiled with them, so they stay in
    the model file."""
    return {p.enabled_by for p in info.ports if p.enabled_by} | ADAPTOR_SIGNALS


def _table(value: object) -> list[list[float]] | None:
    """A table given in the model (rows of numbers, all of one length), else None."""
    if not isinstance(value, list) or not value or not all(isinstance(r, list) for r in value):
        return None
    if len({len(r) for r in value}) != 1 or not all(_is_number(x) for r in value for x in r):
        return None
    return value


def _table_variables(
    name: str, rows: list[list[float]], description: str, fmi_version: int, tunable: bool
) -> list[FmuVariable]:
    """FMI 3.0: one array variable; FMI 2.0: one Real per element, ``name[i,j]`` (1-based)."""
    if fmi_version == 3:
        values = tuple(float(x) for r in rows for x in r)
        shape = (len(rows), len(rows[0]))
        return [FmuVariable(name, "table", 0.0, "", description, shape=shape, values=values, tunable=tunable)]
    return [
        FmuVariable(f"{name}[{i + 1},{j + 1}]", "element", float(x), "", description, tunable=tunable)
        for i, r in enumerate(rows)
        for j, x in enumerate(r)
    ]


def _parameters(model: Model, components: dict[str, dict], fmi_version: int = 2) -> list[FmuVariable]:
    """Every Real parameter with a numeric value (given, or its MSL default), every Boolean
    parameter that leaves the structure alone, and every table given in the model."""
    from stiction.model.catalogue import catalogue

    known = catalogue()
    found = []
    for name, spec in components.items():
        info = known[spec["type"]]
        for p in info.parameters:
            value = spec.get(p.name, p.default)
            full = f"{name}.{p.name}"
            if p.kind == "Real" and _is_number(value):
                found.append(
                    FmuVariable(full, "parameter", float(value), p.unit, p.description, tunable=p.tunable)
                )
            elif p.kind == "Boolean" and isinstance(value, bool) and p.name not in _structural(info):
                found.append(FmuVariable(full, "boolean", float(value), "", p.description))
            elif p.kind.startswith("table") and "file" not in spec and (rows := _table(value)) is not None:
                found.extend(_table_variables(full, rows, p.description, fmi_version, p.tunable))
    return found


def _start_values(components: dict[str, dict]) -> dict[str, FmuVariable]:
    """The start value of every Real state (an Inertia's phi and w, a HeatCapacitor's T), by
    the state's name: ``start`` where the model fixes it (a bare number, ``fixed = true``),
    ``guess`` where it is a guess for the initialization (``fixed = false``, or not given); and
    of every Boolean state (a OneWayClutch's ``stuck``): ``boolean-start``."""
    from stiction.model.catalogue import catalogue

    known = catalogue()
    found = {}
    for name, spec in components.items():
        for p in known[spec["type"]].parameters:
            if p.kind not in ("start value", "Boolean start value"):
                continue
            value = spec.get(p.name, {})
            value = value if isinstance(value, dict) else {"start": value, "fixed": True}
            start = value.get("start", p.default)
            full = f"{name}.{p.name}"
            if p.kind == "Boolean start value" and isinstance(start, bool):
                found[full] = FmuVariable(full, "boolean-start", float(start), "", p.description)
            elif _is_number(start):
                kind = "start" if value.get("fixed", False) else "guess"
                found[full] = FmuVariable(full, kind, float(start), p.unit, p.description)
    return found


def default_outputs(model: Model) -> list[str]:
    """The states: every Inertia's phi and w, every HeatCapacitor's T."""
    return [f"{n}.{v}" for n, c in model.components.items() for v in STATES.get(c.type, ())]


def _outputs(model: Model, names: list[str]) -> list[FmuVariable]:
    from stiction.model.catalogue import unit_of

    known = set(model.simulation().values())
    types = model.types()
    found = []
    for name in names:
        if name not in known:
            raise ModelError(f"output '{name}': not a variable of the model")
        found.append(FmuVariable(name, "output", 0.0, unit_of(name, types)))
    return found


def interface(model: Model, outputs: list[str] | None = None, fmi_version: int = 2) -> list[FmuVariable]:
    """The FMU's variables: inputs, outputs, parameters (and time for FMI 3.0), in
    value-reference order."""
    components = tomllib.loads(model.engine_toml()).get("components", {})
    inputs = [FmuVariable(port, "input", start) for port, start in model.inputs.items()]
    chosen = _outputs(model, list(outputs) if outputs is not None else default_outputs(model))
    variables = set(model.simulation().values())
    starts = {n: v for n, v in _start_values(components).items() if n in variables}
    # a chosen state is the output that carries its start value; the others are local variables
    chosen = [
        replace(starts.pop(v.name), unit=v.unit, output=True) if v.name in starts else v for v in chosen
    ]
    time = [FmuVariable("time", "independent", 0.0, "s", "Simulation time")] if fmi_version == 3 else []
    params = _parameters(model, components, fmi_version)
    return inputs + chosen + params + list(starts.values()) + time


def _identifier(name: str) -> str:
    ident = re.sub(r"\W", "_", name)
    return ident if re.match(r"[A-Za-z_]", ident) else "_" + ident


def variable_table(variables: list[FmuVariable], guid: str) -> str:
    """``resources/variables.tsv``: what the runtime reads to map value references."""
    rows = [f"{k}\t{v.table_kind()}\t{v.name}\t{v.start_text()}" for k, v in enumerate(variables)]
    return "\n".join([f"guid\t{guid}", *rows]) + "\n"


def export_fmu(
    model: Model,
    path: str | os.PathLike[str],
    fmi_version: int = 2,
    outputs: list[str] | None = None,
) -> Path:
    """Write ``model`` as a Co-Simulation FMU (FMI 2.0 or 3.0) to ``path``; returns the path."""
    if fmi_version not in (2, 3):
        raise ModelError(f"fmi_version={fmi_version}: FMI 2 and 3 are written")
    library = runtime_library()
    folder, ext = _platform(fmi_version)
    variables = interface(model, outputs, fmi_version)
    text = model.engine_toml()
    guid = "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, text + variable_table(variables, ""))) + "}"
    ident = _identifier(model.name)
    exp = tomllib.loads(text).get("experiment", {})
    write = fmu_xml.fmi2 if fmi_version == 2 else fmu_xml.fmi3
    path = Path(path)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("modelDescription.xml", write(model.name, exp, variables, ident, guid))
        z.write(library, f"binaries/{folder}/{ident}{ext}")
        for plat, other in other_runtimes().items():
            fmi2, fmi3, other_ext = PLATFORM[plat]
            z.write(other, f"binaries/{fmi2 if fmi_version == 2 else fmi3}/{ident}{other_ext}")
        z.writestr("resources/model.toml", text)
        z.writestr("resources/variables.tsv", variable_table(variables, guid))
        for name in _data_files(model, tomllib.loads(text).get("components", {})):
            z.write(model.base_dir / name, f"resources/{name}")
    return path


def _data_files(model: Model, components: dict[str, dict]) -> list[str]:
    """The files the model reads (a TimeTable's ``file``) by relative name: the FMU carries
    them in ``resources/``, where the runtime resolves relative names. An absolute name would
    point outside the FMU: refused."""
    from stiction.model.catalogue import catalogue

    known = catalogue()
    names = []
    for comp, spec in components.items():
        for p in known[spec["type"]].parameters:
            if p.kind == "String" and p.name == "file" and isinstance(spec.get("file"), str):
                if Path(spec["file"]).is_absolute():
                    raise ModelError(f"{comp}.file: an FMU carries its data files by relative name")
                names.append(spec["file"])
    return names
