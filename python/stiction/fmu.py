"""FMU export: a model as an FMI 2.0 Co-Simulation FMU that any FMI importer runs.

The FMU holds ``modelDescription.xml``, the runtime library (``crates/stiction-fmi``, a C-ABI
build of the engine: no Python in the importer's process) in ``binaries/<platform>/`` and, in
``resources/``, the model file and the table that maps value references to names. Inputs are
the model's declared inputs; outputs are the chosen variables; parameters are the numeric
parameters of the components with their MSL names, set before the end of initialization
(``variability="fixed"``: the engine compiles them into the run).
"""

from __future__ import annotations

import datetime
import os
import platform
import re
import sys
import tomllib
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING
from xml.sax.saxutils import quoteattr

from . import __version__
from .errors import ModelError, StictionError

if TYPE_CHECKING:
    from .model import Model

__all__ = ["export_fmu", "runtime_library"]

LIBRARY = {"linux": "libstiction_fmi.so", "darwin": "libstiction_fmi.dylib", "win32": "stiction_fmi.dll"}
PLATFORM = {"linux": ("linux64", ".so"), "darwin": ("darwin64", ".dylib"), "win32": ("win64", ".dll")}
# variables whose values are states, by component type: the default outputs
STATES = {"Inertia": ("phi", "w"), "HeatCapacitor": ("T",)}


@dataclass(frozen=True)
class FmuVariable:
    """One scalar variable of the FMU, in value-reference order."""

    name: str
    kind: str  # input, output or parameter
    start: float
    unit: str = ""
    description: str = ""


def runtime_library() -> Path:
    """The FMU runtime built for this platform: shipped in the package, or in the build tree.

    ``STICTION_FMI_LIBRARY`` names another build.
    """
    name = LIBRARY.get(sys.platform, "libstiction_fmi.so")
    candidates = [Path(os.environ["STICTION_FMI_LIBRARY"])] if "STICTION_FMI_LIBRARY" in os.environ else []
    here = Path(__file__).resolve().parent
    candidates += [here / name, here.parents[1] / "target" / "release" / name]
    for path in candidates:
        if path.is_file():
            return path
    raise StictionError(
        f"the FMU runtime ({name}) is not built: run `make setup` "
        "(or `cargo build --release -p stiction-fmi`)"
    )


def _platform() -> tuple[str, str]:
    """The FMI 2.0 ``binaries/`` folder of this platform and its library suffix."""
    if sys.platform not in PLATFORM or platform.machine().lower() not in ("x86_64", "amd64"):
        raise StictionError(f"FMU export: FMI 2.0 names no platform for {sys.platform}/{platform.machine()}")
    return PLATFORM[sys.platform]


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _parameters(model: Model, components: dict[str, dict]) -> list[FmuVariable]:
    """Every Real parameter with a numeric value (given, or its MSL default)."""
    from .catalogue import catalogue

    known = catalogue()
    found = []
    for name, spec in components.items():
        for p in known[spec["type"]].parameters:
            value = spec.get(p.name, p.default)
            if p.kind == "Real" and _is_number(value):
                found.append(
                    FmuVariable(f"{name}.{p.name}", "parameter", float(value), p.unit, p.description)
                )
    return found


def default_outputs(model: Model) -> list[str]:
    """The states: every Inertia's phi and w, every HeatCapacitor's T."""
    return [f"{n}.{v}" for n, c in model.components.items() for v in STATES.get(c.type, ())]


def _outputs(model: Model, names: list[str]) -> list[FmuVariable]:
    from .catalogue import unit_of

    known = set(model.simulation().values())
    types = model.types()
    found = []
    for name in names:
        if name not in known:
            raise ModelError(f"output '{name}': not a variable of the model")
        found.append(FmuVariable(name, "output", 0.0, unit_of(name, types)))
    return found


