"""The module paths of the flat package before it was split by job, kept importing.

``import stiction.result``, ``from stiction.catalogue import catalogue`` and
``st.result.mode_name`` keep working: each old name is the new module itself (the same object,
so a monkeypatch or an ``isinstance`` sees one module). New code imports the new paths.
"""

from __future__ import annotations

import importlib
import sys
from importlib.machinery import ModuleSpec
from types import ModuleType

__all__ = ["MOVED", "install"]

MOVED = {
    "audit": "results.audit",
    "bench": "cli.benchmarks",
    "catalogue": "model.catalogue",
    "cli_bench": "cli.bench",
    "cli_sweep": "cli.sweep",
    "comparison": "results.comparison",
    "compiled": "run.compiled",
    "components": "model.components",
    "csvio": "results.io.csv",
    "derived": "modelica.derived",
    "fmu_xml": "fmu.description",
    "modelfile": "model.modelfile",
    "parameters": "model.parameters",
    "plotting": "results.plotting",
    "result": "results.result",
    "resultio": "results.io.formats",
    "runinfo": "model.runinfo",
    "simulation": "run.simulation",
    "modelica.expr": "expressions.evaluate",
    "modelica.exprparse": "expressions.parser",
    "modelica.lexer": "expressions.lexer",
}


class _Alias:
    """Finds ``stiction.<old>`` and loads it as the module at its new path: a meta path finder
    and its loader (by protocol: ``importlib.abc`` would cost ``import stiction`` 11 ms)."""

    def find_spec(self, fullname: str, path: object, target: object = None) -> ModuleSpec | None:
        old = fullname.removeprefix("stiction.")
        if old == fullname or old not in MOVED:
            return None
        return ModuleSpec(fullname, self)

    def __init__(self) -> None:
        self._specs: dict[str, ModuleSpec | None] = {}

    def create_module(self, spec: ModuleSpec) -> ModuleType:
        module = importlib.import_module(f"stiction.{MOVED[spec.name.removeprefix('stiction.')]}")
        self._specs[module.__name__] = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        """Nothing to run (the module at the new path has run already); the import system has
        just given the module the alias's spec, so it gets its own back."""
        module.__spec__ = self._specs.pop(module.__name__)


def install() -> None:
    """Put the alias finder on ``sys.meta_path`` (once)."""
    if not any(isinstance(finder, _Alias) for finder in sys.meta_path):
        sys.meta_path.append(_Alias())
