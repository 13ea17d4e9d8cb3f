"""``geomexact check``: validate a triangle, tetrahedral, mixed-cell or polygon mesh, or a
PSLG (exit 1 on violations)."""

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
from geomexact.cli.errors import UsageProblem, cli_wording, print_warning
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.info import materials_report, print_materials
from geomexact.cli.loading import (
    Loaded,
    load,
    seed_warnings,
    surface_instead,
    triangulation_problems,
)
from geomexact.cli.reporting import print_json, violation_reports
from geomexact.errors import FormatError, PreconditionError, Violation
from geomexact.mesh2d.polygonal.polygon_mesh import (
    PolygonMesh,
    isolated_polygon_vertices,
    validate_polygon_mesh,
)
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.validation import validate
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

_LISTED = 10
"""At most this many vertices are named in a note."""


def _check_surface(args: argparse.Namespace, surface: Any) -> int:
    """``check`` of a triangulated surface (a 3D OBJ, STL, PLY, OFF): the exact checks a
    domain's surface must pass (:func:`~geomexact.mesh3d.surface.checks.surface_problems`);
    exit 1 listing every problem."""
    from geomexact.mesh3d.surface.checks import surface_problems

    violations = surface_problems(surface)
    if args.json:
        print_json({"file": args.file, "kind": "triangle_surface", "valid": not violations,
                    "vertices": surface.vertex_count, "triangles": surface.triangle_count,
                    "violations": violation_reports(violations), "warnings": []})
    elif violations:
        print(f"{args.file}: not the surface of a domain, {len(violations)} problem(s)")
        for violation in violations[:20]:
            print(f"  {violation}")
        if len(violations) > 20:
            print(f"  … and {len(violations) - 20} more (--json lists them all)")
    else:
        print(f"{args.file}: valid ({surface.vertex_count} vertices, "
              f"{surface.triangle_count} triangles: closed, manifold, oriented outward, not "
              "self-intersecting)")
    return EXIT_FAILED if violations else EXIT_OK


def command_check(args: argparse.Namespace) -> int:
    """Validate a triangle mesh (:func:`geomexact.mesh2d.validation`), a tetrahedral or
    mixed-cell mesh (``validate3``, ``validate_mixed``), a polygon mesh
    (:func:`geomexact.mesh2d.polygonal.polygon_mesh.validate_polygon_mesh`, with its geometric
    checks) or a PSLG (:func:`pslg_violations`); exit 1 listing every violation."""
    try:
        loaded = load(args.file, args.format, args.verbose)
    except (FormatError, UsageProblem) as error:
        surface = surface_instead(args.file, args.format, error)
        if surface is None:
            raise
        return _check_surface(args, surface)
    value = loaded.value
    warnings: list[str] = []
    counts: dict[str, int | dict[str, int]]
    if isinstance(value, Mesh2):
        violations = validate(value, allow_isolated=not args.strict)
        counts = {"vertices": value.vertex_count, "triangles": value.triangle_count}
        digest = f", digest {value.digest_text}"
    elif isinstance(value, Mesh3):
        # imported here, as each kind's checks: the 3D ones run on arrays (NumPy)
        from geomexact.mesh3d.validation import isolated_vertices3, validate3

        violations = validate3(value)
        isolated = isolated_vertices3(value)
        if args.strict:
            violations.extend(isolated)
        elif isolated:  # legal, but worth a word
            warnings.append(isolated_note([v.elements[0] for v in isolated], "tetrahedron"))
            print_warning(f"{args.file}: {warnings[-1]}")
        counts = {"vertices": value.vertex_count, "tetrahedra": value.tetrahedron_count}
        digest = f", digest {value.digest_text}"
    elif isinstance(value, MixedMesh3):
        from geomexact.cli.summaries import cells_by_kind
        from geomexact.mesh3d.mixed.validation import validate_mixed

        violations = validate_mixed(value)
        used = {vertex for cell in value.cell_list() for vertex in cell.vertices}
        unused = [v for v in range(value.vertex_count) if v not in used]
        if args.strict:
            violations.extend(Violation("isolated-vertex", f"vertex {v} is in no cell", (v,))
                              for v in unused)
        elif unused:  # legal, but worth a word
            warnings.append(isolated_note(unused, "cell"))
            print_warning(f"{args.file}: {warnings[-1]}")
        counts = {"vertices": value.vertex_count, "cells": value.cell_count,
                  "cells_by_kind": cells_by_kind(value)}
        digest = f", digest {value.digest_text}"
    elif isinstance(value, PolygonMesh):
        violations = validate_polygon_mesh(value, geometric=True)
        if args.strict:
            violations.extend(isolated_polygon_vertices(value))
        counts = {"vertices": len(value.vertices), "polygons": len(value.polygons)}
        digest = ""
    elif isinstance(value, PSLG):
        violations, warnings = pslg_violations(loaded, strict=args.strict)
        counts = {"vertices": len(value.vertices), "segments": len(value.segments),
                  "holes": len(value.holes), "regions": len(value.regions)}
        digest = ""
        for warning in warnings if not args.strict else ():  # strict: they are violations
            print_warning(warning)
    else:
        raise UsageProblem(
            f"{args.file}: is a {loaded.kind.replace('_', ' ')}, but check needs a triangle, "
            "tetrahedral or polygon mesh or a PSLG"
        )
    materials = materials_report(loaded)
    if args.json:
        print_json(
            {
                "file": args.file,
                "kind": loaded.kind,
                "valid": not violations,
                **counts,
                **materials,
                "violations": violation_reports(violations),
                "warnings": warnings,
            }
        )
    elif violations:
        print(f"{args.file}: invalid, {len(violations)} violation(s)")
        for violation in violations:
            print(f"  {violation}")
    else:
        listed = ", ".join(
            f"{count} {name}" if not isinstance(count, dict) else
            f"{', '.join(f'{number} {kind}' for kind, number in count.items())}"
            for name, count in counts.items())
        print(f"{args.file}: valid ({listed}{digest})")
        print_materials(materials)
    return EXIT_FAILED if violations else EXIT_OK


