"""Modelica in and out: read MSL-style ``.mo`` models into a ``Model``, write them back.

``lexer`` → ``parser`` (syntax tree in ``ast``) → ``names`` (MSL catalogue and lookup) →
``convert`` (parameters, modifiers, connections, experiment) → ``Model``; ``export`` goes the
other way. Errors are ``ModelicaError`` (a ``ModelError``) starting with ``file:line:column``;
a file with several errors raises one listing them all, one a line (``errors``: each as
``(line, column, message)``).
"""

from __future__ import annotations

import gc
import os
from pathlib import Path
from typing import TYPE_CHECKING

from stiction.expressions.lexer import ModelicaError

if TYPE_CHECKING:
    from stiction.model.model import Model

__all__ = ["ModelicaError", "read_modelica"]


def read_modelica(source: str | os.PathLike[str], model: str | None = None) -> Model:
    """A ``Model`` from a ``.mo`` file path or Modelica text; ``model`` picks one class.
    Raises one ``ModelicaError`` listing every error of the file, sorted by place."""
    from stiction.modelica.convert import convert
    from stiction.modelica.parser import parse

    if isinstance(source, os.PathLike) or (
        isinstance(source, str) and "\n" not in source and source.strip().endswith(".mo")
    ):
        path = Path(source)
        text = path.read_text(encoding="utf-8")
        label, base_dir = str(path), str(path.resolve().parent)
    elif isinstance(source, str):
        text, label, base_dir = source, "<modelica>", "."
    else:
        raise TypeError(f"expected a path or Modelica text, got {type(source).__name__}")
    # Tree nodes are many small objects that all live until the end: the cyclic garbage
    # collector would scan them again and again.
    enabled = gc.isenabled()
    gc.disable()
    try:
        return convert(parse(text, label), model, label, base_dir)
    finally:
        if enabled:
            gc.enable()
