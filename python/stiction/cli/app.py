"""The ``stiction`` command: simulate, check, compare against references, convert, sweep, fit,
dyno, benchmark; one module per command, added to the group here.

User mistakes (a bad model, a missing file, malformed TOML) and engine failures end in
one ``error: …`` line on stderr and exit code 2, never a traceback; a failed comparison
exits with 1.
"""

from __future__ import annotations

import click

from stiction.cli import bench, catalogue, check, compare, convert, dyno, fit, simulate, sweep

__all__ = ["main"]


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="stiction", prog_name="stiction", message="%(prog)s %(version)s")
def main() -> None:
    """Simulate rotational drivetrains with exact Coulomb friction (MSL semantics)."""


for _command in (
    simulate.simulate,
    convert.import_cmd,
    convert.export_cmd,
    convert.fmu,
    check.check,
    catalogue.list_cmd,
    catalogue.describe,
    compare.compare_cmd,
    sweep.sweep_cmd,
    fit.fit_cmd,
    dyno.dyno_cmd,
    bench.bench,
):
    main.add_command(_command)
