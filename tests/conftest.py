"""Shared fixtures. tests/ mirrors the package python/stiction, one folder per subpackage:

    expressions/  model/  results/  run/  sweeps/  modelica/  fmu/  cli/
    integration/  MSL examples against their references and an oracle, the tutorial, end to end
    properties/   Hypothesis: random drivetrains (``make soak`` runs 10⁴) and the .mo fuzzer
    tests/ itself: checks of the whole tree (layers, structure, the public names)

Shared data stays put: tests/data (models written for tests; data/msl: MSL reference results,
see data/msl/README.md) and tests/fmi (a C host for FMUs). Tests reach them, and the repository's
examples, through tests/paths.py (``from paths import DATA, MSL_DATA, EXAMPLES, ...``).

``make test-fast`` leaves out the tests marked ``@pytest.mark.slow`` (seconds each: 1000-element
models, the wheel build, the longest runs); ``make test`` runs everything.
"""

from __future__ import annotations

import pytest
from click.testing import CliRunner


@pytest.fixture
def cli_runner() -> CliRunner:
    """A click test runner that keeps stderr apart from stdout (click 8.1 and 8.2+)."""
    try:
        return CliRunner(mix_stderr=False)  # type: ignore[call-arg]  # click < 8.2
    except TypeError:
        return CliRunner()  # click >= 8.2 always keeps stderr apart