def interface(model: Model, outputs: list[str] | None = None) -> list[FmuVariable]:
    """The FMU's variables: inputs, outputs, parameters, in value-reference order."""
    components = tomllib.loads(model.engine_toml()).get("components", {})
    inputs = [FmuVariable(port, "input", start) for port, start in model.inputs.items()]
    chosen = _outputs(model, list(outputs) if outputs is not None else default_outputs(model))
    return inputs + chosen + _parameters(model, components)


def _identifier(name: str) -> str:
    ident = re.sub(r"\W", "_", name)
    return ident if re.match(r"[A-Za-z_]", ident) else "_" + ident


def _scalar(k: int, v: FmuVariable) -> str:
    attrs = {
        "input": 'causality="input" variability="continuous"',
        "output": 'causality="output" variability="continuous" initial="calculated"',
        "parameter": 'causality="parameter" variability="fixed" initial="exact"',
    }[v.kind]
    if v.kind == "output" and v.name.endswith(".mode"):
        attrs = attrs.replace("continuous", "discrete")
    desc = f" description={quoteattr(v.description)}" if v.description else ""
    real = [f'unit="{v.unit}"'] if v.unit else []
    real += [] if v.kind == "output" else [f'start="{v.start!r}"']
    return (
        f'    <ScalarVariable name={quoteattr(v.name)} valueReference="{k}" {attrs}{desc}>\n'
        f"      <Real {' '.join(real)}/>\n    </ScalarVariable>"
    )


def model_description(model: Model, variables: list[FmuVariable], ident: str, guid: str) -> str:
    """``modelDescription.xml`` (FMI 2.0, Co-Simulation)."""
    exp = tomllib.loads(model.engine_toml()).get("experiment", {})
    units = sorted({v.unit for v in variables if v.unit})
    outs = [k + 1 for k, v in enumerate(variables) if v.kind == "output"]
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    experiment = " ".join(
        f'{fmi}="{float(exp[ours])!r}"'
        for fmi, ours in [("startTime", "StartTime"), ("stopTime", "StopTime"), ("tolerance", "Tolerance")]
        if ours in exp
    )
    unknowns = "\n".join(f'      <Unknown index="{k}"/>' for k in outs)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(model.name)} guid="{guid}"
  generationTool="stiction {__version__}" generationDateAndTime="{now}"
  variableNamingConvention="structured" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUstate="true" canSerializeFMUstate="false" canNotUseMemoryManagementFunctions="true"/>
  <UnitDefinitions>
{chr(10).join(f"    <Unit name={quoteattr(u)}/>" for u in units)}
  </UnitDefinitions>
  <DefaultExperiment {experiment}/>
  <ModelVariables>
{chr(10).join(_scalar(k, v) for k, v in enumerate(variables))}
  </ModelVariables>
  <ModelStructure>
    <Outputs>
{unknowns}
    </Outputs>
    <InitialUnknowns>
{unknowns}
    </InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""


def variable_table(variables: list[FmuVariable], guid: str) -> str:
    """``resources/variables.tsv``: what the runtime reads to map value references."""
    rows = [f"{k}\t{v.kind}\t{v.name}\t{v.start!r}" for k, v in enumerate(variables)]
    return "\n".join([f"guid\t{guid}", *rows]) + "\n"


def export_fmu(
    model: Model,
    path: str | os.PathLike[str],
    fmi_version: int = 2,
    outputs: list[str] | None = None,
) -> Path:
    """Write ``model`` as a Co-Simulation FMU to ``path``; returns the path."""
    if fmi_version != 2:
        raise ModelError(f"fmi_version={fmi_version}: only FMI 2.0 FMUs are written so far")
    library = runtime_library()
    variables = interface(model, outputs)
    text = model.engine_toml()
    guid = "{" + str(uuid.uuid5(uuid.NAMESPACE_URL, text + variable_table(variables, ""))) + "}"
    ident = _identifier(model.name)
    folder, ext = _platform()
    path = Path(path)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("modelDescription.xml", model_description(model, variables, ident, guid))
        z.write(library, f"binaries/{folder}/{ident}{ext}")
        z.writestr("resources/model.toml", text)
        z.writestr("resources/variables.tsv", variable_table(variables, guid))
    return path
