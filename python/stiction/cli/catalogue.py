"""``stiction list`` and ``describe``: the component types, their parameters, ports and variables."""

from __future__ import annotations

import click

from stiction.cli.options import friendly_errors


@click.command(name="list")
@friendly_errors
def list_cmd() -> None:
    """List every component type with its MSL class and description."""
    from stiction.model.catalogue import catalogue

    known = catalogue()
    width = max(len(n) for n in known)
    for info in known.values():
        click.echo(f"{info.name:<{width}}  {info.description} ({info.msl_class})")


@click.command()
@click.argument("type_name")
@friendly_errors
def describe(type_name: str) -> None:
    """Show TYPE_NAME's parameters (default, unit, range), ports and variables."""
    from stiction.model.catalogue import describe as describe_type

    click.echo(str(describe_type(type_name)))
