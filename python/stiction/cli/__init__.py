"""The command line, ``stiction``: ``main`` (the group and the shared options) and one
module per command."""

from stiction.cli.app import main

__all__ = ["main"]
