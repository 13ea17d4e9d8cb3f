"""``geomexact cuboid``: the partition of one 1-irregular cuboid pattern into
tetrahedra, optionally improved by Joe's flips, or its mixed or polyhedral cells
(``--final``); reports it and can write its trace."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from geomexact import io
from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_run_outputs,
)
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.provenance import with_provenance
from geomexact.cli.reporting import print_json, print_table, violation_reports
from geomexact.cli.writing import check_outputs, distinct_outputs, write
from geomexact.io.registry import NumberStyle, nearest_double_text
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents
from geomexact.mesh3d.cuboid.numbering import FACE_NAMES, PATTERN_COUNT
from geomexact.mesh3d.cuboid.partition import point_label
from geomexact.mesh3d.cuboid.split_order import ORDERS
from geomexact.mesh3d.snapshot import Mesh3

CELL_FINALS = ("mixed", "polyhedral")
"""The ``--final`` choices that make cells other than tetrahedra (cuboid and octree)."""


def pattern_argument(text: str) -> int:
    """A pattern: an integer 0 .. 2**18 - 1 (decimal, or 0x… / 0b…)."""
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if not 0 <= value < PATTERN_COUNT:
        raise argparse.ArgumentTypeError(f"{value} is outside 0..{PATTERN_COUNT - 1}")
    return value


def rational_argument(text: str) -> Any:
    """An exact positive number (``2``, ``0.5``, ``1/3``)."""
    try:
        value = parse_rational(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"{text} is not positive")
    return value


def shape_box(args: argparse.Namespace) -> Box:
    """The box [0, X] x [0, Y] x [0, Z] of ``--shape X Y Z``."""
    x, y, z = args.shape
    return box_of_extents(x, y, z)


def add_cuboid_options(sub: argparse.ArgumentParser) -> None:
    """``--shape``, ``--order``, ``--template``, ``--improve``, ``--allow-boundary-flips``."""
    sub.add_argument("--shape", nargs=3, type=rational_argument, metavar=("X", "Y", "Z"),
                     default=[parse_rational("1")] * 3,
                     help="the box [0,X]x[0,Y]x[0,Z], exact (default: the unit cube)")
    sub.add_argument("--order", choices=ORDERS, default="conforming",
                     help="split order: face centres first, then edge midpoints, each by "
                     "exact coordinates (conforming, the default), or by bit number (index)")
    sub.add_argument("--template", type=int, choices=(0, 1), default=0,
                     help="the 5-tetrahedron template: central tetrahedron on corners "
                     "0,3,5,6 (0, the default) or 1,2,4,7 (1)")
    sub.add_argument("--improve", action="store_true",
                     help="improve the partition toward Delaunay by Joe's flips")
    sub.add_argument("--allow-boundary-flips", action="store_true",
                     help="let the improvement flip T22 (changes the box's boundary)")


def add_final_option(sub: argparse.ArgumentParser, help: str) -> None:
    """``--final`` (``args.final``): what the cuboids become, ``patterns`` (the default),
    ``delaunay`` or one of :data:`CELL_FINALS`; ``help`` says it for the command."""
    sub.add_argument("--final", choices=("patterns", "delaunay", *CELL_FINALS),
                     default="patterns", help=help)


def _configurations(mesh: Mesh3) -> dict[str, dict[str, int]]:
    from geomexact.mesh3d.cuboid.census import configuration_counts

    return {kind: {"total": total, "failing": failing}
            for kind, (total, failing) in configuration_counts(mesh).items()}


def command_cuboid(args: argparse.Namespace) -> int:
    """Partition one pattern (optionally improve it), report it, write its trace."""
    if args.final in CELL_FINALS:
        return _cuboid_cells(args)
    if args.final == "delaunay":
        args.improve = True
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.cuboid.partition import partition_cuboid
    from geomexact.mesh3d.measures import is_delaunay3, total_volume
    from geomexact.mesh3d.validation import validate3

    box = shape_box(args)
    check_outputs([("-o", args.output, args.to), ("--start", args.start, None),
                   ("--trace", args.trace, "file")], Mesh3, force=args.force)
    start_numbers = _start_numbers(args.start, box)
    run = partition_cuboid(args.pattern, box, order=args.order, template=args.template,
                           improve=args.improve,
                           allow_boundary_flips=args.allow_boundary_flips)
    mesh = run.mesh
    violations = validate3(mesh, volume=box.volume)
    faces = {FACE_NAMES[bit - 12]: [[point_label(code) for code in triangle]
                                    for triangle in triangles]
             for bit, triangles in run.face_triangulations().items()}
    report = run.improvement
    report_json: dict[str, Any] = {
        "pattern": args.pattern,
        "bits": [bit for bit, _ in sorted(run.steiner)],
        "shape": box.describe(),
        "order": run.order,
        "template": run.template,
        "split_order": [bit for bit, _ in run.steiner],
        "tetrahedra": mesh.tetrahedron_count,
        "tetrahedra_partition": run.partition.tetrahedron_count,
        "vertices": mesh.vertex_count,
        "volume": format_rational(total_volume(mesh)),
        "valid": not violations,
        "delaunay": is_delaunay3(mesh),
        "delaunay_partition": is_delaunay3(run.partition),
        "flips": None if report is None else {
            **{name: report.flips_of(name) for name in ("flip23", "flip32", "flip22",
                                                        "flip44")},
            "total": report.flip_count, "rounds": report.rounds},
        "failing_kinds": None if report is None else list(report.failing_kinds),
        "cells": _cells(mesh),
        "configurations": _configurations(mesh),
        "configurations_partition": _configurations(run.partition),
        "faces": faces,
        "steps": len(run.trace),
        "digest": mesh.digest_text,
        "start_digest": run.start.digest_text,
        "trace": args.trace,
        "written": [],
    }
    written: list[Path] = []
    if args.start:
        written += write(args.start, run.start, None, overwrite=args.force,
                         numbers=start_numbers)
    if args.output:
        written += write(args.output, mesh, args.to, overwrite=args.force,
                         numbers=args.numbers)
    if args.trace:
        # the trace names the file it replays on (the cuboid command runs the reference)
        trace = with_provenance(run.trace, args, engine="reference", input_path=args.start)
        write_trace(args.trace, trace, overwrite=args.force)
        written.append(Path(args.trace))
    report_json["written"] = [str(path) for path in written]
    if args.json:
        report_json["violations"] = violation_reports(violations)
        print_json(report_json)
    else:
        _print_text(report_json)
        for violation in violations:
            print(f"  {violation}")
    return EXIT_FAILED if violations else EXIT_OK


def _cuboid_cells(args: argparse.Namespace) -> int:
    """``--final mixed|polyhedral``: the pattern's cell template on the box, validated
    exactly, reported and written (the start: the cuboid's points, as tetrahedral mesh
    files of vertices only)."""
    from geomexact.cli.summaries import cells_by_kind
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.cuboid.cell_templates import cuboid_cells
    from geomexact.mesh3d.mixed.snapshot import MixedMesh3
    from geomexact.mesh3d.mixed.validation import validate_mixed
    from geomexact.mesh3d.transient import mesh3_from_positive_arrays

    if args.improve or args.allow_boundary_flips:
        raise UsageProblem(f"--final {args.final} makes cells, not tetrahedra: --improve "
                           "and --allow-boundary-flips apply to --final patterns|delaunay")
    box = shape_box(args)
    outputs = [("-o", args.output, args.to), ("--start", args.start, None),
               ("--trace", args.trace, "file")]
    distinct_outputs(outputs)
    check_outputs(outputs[:1], MixedMesh3, force=args.force)
    check_outputs(outputs[1:], Mesh3, force=args.force)
    start_numbers = _start_numbers(args.start, box)
    parameters = {"algorithm": "cuboid", "final": args.final, "pattern": args.pattern,
                  "box": {"low": [format_rational(v) for v in box.low],
                          "high": [format_rational(v) for v in box.high]}}
    run = cuboid_cells(args.pattern, box, args.final, trace=bool(args.trace or args.start),
                       parameters=parameters)
    mesh = run.mesh
    violations = validate_mixed(mesh, volume=box.volume)
    written: list[Path] = []
    if args.start:
        start = run.start
        vertices = mesh3_from_positive_arrays(
            [start.point(vertex) for vertex in range(start.vertex_count)], ())
        written += write(args.start, vertices, None, overwrite=args.force,
                         numbers=start_numbers)
    if args.output:
        written += write(args.output, mesh, args.to, overwrite=args.force,
                         numbers=args.numbers)
    if args.trace and run.trace is not None:
        trace = with_provenance(run.trace, args, engine="reference", input_path=args.start)
        write_trace(args.trace, trace, overwrite=args.force)
        written.append(Path(args.trace))
    report: dict[str, Any] = {
        "pattern": args.pattern,
        "bits": [bit for bit in range(18) if args.pattern >> bit & 1],
        "shape": box.describe(),
        "final": args.final,
        "template": run.template.name,
        "cells": mesh.cell_count,
        "cells_by_kind": cells_by_kind(mesh),
        "added_points": len(run.template.points),
        "vertices": mesh.vertex_count,
        "volume": format_rational(box.volume),
        "valid": not violations,
        "steps": None if run.trace is None else len(run.trace),
        "digest": mesh.digest_text,
        "start_digest": run.start.digest_text,
        "written": [str(path) for path in written],
    }
    if args.json:
        report["violations"] = violation_reports(violations)
        print_json(report)
    else:
        title = (f"cuboid pattern {args.pattern} (bits {report['bits']}) on "
                 f"{report['shape']}, final {args.final}")
        print_table(title, {key: report[key] for key in (
            "template", "cells", "cells_by_kind", "added_points", "vertices", "volume",
            "valid", "digest")})
        for violation in violations:
            print(f"  {violation}")
        for path in written:
            print(f"wrote {path}")
    return EXIT_FAILED if violations else EXIT_OK


def _cells(mesh: Mesh3) -> list[int] | None:
    """The vertex count of each polyhedral Delaunay cell (co-spherical tetrahedra grouped
    exactly), or None when the mesh is not Delaunay (without --improve
    --allow-boundary-flips it rarely is)."""
    from geomexact.mesh3d.cospherical import polyhedral_cells
    from geomexact.mesh3d.measures import is_delaunay3

    if not is_delaunay3(mesh):
        return None
    return [len(cell.vertices) for cell in polyhedral_cells(mesh)]


def _start_numbers(path: str | None, box: Box) -> NumberStyle:
    """How ``--start`` writes numbers: always losslessly (a rounded start would not be the
    trace's input): ``exact`` in a text format; in a format of doubles (VTK, …) only
    when every corner of the box is a double, else a :class:`UsageProblem`."""
    if path is None or io.detect_format(path) != "meshio":
        return "exact"
    for value in (*box.low, *box.high):
        if not nearest_double_text(value)[1]:
            raise UsageProblem(
                f"{path} (--start): this format stores doubles and the box corner "
                f"coordinate {format_rational(value)} is not one, so the start would not be "
                "the trace's input; write it as TetGen files (START.ele), which are exact")
    return "decimal"


def _print_text(report: dict[str, Any]) -> None:
    title = (f"cuboid pattern {report['pattern']} (bits {report['bits']}) on "
             f"{report['shape']}, order {report['order']}, template {report['template']}")
    configurations = {
        kind: f"{counts['total']} ({counts['failing']} failing)"
        for kind, counts in report["configurations"].items() if counts["total"]}
    rows = {key: report[key] for key in ("tetrahedra", "tetrahedra_partition", "vertices",
                                         "volume", "valid", "delaunay",
                                         "delaunay_partition", "steps", "digest")}
    if report["flips"] is not None:
        rows["flips"] = ", ".join(f"{k} {v}" for k, v in report["flips"].items())
        rows["failing_kinds"] = " ".join(report["failing_kinds"]) or "none"
    rows["configurations"] = ", ".join(f"{k} {v}" for k, v in configurations.items())
    cells = report["cells"]
    rows["polyhedral cells"] = ("not Delaunay" if cells is None else
                                f"{len(cells)} (vertices: {' '.join(map(str, cells))})")
    print_table(title, rows)
    print("  box faces (triangles by point: cK corner, eI edge midpoint, fJ face centre):")
    for name, triangles in report["faces"].items():
        print(f"    {name}: " + "  ".join("-".join(t) for t in triangles))
    for path in report["written"]:
        print(f"wrote {path}")


def add_parser(commands: Subcommands) -> None:
    """Add the ``cuboid`` command."""
    cuboid = add_command(commands, "cuboid", command_cuboid)
    cuboid.add_argument("pattern", metavar="PATTERN", type=pattern_argument,
                        help="0 .. 262143: bit i marks a Steiner point on cube edge i "
                        "(0-11) or face i (12-17); see docs/cuboid.md")
    add_cuboid_options(cuboid)
    add_final_option(cuboid, "the pattern's tetrahedra (default), improved by Joe's flips "
                     "(delaunay: --improve), its mixed template (a hexahedron when bare; "
                     "wedges, pyramids, tetrahedra) or its polyhedral Delaunay cells")
    add_run_outputs(
        cuboid,
        output="write the final mesh (TetGen OUT.ele with OUT.node and OUT.face, or .vtu, …)",
        start="write the 5-tetrahedron start mesh, exactly: the INPUT of "
              "'geomexact replay FILE TRACE'",
        trace="write the trace (from the 5-tetrahedron start) to FILE")
