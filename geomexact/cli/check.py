"""``geomexact check``: validate a triangle or polygon mesh (exit 1 on violations)."""

from __future__ import annotations

import argparse

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_format_option,
    add_json_flag,
    add_verbose_flag,
)
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.loading import load
from geomexact.cli.reporting import print_json, violation_reports
from geomexact.mesh2d.polygonal.polygon_mesh import (
    PolygonMesh,
    isolated_polygon_vertices,
    validate_polygon_mesh,
)
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.validation import validate


def command_check(args: argparse.Namespace) -> int:
    """Validate a triangle mesh (:func:`geomexact.mesh2d.validation`) or a polygon mesh
    (:func:`geomexact.mesh2d.polygonal.polygon_mesh.validate_polygon_mesh`, with its geometric
    checks); exit 1
    listing every violation."""
    loaded = load(args.file, args.format, args.verbose)
    value = loaded.value
    if isinstance(value, Mesh2):
        violations = validate(value, allow_isolated=not args.strict)
        counts = {"vertices": value.vertex_count, "triangles": value.triangle_count}
        digest = f", digest {value.digest_text}"
    elif isinstance(value, PolygonMesh):
        violations = validate_polygon_mesh(value, geometric=True)
        if args.strict:
            violations.extend(isolated_polygon_vertices(value))
        counts = {"vertices": len(value.vertices), "polygons": len(value.polygons)}
        digest = ""
    else:
        raise UsageProblem(
            f"{args.file}: is a {loaded.kind.replace('_', ' ')}, but check needs a triangle mesh "
            "or a polygon mesh (a Triangle .ele, OFF, or PSLG text file of triangles, …)"
        )
    if args.json:
        print_json(
            {
                "file": args.file,
                "kind": loaded.kind,
                "valid": not violations,
                **counts,
                "violations": violation_reports(violations),
            }
        )
    elif violations:
        print(f"{args.file}: invalid, {len(violations)} violation(s)")
        for violation in violations:
            print(f"  {violation}")
    else:
        listed = ", ".join(f"{count} {name}" for name, count in counts.items())
        print(f"{args.file}: valid ({listed}{digest})")
    return EXIT_FAILED if violations else EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``check`` command."""
    check = add_command(commands, "check", command_check,
                        "validate a triangle or polygon mesh (exit 1 on violations)")
    check.add_argument("file", metavar="FILE", help="triangle or polygon mesh file")
    add_format_option(check)
    check.add_argument(
        "--strict",
        action="store_true",
        help="also report vertices in no triangle or polygon (isolated-vertex)",
    )
    add_json_flag(check)
    add_verbose_flag(check)
