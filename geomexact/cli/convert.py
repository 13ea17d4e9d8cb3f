"""``geomexact convert``: read a file in one format and write it in another."""

from __future__ import annotations

import argparse

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_writing_options,
    format_names,
)
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.loading import load
from geomexact.cli.reporting import print_json
from geomexact.cli.writing import refuse_existing, write


def command_convert(args: argparse.Namespace) -> int:
    """Read a file in one format and write it in another."""
    refuse_existing([("OUT", args.output, args.target_format)], force=args.force)
    loaded = load(args.input, args.source_format, args.verbose)
    written = write(
        args.output, loaded.value, args.target_format, overwrite=args.force, numbers=args.numbers
    )
    if args.json:
        print_json(
            {
                "input": args.input,
                "format": loaded.format,
                "kind": loaded.kind,
                "written": [str(path) for path in written],
            }
        )
    else:
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``convert`` command."""
    formats = format_names()
    names = ", ".join(formats)
    convert = add_command(commands, "convert", command_convert)
    convert.add_argument("input", metavar="IN", help="file to read")
    convert.add_argument("output", metavar="OUT", help="file to write")
    convert.add_argument(
        "--from", dest="source_format", choices=formats, metavar="F",
        help=f"format of IN, one of {names} (default: from its extension)",
    )
    convert.add_argument(
        "--to", dest="target_format", choices=formats, metavar="F",
        help=f"format of OUT, one of {names} (default: from its extension)",
    )
    add_writing_options(convert, formats=False)
