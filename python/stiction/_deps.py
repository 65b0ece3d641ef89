"""The optional packages, loaded through this one module (as polars does).

``from stiction._deps import pandas as pd`` costs nothing: the name is a stand-in that imports
pandas on first use, so ``import stiction`` and a plain run never pay for pandas, Arrow,
matplotlib or Dask. A package that is not installed raises ``ModuleNotFoundError`` naming the
extra that brings it (``pip install 'stiction[parquet]'``) at that first use. Everything else
of stiction imports these packages only here (``make lint`` checks it with import-linter);
type annotations may still import them under ``TYPE_CHECKING``.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

__all__ = ["distributed", "figure", "pandas", "parquet", "pyarrow", "pyplot", "ticker", "tqdm_auto"]


class _LazyModule(ModuleType):
    """A module imported on first attribute access; a missing one names its extra."""

    def __init__(self, name: str, extra: str) -> None:
        super().__init__(name)
        self._extra = extra
        self._module: ModuleType | None = None

    def _load(self) -> ModuleType:
        if self._module is None:
            try:
                self._module = importlib.import_module(self.__name__)
            except ModuleNotFoundError as exc:
                raise ModuleNotFoundError(
                    f"{self.__name__} is needed for this: pip install 'stiction[{self._extra}]'",
                    name=exc.name,
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
distributed: Any = _LazyModule("distributed", "dask")
tqdm_auto: Any = _LazyModule("tqdm.auto", "sweep")
