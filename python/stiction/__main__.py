"""``python -m stiction``: the same command line as ``stiction``."""

from stiction.cli.app import main

main(prog_name="stiction")
