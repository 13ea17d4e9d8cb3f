"""``geomexact check``: validate a triangle mesh (exit 1 on violations)."""

from __future__ import annotations

import argparse

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_format_option,
    add_json_flag,
    add_verbose_flag,
)
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.loading import load_mesh
from geomexact.cli.reporting import print_json, violation_reports
from geomexact.validate import validate


def command_check(args: argparse.Namespace) -> int:
    """Validate a triangle mesh; exit 1 listing every violation."""
    mesh = load_mesh(args.file, args.format, args.verbose, "check")
    violations = validate(mesh, allow_isolated=not args.strict)
    if args.json:
        print_json(
            {
                "file": args.file,
                "valid": not violations,
                "vertices": mesh.vertex_count,
                "triangles": mesh.triangle_count,
                "violations": violation_reports(violations),
            }
        )
    elif violations:
        print(f"{args.file}: invalid, {len(violations)} violation(s)")
        for violation in violations:
            print(f"  {violation}")
    else:
        print(
            f"{args.file}: valid ({mesh.vertex_count} vertices, "
            f"{mesh.triangle_count} triangles, digest {mesh.digest_text})"
        )
    return EXIT_FAILED if violations else EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``check`` command."""
    check = add_command(commands, "check", command_check,
                        "validate a triangle mesh (exit 1 on violations)")
    check.add_argument("file", metavar="FILE", help="triangle mesh file")
    add_format_option(check)
    check.add_argument(
        "--strict",
        action="store_true",
        help="also report vertices in no triangle (isolated-vertex)",
    )
    add_json_flag(check)
    add_verbose_flag(check)
