"""The translational components (``Modelica.Mechanics.Translational``), one class per engine
type ``Translational.X``: ``st.translational.Mass(m=400.0)`` is
``st.Component("Translational.Mass", {"m": 400.0})``; in a TOML model the type stays
``Translational.Mass``. Made from the engine's catalogue on first import (``import stiction``
does not load this module); ``translational.pyi`` lists them for IDEs.
"""

from __future__ import annotations

from stiction.model.components import namespace_classes

_CLASSES = namespace_classes("Translational")
globals().update(_CLASSES)

__all__ = sorted(_CLASSES)  # noqa: PLE0605  # made from the catalogue
