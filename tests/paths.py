"""Where the tests find the repository, its examples and the shared test data.

Tests reach files through these names, never through their own location (``__file__``), so a
test file can move between the folders of tests/ without an edit. ``tests`` is on the import
path (pyproject.toml: ``[tool.pytest.ini_options] pythonpath``): ``from paths import DATA``.
"""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parent
REPO = TESTS.parent
DATA = TESTS / "data"  # models written for the tests (see data/msl/README.md for msl/)
MSL_DATA = DATA / "msl"  # MAP-LIB reference trajectories and MSL's signal lists
FMI_HARNESS = TESTS / "fmi" / "harness.c"  # a C host for the FMU runtime
EXAMPLES = REPO / "examples"
MSL_EXAMPLES = EXAMPLES / "msl"

# examples/msl/*.mo files (MSL's genuine structure) that need a component still being built
# (issue 30): the tests skip them with this reason; the coordinator removes an entry when the
# component is merged. Shared by every test that globs the shipped .mo files.
AWAITING_COMPONENTS = {}
