"""The optional packages, loaded through this one module (as polars does).

``from stiction._deps import pandas as pd`` costs nothing: the name is a stand-in that imports
pandas on first use, so ``import stiction`` and a plain run never pay for pandas, Arrow,
matplotlib, Dask or pint. A package that is not installed raises ``ModuleNotFoundError`` naming the
extra that brings it (``pip install 'stiction[parquet]'``) at that first use. pint (quantities
with units, ``"20 kN"``) is a dependency, not an extra; it loads here too because its unit
registry costs a quarter of a second, paid only by a model that writes a unit. Everything else
of stiction imports these packages only here (``make lint`` checks it with import-linter);
type annotations may still import them under ``TYPE_CHECKING``.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

__all__ = [
    "backend_agg",
    "distributed",
    "figure",
    "lines",
    "matplotlib",
    "pandas",
    "parquet",
    "pint",
    "pyarrow",
    "pyplot",
    "scipy_optimize",
    "scipy_stats",
    "ticker",
    "tqdm_auto",
]


class _LazyModule(ModuleType):
    """A module imported on first attribute access; a missing one names its extra."""

    def __init__(self, name: str, extra: str | None) -> None:
        super().__init__(name)
        self._extra = extra
        self._module: ModuleType | None = None

    def _load(self) -> ModuleType:
        if self._module is None:
            try:
                self._module = importlib.import_module(self.__name__)
            except ModuleNotFoundError as exc:
                install = f"stiction[{self._extra}]" if self._extra else self.__name__
                raise ModuleNotFoundError(
                    f"{self.__name__} is needed for this: pip install '{install}'", name=exc.name
                ) from None
        return self._module

    def __getattr__(self, attr: str) -> Any:
        return getattr(self._load(), attr)

    def __dir__(self) -> list[str]:
        return dir(self._load())


pandas: Any = _LazyModule("pandas", "pandas")
pyarrow: Any = _LazyModule("pyarrow", "parquet")
parquet: Any = _LazyModule("pyarrow.parquet", "parquet")
pyplot: Any = _LazyModule("matplotlib.pyplot", "plot")
ticker: Any = _LazyModule("matplotlib.ticker", "plot")
figure: Any = _LazyModule("matplotlib.figure", "plot")
lines: Any = _LazyModule("matplotlib.lines", "plot")
matplotlib: Any = _LazyModule("matplotlib", "plot")
backend_agg: Any = _LazyModule("matplotlib.backends.backend_agg", "plot")
distributed: Any = _LazyModule("distributed", "dask")
tqdm_auto: Any = _LazyModule("tqdm.auto", "sweep")
scipy_optimize: Any = _LazyModule("scipy.optimize", "fit")
scipy_stats: Any = _LazyModule("scipy.stats", "fit")
pint: Any = _LazyModule("pint", None)  # a dependency: a missing one is a broken install
