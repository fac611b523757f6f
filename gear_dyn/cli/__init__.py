"""The ``gear-dyn`` command: :mod:`.main` (parser, exit codes) and one thin module per
subcommand (parse, call the API, write, print)."""

from gear_dyn.cli.app import build_parser, main

__all__ = ["build_parser", "main"]
