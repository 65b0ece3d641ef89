"""The Python package's layers (.importlinter, run by `make lint`) hold, and the check catches
a wrong import: an upward one, and an optional package imported past ``stiction._deps``."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "stiction"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")

pytestmark = pytest.mark.skipif(not LINT_IMPORTS.exists(), reason="import-linter is not installed")


def lint_imports(source_root: Path) -> subprocess.CompletedProcess[str]:
    """`lint-imports` with the project's contracts over the package found in ``source_root``."""
    env = {**os.environ, "PYTHONPATH": str(source_root)}
    return subprocess.run(
        [str(LINT_IMPORTS), "--config", str(ROOT / ".importlinter"), "--no-cache"],
        cwd=source_root,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )


def package_copy(tmp_path: Path) -> Path:
    """The package's Python sources in ``tmp_path/stiction`` (no compiled module: the check
    reads the source text)."""
    shutil.copytree(PACKAGE, tmp_path / "stiction", ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    return tmp_path


def add_line(path: Path, line: str) -> None:
    """Put ``line`` right after the ``from __future__`` import of ``path``."""
    text = path.read_text()
    marker = "from __future__ import annotations\n"
    assert marker in text
    path.write_text(text.replace(marker, marker + line + "\n", 1))


def test_the_package_keeps_its_layers() -> None:
    run = lint_imports(PACKAGE.parent)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "2 kept, 0 broken" in run.stdout


def test_an_upward_import_breaks_the_layers(tmp_path: Path) -> None:
    root = package_copy(tmp_path)
    add_line(root / "stiction" / "expressions" / "lexer.py", "import stiction.run.compiled")
    run = lint_imports(root)
    assert run.returncode == 1
    assert "stiction.expressions.lexer -> stiction.run.compiled" in run.stdout


def test_an_optional_package_outside_deps_is_refused(tmp_path: Path) -> None:
    root = package_copy(tmp_path)
    add_line(root / "stiction" / "results" / "result.py", "import pandas")
    run = lint_imports(root)
    assert run.returncode == 1
    assert "stiction.results.result -> pandas" in run.stdout
