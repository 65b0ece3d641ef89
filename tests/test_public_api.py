"""What users import keeps importing after the package was split by job (issue 28): every
public name of ``stiction``, and every module path of the flat package of before, which is the
module at its new path (one object: a monkeypatch or a class check sees one module)."""

from __future__ import annotations

import importlib

import pytest

import stiction as st
from stiction._moved import MOVED


def test_every_public_name_imports() -> None:
    for name in st.__all__:
        assert getattr(st, name) is not None, name
    assert set(dir(st)) == {*st.__all__, "__version__"}


@pytest.mark.parametrize(("old", "new"), sorted(MOVED.items()))
def test_an_old_module_path_is_the_new_module(old: str, new: str) -> None:
    moved = importlib.import_module(f"stiction.{old}")
    assert moved is importlib.import_module(f"stiction.{new}")
    assert moved.__spec__ is not None and moved.__spec__.name == f"stiction.{new}"


def test_old_paths_users_wrote() -> None:
    from stiction.catalogue import catalogue
    from stiction.comparison import compare
    from stiction.result import Result, mode_name

    assert st.result.mode_name(0) == mode_name(0) == st.mode_name(0) == "stuck"
    assert Result is st.Result and compare is st.compare and "Brake" in catalogue()


def test_a_missing_optional_package_names_its_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    from stiction import _deps

    lazy = _deps._LazyModule("surely_not_installed_pkg", "parquet")
    with pytest.raises(ModuleNotFoundError, match=r"pip install 'stiction\[parquet\]'"):
        lazy.anything  # noqa: B018