def isolated_note(vertices: list[int], cell: str) -> str:
    """The note on vertices in no ``cell``: how many, and the first :data:`_LISTED`."""
    shown = ", ".join(map(str, vertices[:_LISTED]))
    more = f" and {len(vertices) - _LISTED} more" if len(vertices) > _LISTED else ""
    if len(vertices) == 1:
        return f"vertex {shown} is in no {cell} (unused; --strict makes it a violation)"
    return (f"{len(vertices)} vertices are in no {cell}: {shown}{more} (unused; --strict "
            "makes them violations)")


def pslg_violations(loaded: Loaded, *, strict: bool) -> tuple[list[Violation], list[str]]:
    """What ``triangulate`` would refuse in the PSLG of ``loaded`` (crossing segments,
    segments through vertices, duplicate or collinear points: violations naming each
    item's file and line) and the hole and region seeds it would ignore (warnings, and
    violations too when ``strict``).  Seeds are checked on the triangulation that splits
    segments and merges duplicates when the plain one is refused."""
    from geomexact.mesh2d.delaunay.triangulation import triangulate

    pslg = loaded.value
    assert isinstance(pslg, PSLG)
    violations: list[Violation] = []
    construction = None
    for lenient in (False, True):
        try:
            construction = triangulate(pslg, split_segments=lenient, merge_duplicates=lenient)
            break
        except PreconditionError as error:
            if lenient:
                break  # still refused (e.g. collinear): the first refusal says why
            found = triangulation_problems(error, loaded)
            if found is None:
                violations.append(Violation("triangulation", cli_wording(str(error))))
                continue
            kind, _, items = found
            violations.extend(Violation(kind, item) for item in items)
    warnings = seed_warnings(loaded, construction) if construction is not None else []
    if strict:
        violations.extend(Violation("ignored-seed", warning) for warning in warnings)
    return violations, warnings


def add_parser(commands: Subcommands) -> None:
    """Add the ``check`` command."""
    check = add_command(commands, "check", command_check)
    check.add_argument("file", metavar="FILE",
                       help="triangle, tetrahedral, mixed-cell or polygon mesh or PSLG file")
    add_format_option(check)
    check.add_argument(
        "--strict",
        action="store_true",
        help="also report vertices in no triangle, tetrahedron, cell or polygon "
             "(isolated-vertex; for a 3D mesh, a warning without it), and a "
             "PSLG's hole or region seeds that lie in no triangle (ignored-seed)",
    )
    add_json_flag(check)
    add_verbose_flag(check)
