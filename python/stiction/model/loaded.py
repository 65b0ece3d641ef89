"""A model file loaded as it stands: compiled by the engine, its Python objects made when
first touched.

Loading a file used to build a ``Component`` per component and check each connection in
Python, and to fingerprint the result, before the engine compiled the same text: a ladder of
100 inertias spent 3 ms of its 20 there, for a model run unchanged. A *plain* file (numbers
and Booleans for parameters, nothing but ``name``, ``connect``, ``experiment`` and
``components``, nothing the Python checks refuse where the engine does not; see
``_core.load_model``) is compiled at load instead, which checks it as fully:
the ``Model`` holds the compile and the text, and its components, connections and the rest
are made from the text the first time any of them is read (``Model.__getattr__``). A file
that is not plain, or that the engine refuses, is built in Python at load as before, and
its errors are Python's.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stiction.model import modelfile

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["LAZY_FIELDS", "LoadedFile", "load_file", "named_text"]

# The attributes of a ``Model`` made from the file when first read; the others (name,
# base_dir, the caches) are set at load.
LAZY_FIELDS = frozenset(
    (
        "components",
        "connections",
        "_pairs",
        "_paths",
        "experiment",
        "inputs",
        "variables",
        "parameters",
        "declarations",
    )
)


class Compiled:
    """An engine compile at hand, as ``CompiledModel`` takes a ``Precompiled`` one."""

    __slots__ = ("_core",)

    def __init__(self, core: Any) -> None:
        self._core = core

    def result(self) -> Any:
        """The compile (None once taken: a second taker compiles the text itself)."""
        core, self._core = self._core, None
        return core


class LoadedFile:
    """What a lazily loaded ``Model`` holds of its file until its objects are made."""

    __slots__ = ("_data", "counts", "default_name", "engine_text", "name", "source", "text")

    def __init__(
        self, text: str, engine_text: str, name: str, source: str, default_name: str, counts: tuple[int, int]
    ) -> None:
        self.text = text  # the file as read
        self.engine_text = engine_text  # what the engine compiled: the file, named
        self.name = name
        self.source = source
        self.default_name = default_name
        self.counts = counts  # components, connections
        self._data: modelfile.ModelData | None = None

    def data(self) -> modelfile.ModelData:
        """The file's content as Python data (parsed the first time it is asked for)."""
        if self._data is None:
            self._data = modelfile.parse(self.text, self.source)
        return self._data

    def types(self) -> dict[str, str]:
        """Component name → type name, as ``Model.types`` gives them."""
        return {name: kind for name, kind, _ in self.data().components}

    def parameter_values(self) -> dict[str, float]:
        """The file's scalar parameters by ``component.parameter``, as
        ``Model.parameter_values`` gives them (a plain file has no top-level ones)."""
        from stiction.model.model import parameter_values

        return parameter_values({}, {name: params for name, _, params in self.data().components})


def load_file(
    cls: type[Model], text: str, base_dir: str | os.PathLike[str], source: str, default_name: str
) -> tuple[Model | None, dict[str, Any] | None, Any]:
    """Model-file ``text`` parsed once (``_core.load_model``): a plain file compiled now, as a
    ``cls`` whose objects are made when first read; for any other file (or one the engine
    refuses), no model but the TOML document and the engine's reading of it for a compile
    (None for text the engine does not read, or without the compiled engine: the caller's
    ``modelfile.parse`` then parses and reports)."""
    try:
        from stiction import _core
    except ImportError:  # the pure-Python package
        return None, None, None
    folder = Path(base_dir)
    plain, doc, parsed = _core.load_model(text, str(folder), default_name)
    if plain is None:
        return None, doc, parsed
    own, n_components, n_connections, core = plain
    name = own or default_name
    engine_text = text if own is not None else named_text(name, text)
    model = cls.__new__(cls)
    model.name = name
    model.base_dir = folder
    model._compiled = None
    model._parsed = (engine_text, str(folder), Compiled(core))
    model._derived = None
    model._lazy = LoadedFile(text, engine_text, name, source, default_name, (n_components, n_connections))
    return model, None, None


def named_text(name: str, text: str) -> str:
    """Model-file ``text`` that names no model, named ``name`` (the engine text of a file)."""
    return f"name = {modelfile.dumps_scalar(name)}\n{text}"
