"""``geomexact polylla``: the Polylla polygon mesh of a triangle mesh, optionally
decomposed into convex polygons."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from geomexact.cli.arguments import (
    MESH_OR_PSLG,
    Subcommands,
    add_check_flag,
    add_command,
    add_input_argument,
    add_output_option,
    add_picture_option,
    add_writing_options,
)
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.kinds import wrong_kind
from geomexact.cli.loading import load
from geomexact.cli.reporting import print_json, print_table, violation_reports
from geomexact.cli.writing import distinct_outputs, write_output
from geomexact.errors import OverwriteError
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2


def command_polylla(args: argparse.Namespace) -> int:
    """Polylla polygon mesh of a triangle mesh (a PSLG is triangulated first), optionally
    decomposed into convex polygons; writes the polygons and optionally a picture."""
    from geomexact.mesh2d.polygonal.convex import convex_decomposition
    from geomexact.mesh2d.polygonal.polygon_mesh import mesh_stats, nonconvex_polygons
    from geomexact.mesh2d.polygonal.polylla_meshing import polylla_run

    loaded = load(args.input, args.format, args.verbose)
    if isinstance(loaded.value, PSLG):
        mesh = triangulate(loaded.value).mesh
    elif isinstance(loaded.value, Mesh2):
        mesh = loaded.value
    else:
        raise wrong_kind(args.input, loaded.value, "polylla",
                         "a triangle mesh (or a PSLG, which is triangulated first)")
    convex = args.convex or args.no_opt
    distinct_outputs([("-o", args.output, args.to), ("--picture", args.picture, "file")])
    for path in (args.output, args.picture):
        if path and Path(path).exists() and not args.force:
            raise OverwriteError(str(path))
    started = time.perf_counter()
    run = polylla_run(mesh)
    result = run.mesh
    inserted: tuple[tuple[int, int], ...] = ()
    nonconvex = -1
    if convex:
        decomposition = convex_decomposition(
            run.mesh, criterion_one=not args.no_opt, reflex=args.reflex,
            criterion_one_rule=args.criterion_one_rule, preset=args.preset,
        )
        result, inserted = decomposition.mesh, decomposition.inserted_edges
        nonconvex = decomposition.nonconvex_before  # by its reflex rule
    seconds = time.perf_counter() - started
    violations = result.validate(mesh) if args.check else []
    written = write_output(args, args.output, result, "polygon mesh")
    if args.picture:
        from geomexact.viz import pictures

        if Path(args.picture).suffix.lower() not in pictures.PICTURE_FORMATS:
            raise UsageProblem(f"{args.picture}: the picture must end in .png, .svg or .pdf")
        title = f"{Path(args.input).name}: {'convex ' if convex else ''}Polylla mesh"
        pictures.plot(result, args.picture, overwrite=args.force, title=title,
                      highlight_edges=inserted)
        written.append(Path(args.picture))
    if nonconvex < 0:
        nonconvex = len(nonconvex_polygons(run.mesh))
    report = {
        "input": args.input,
        "triangulated": isinstance(loaded.value, PSLG),
        "vertices": mesh.vertex_count,
        "triangles": mesh.triangle_count,
        "regions": run.regions,
        "barrier_tips": len(run.barrier_tips),
        "repair_edges": len(run.repair_edges),
        "polygons": len(run.mesh.polygons),
        "nonconvex": nonconvex,
        "convex_decomposition": convex,
        "criterion_one": convex and not args.no_opt,
        "inserted_edges": len(inserted) if convex else None,
        "polygons_after": len(result.polygons) if convex else None,
        "nonconvex_after": len(nonconvex_polygons(result)) if convex else None,
        "seconds": round(seconds, 6),
        "valid": not violations if args.check else None,
        "stats": mesh_stats(result, inserted_edges=len(inserted) if convex else None),
        "written": [str(path) for path in written],
    }
    if args.json:
        report["violations"] = violation_reports(violations)
        print_json(report)
    else:
        what = "Polylla + convex decomposition" if convex else "Polylla"
        rows = {key: value for key, value in report.items()
                if key not in {"input", "stats", "written", "seconds", "convex_decomposition"}
                and value is not None}
        print_table(f"{args.input}: {what} in {seconds:.3f} s", rows)
        for path in written:
            print(f"wrote {path}")
        for violation in violations:
            print(f"  {violation}")
    return EXIT_FAILED if violations else EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``polylla`` command."""
    polylla_ = add_command(commands, "polylla", command_polylla)
    add_input_argument(polylla_, MESH_OR_PSLG)
    add_output_option(polylla_, "polygon mesh file to write (e.g. OUT.off)")
    polylla_.add_argument("--convex", action="store_true",
                          help="split every polygon into convex ones by edges of the "
                               "triangulation")
    polylla_.add_argument("--no-opt", action="store_true",
                          help="convex decomposition without criterion 1 (angle-first mode; "
                               "implies --convex)")
    polylla_.add_argument("--preset", choices=("pineda", "pineda-thesis"),
                          help="--convex with Pineda's rules: pineda follows his program "
                               "(--criterion-one-rule first), pineda-thesis the thesis's "
                               "table (also --reflex straight)")
    polylla_.add_argument("--reflex", choices=("strict", "straight"), default="strict",
                          help="--convex: a reflex corner is above 180 degrees (default) or "
                               "also at exactly 180 (straight; Pineda, Alg. 10)")
    polylla_.add_argument("--criterion-one-rule", choices=("bisector", "first"),
                          default="bisector",
                          help="--convex: criterion 1 takes the edge closest to the "
                               "bisector in a first pass (default) or the first edge found, "
                               "corner by corner (Pineda, Alg. 11)")
    add_picture_option(polylla_, "draw the result (.png, .svg or .pdf; inserted edges in "
                       "orange, non-convex polygons filled)", metavar="PNG")
    add_check_flag(polylla_, "validate the polygons against the triangulation (exit 1 if "
                   "invalid)")
    add_writing_options(polylla_)
