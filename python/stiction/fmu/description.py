"""``modelDescription.xml`` of stiction's Co-Simulation FMUs, for FMI 2.0 and FMI 3.0.

Inputs are continuous with their start value; outputs are calculated (``*.mode`` discrete);
parameters (Real, Boolean, a table: FMI 3.0 an array with two ``Dimension``s, FMI 2.0 its
elements) have ``initial="exact"``: ``tunable`` where the catalogue says so (settable between
two ``doStep`` calls: an event at the communication point), else ``fixed`` (compiled into the
run at the end of initialization). A state with a start value (output or local) has ``initial="exact"`` where
the start value is fixed, ``"approx"`` where it is a guess, settable until initialization ends. No event indicators, no derivatives; states can be saved and serialized.
"""

from __future__ import annotations

import datetime
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

from stiction import __version__

if TYPE_CHECKING:
    from stiction.fmu.export import FmuVariable

ATTRIBUTES = {
    "input": 'causality="input" variability="continuous"',
    "output": 'causality="output" variability="continuous" initial="calculated"',
    "parameter": 'causality="parameter" variability="fixed" initial="exact"',
    "independent": 'causality="independent" variability="continuous"',
}
ATTRIBUTES.update(
    boolean=ATTRIBUTES["parameter"], table=ATTRIBUTES["parameter"], element=ATTRIBUTES["parameter"]
)


def _attributes(v: FmuVariable) -> str:
    if v.kind in ("start", "guess", "boolean-start"):
        causality = "output" if v.output else "local"
        initial = "approx" if v.kind == "guess" else "exact"
        variability = "discrete" if v.is_boolean else "continuous"
        attrs = f'causality="{causality}" variability="{variability}" initial="{initial}"'
        return attrs + (f" description={quoteattr(v.description)}" if v.description else "")
    attrs = ATTRIBUTES[v.kind]
    if v.tunable:
        attrs = attrs.replace('variability="fixed"', 'variability="tunable"')
    if v.kind == "output" and v.name.endswith(".mode"):
        attrs = attrs.replace("continuous", "discrete")
    return attrs + (f" description={quoteattr(v.description)}" if v.description else "")


def _start(v: FmuVariable) -> str:
    if v.kind == "table":
        return " ".join(repr(float(x)) for x in v.values)
    if v.is_boolean:
        return "true" if v.start else "false"
    return repr(v.start)


def _value(v: FmuVariable) -> list[str]:
    unit = [f"unit={quoteattr(v.unit)}"] if v.unit else []
    has_start = v.kind not in ("output", "independent")
    return unit + ([f'start="{_start(v)}"'] if has_start else [])


def _is_output(v: FmuVariable) -> bool:
    return v.kind == "output" or (v.kind in ("start", "guess", "boolean-start") and v.output)


def _initial_unknown(v: FmuVariable) -> bool:
    """Outputs computed in initialization (not those whose start value is exact)."""
    return _is_output(v) and v.kind not in ("start", "boolean-start")


def _header(exp: Mapping[str, Any], variables: Sequence[FmuVariable]) -> tuple[str, str, str]:
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    names = [("startTime", "StartTime"), ("stopTime", "StopTime"), ("tolerance", "Tolerance")]
    experiment = " ".join(f'{fmi}="{float(exp[ours])!r}"' for fmi, ours in names if ours in exp)
    units = "\n".join(
        f"    <Unit name={quoteattr(u)}/>" for u in sorted({v.unit for v in variables if v.unit})
    )
    return now, experiment, units


def fmi2(name: str, exp: Mapping[str, Any], variables: Sequence[FmuVariable], ident: str, guid: str) -> str:
    """FMI 2.0: ``ScalarVariable`` elements (``Real`` or ``Boolean``); the structure lists
    outputs by 1-based index."""
    now, experiment, units = _header(exp, variables)
    scalars = "\n".join(
        f'    <ScalarVariable name={quoteattr(v.name)} valueReference="{k}" {_attributes(v)}>\n'
        f"      <{'Boolean' if v.is_boolean else 'Real'} {' '.join(_value(v))}/>\n    </ScalarVariable>"
        for k, v in enumerate(variables)
    )
    outs = "\n".join(f'      <Unknown index="{k + 1}"/>' for k, v in enumerate(variables) if _is_output(v))
    unknowns = [f'      <Unknown index="{k + 1}"/>' for k, v in enumerate(variables) if _initial_unknown(v)]
    # the schema wants at least one Unknown in the element (every output may be exact)
    initial = "    <InitialUnknowns>\n" + "\n".join(unknowns) + "\n    </InitialUnknowns>" if unknowns else ""
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName={quoteattr(name)} guid="{guid}"
  generationTool="stiction {__version__}" generationDateAndTime="{now}"
  variableNamingConvention="structured" numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUstate="true" canSerializeFMUstate="true" canNotUseMemoryManagementFunctions="true"/>
  <UnitDefinitions>
{units}
  </UnitDefinitions>
  <DefaultExperiment {experiment}/>
  <ModelVariables>
{scalars}
  </ModelVariables>
  <ModelStructure>
    <Outputs>
{outs}
    </Outputs>
{initial}
  </ModelStructure>
</fmiModelDescription>
"""


def _fmi3_variable(k: int, v: FmuVariable) -> str:
    """A ``Float64`` or ``Boolean``; a table is a ``Float64`` array with its two dimensions."""
    element = "Boolean" if v.is_boolean else "Float64"
    head = (
        f'    <{element} name={quoteattr(v.name)} valueReference="{k}" {_attributes(v)} {" ".join(_value(v))}'
    )
    if v.shape is None:
        return head + "/>"
    dims = "".join(f'\n      <Dimension start="{n}"/>' for n in v.shape)
    return f"{head}>{dims}\n    </{element}>"


def fmi3(name: str, exp: Mapping[str, Any], variables: Sequence[FmuVariable], ident: str, token: str) -> str:
    """FMI 3.0: ``Float64`` and ``Boolean`` elements; the structure lists outputs by value
    reference."""
    now, experiment, units = _header(exp, variables)
    floats = "\n".join(_fmi3_variable(k, v) for k, v in enumerate(variables))
    structure = "\n".join(
        [f'    <Output valueReference="{k}"/>' for k, v in enumerate(variables) if _is_output(v)]
        + [
            f'    <InitialUnknown valueReference="{k}"/>'
            for k, v in enumerate(variables)
            if _initial_unknown(v)
        ]
    )
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName={quoteattr(name)} instantiationToken="{token}"
  generationTool="stiction {__version__}" generationDateAndTime="{now}"
  variableNamingConvention="structured">
  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"
    canGetAndSetFMUState="true" canSerializeFMUState="true"/>
  <UnitDefinitions>
{units}
  </UnitDefinitions>
  <DefaultExperiment {experiment}/>
  <ModelVariables>
{floats}
  </ModelVariables>
  <ModelStructure>
{structure}
  </ModelStructure>
</fmiModelDescription>
"""
