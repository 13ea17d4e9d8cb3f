"""``geomexact info``: statistics of meshes, PSLGs and polygon meshes."""

from __future__ import annotations

import argparse
from typing import Any

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_format_option,
    add_json_flag,
    add_verbose_flag,
)
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.loading import Loaded, load
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.summaries import summary_of


def _describe(loaded: Loaded) -> dict[str, Any]:
    return {
        "file": loaded.path,
        "format": loaded.format,
        "kind": loaded.kind,
        **summary_of(loaded.value),
        "notes": list(loaded.notes),
    }


def command_info(args: argparse.Namespace) -> int:
    """Statistics of each file."""
    reports = [_describe(load(path, args.format, args.verbose)) for path in args.files]
    if args.json:
        print_json(reports[0] if len(reports) == 1 else {"files": reports})
        return EXIT_OK
    for index, report in enumerate(reports):
        if index:
            print()
        rows = {k: v for k, v in report.items() if k not in {"file", "format", "kind", "notes"}}
        kind = report["kind"].replace("_", " ")
        print_table(f"{report['file']} ({report['format']}, {kind})", rows)
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``info`` command."""
    info = add_command(commands, "info", command_info,
                       "print statistics of meshes, PSLGs and polygon meshes")
    info.add_argument("files", nargs="+", metavar="FILE", help="mesh, PSLG or polygon mesh file")
    add_format_option(info)
    add_json_flag(info)
    add_verbose_flag(info)
