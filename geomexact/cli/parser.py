"""The ``geomexact`` argument parser, assembled from each command's ``add_parser``."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from typing import NoReturn, cast

from geomexact import __version__
from geomexact.cli import (
    check,
    convert,
    demo,
    info,
    polylla,
    refine,
    replay,
    serve,
    triangulate,
    view,
)
from geomexact.cli.arguments import Subcommands
from geomexact.cli.exit_codes import EXIT_BAD_INPUT, EXIT_CODES_HELP

COMMANDS: tuple[Callable[[Subcommands], None], ...] = (
    info.add_parser,
    check.add_parser,
    convert.add_parser,
    replay.add_parser,
    triangulate.add_parser,
    polylla.add_parser,
    refine.add_parser,
    view.add_parser,
    serve.add_parser,
    demo.add_parser,
)
"""Each command's ``add_parser``, in the order ``geomexact --help`` lists them."""


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors name the program as ``geomexact: error:``."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The ``geomexact`` argument parser."""
    parser = _Parser(
        prog="geomexact",
        description="Exact, replayable mesh refinement on rational coordinates.",
        epilog=EXIT_CODES_HELP + "\nSee docs/cli.md for every command, option and JSON key.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"geomexact {__version__}")
    commands = cast(  # its subparsers are _Parser instances, so ArgumentParsers
        Subcommands, parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    )
    for add_parser in COMMANDS:
        add_parser(commands)
    return parser
