"""``python -m stiction``: the same command line as ``stiction``."""

from .cli import main

main(prog_name="stiction")
