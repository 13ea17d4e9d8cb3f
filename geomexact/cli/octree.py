"""``geomexact octree``: mesh a box by the octree mixed-element mesher (refine where asked,
balance 2:1, partition every leaf by its Steiner pattern), check the result's conformity
exactly, report its statistics and write it."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

import attrs

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_run_outputs,
    non_negative,
    positive_int,
)
from geomexact.cli.cuboid import CELL_FINALS, add_final_option, rational_argument
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.memory import BYTES_PER_TETRAHEDRON, active_budget
from geomexact.cli.octree_command import (
    box_of_arguments,
    control_volumes_or_refuse,
    degrees_below,
    run_report,
)
from geomexact.cli.progress import add_progress_flags, progress_bar
from geomexact.cli.provenance import with_provenance
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.summaries import cells_by_kind
from geomexact.cli.writing import check_outputs, distinct_outputs, write
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

STAGES = ("initial", "refinement", "improvement", "final", "conformity", "write")


def _exact(text: str) -> Any:
    try:
        return parse_rational(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def _output_format(path: str | None, to: str | None) -> str | None:
    """``--to``, or the Geomview OFF of tetrahedra for an ``.off`` output (the 2D OFF
    format holds triangles only)."""
    if to is None and path is not None and Path(path).suffix.lower() == ".off":
        return "geomview3d"
    return to


def _stages(args: argparse.Namespace) -> dict[str, Any]:
    from geomexact.mesh3d.octree.criteria import MaxEdgeLength, RefineToMaxLevel
    from geomexact.mesh3d.octree.refinement import MAX_LEVEL
    from geomexact.mesh3d.octree.regions import (
        BallRegion,
        BoxRegion,
        SphereSurfaceRegion,
        UnionRegion,
        WholeDomain,
    )
    from geomexact.mesh3d.octree.stages import (
        BoxGrid,
        DelaunayPartition,
        MixedPartition,
        PatternPartition,
        PolyhedralPartition,
        RefineWhere,
    )

    regions: list[Any] = []
    sphere = SphereSurfaceRegion if args.surface else BallRegion
    for x, y, z, radius in args.refine_sphere or []:
        if radius <= 0:
            raise UsageProblem(f"--refine-sphere: the radius is positive, not "
                               f"{format_rational(radius)}")
        regions.append(sphere((x, y, z), radius))
    for values in args.refine_box or []:
        if not all(values[a] <= values[a + 3] for a in range(3)):
            raise UsageProblem("--refine-box X0 Y0 Z0 X1 Y1 Z1 needs X0 <= X1, Y0 <= Y1, "
                               "Z0 <= Z1")
        regions.append(BoxRegion(values[:3], values[3:]))
    if args.surface and not args.refine_sphere:
        raise UsageProblem("--surface applies to --refine-sphere, which was not given")
    region = (WholeDomain() if not regions else regions[0] if len(regions) == 1
              else UnionRegion(regions))
    if args.max_edge is not None:
        criterion: Any = MaxEdgeLength(args.max_edge)
        level = MAX_LEVEL if args.level is None else args.level
    else:
        criterion = RefineToMaxLevel()
        level = 3 if args.level is None else args.level
    if level > MAX_LEVEL:
        raise UsageProblem(f"--level is at most {MAX_LEVEL}, not {level}")
    final = {"patterns": PatternPartition, "delaunay": DelaunayPartition,
             "mixed": MixedPartition, "polyhedral": PolyhedralPartition}[args.final]()
    return {"initial": BoxGrid(*args.grid),
            "refinement": RefineWhere(level, criterion=criterion, region=region),
            "final": final}


TETRAHEDRA_PER_LEAF = 6
"""About how many tetrahedra a leaf's pattern partition makes (5 to 12; measured 5.8 on
a ball at level 5)."""


def estimated_tetrahedra(args: argparse.Namespace, level: int) -> int:
    """An upper estimate of the tetrahedra the octree of ``args`` makes at most at
    ``level``: every leaf of the finest level where a region (its bounding box widened by
    one finest box, in the domain) asks, with the coarser levels above them (8/7) and the
    2:1 balance (2x), never more than the grid refined everywhere.  Floats on ratios of the
    domain's sides, so any scale of box is measured alike; a refusal needs only the
    order of magnitude."""
    cells = args.grid[0] * args.grid[1] * args.grid[2]
    if args.max_edge is not None:  # no deeper than where the box's longest side is short
        longest = max((args.box[a + 3] - args.box[a]) / args.grid[a] for a in range(3))
        level = min(level, max(0, math.ceil(math.log2(float(longest / args.max_edge)))))
    everywhere = cells * 8 ** level
    regions = [*(("sphere" if args.surface else "ball", values)
                 for values in args.refine_sphere or []),
               *(("box", values) for values in args.refine_box or [])]
    if not regions:  # the whole domain, to the level (or to --max-edge: at most the level)
        return int(TETRAHEDRA_PER_LEAF * everywhere)
    low, high = args.box[:3], args.box[3:]

    def along(axis: int, value: Any) -> float:  # exact, then one rounding: any scale
        return float((value - low[axis]) / (high[axis] - low[axis]))

    finest = [1 / (args.grid[a] * 2.0 ** level) for a in range(3)]  # in units of the sides
    share = 0.0
    for kind, values in regions:
        if kind == "box":
            spans = [(along(a, values[a]), along(a, values[a + 3])) for a in range(3)]
        else:
            radius = values[3]
            spans = [(along(a, values[a] - radius), along(a, values[a] + radius))
                     for a in range(3)]
        volume = 1.0
        for (start, end), step in zip(spans, finest, strict=True):
            volume *= max(0.0, min(1.0, end + step) - max(0.0, start - step))
        if kind == "sphere":  # a shell two finest boxes thick, not the ball
            radii = [(end - start) / 2 for start, end in spans]
            shell = 4 * math.pi * (radii[0] * radii[1] * radii[2]) ** (2 / 3) * 4 * max(finest)
            volume = min(volume, shell)
        share += volume
    fine_leaves = min(1.0, share) * everywhere
    return int(TETRAHEDRA_PER_LEAF * min(everywhere, fine_leaves * 8 / 7 * 2 + cells))


def _json_number(value: Any) -> Any:
    """``value``, or None for a float beyond the doubles (a radius-edge ratio of a box
    thinner than 2^-1024 of its length along one axis), as JavaScript's JSON writes it."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


def command_octree(args: argparse.Namespace) -> int:
    """Mesh the box, check it, report it, write it (the cyclic collector paused: the
    command builds a few million small objects and frees them at exit)."""
    with collector_paused():
        return _octree(args)


def _octree(args: argparse.Namespace) -> int:
    if args.device:
        from geomexact.cli.octree_domain import command_octree_device

        return command_octree_device(args)
    if args.domain:
        from geomexact.cli.octree_domain import command_octree_domain

        return command_octree_domain(args)
    for name, given in (("--interior-level", args.interior_level), ("--band", args.band),
                        ("--no-warp", args.no_warp),
                        ("--improve-quality", args.improve_quality is not None),
                        ("--feature-angle", args.feature_angle is not None)):
        if given:
            raise UsageProblem(f"{name} applies to --domain, which was not given")
    if args.box is None:
        args.box = [parse_rational(v) for v in "000111"]
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.octree.pipeline import generate, generate_cells

    started = time.perf_counter()
    domain = box_of_arguments(args)
    stages = _stages(args)
    cell_final = args.final in CELL_FINALS
    output_format = _output_format(args.output, args.to)
    outputs = [("-o", args.output, output_format), ("--start", args.start, None),
               ("--trace", args.trace, "file"), ("--voronoi", args.voronoi, "file")]
    distinct_outputs(outputs)
    check_outputs(outputs[:1], MixedMesh3 if cell_final else Mesh3, force=args.force)
    check_outputs(outputs[1:], Mesh3, force=args.force)  # --start: vertices only
    if args.start and not args.trace:
        raise UsageProblem("--start writes the input of the trace: give --trace too")
    level = stages["refinement"].max_level
    active_budget().refuse_beyond(
        f"an octree of {args.grid[0]} x {args.grid[1]} x {args.grid[2]} boxes to level {level}",
        estimated_tetrahedra(args, level) * BYTES_PER_TETRAHEDRON,
        "ask for a coarser mesh (a smaller --level or --grid, a larger --max-edge, smaller "
        "refinement regions)")
    bar = progress_bar(args, "octree")

    def on_stage(name: str) -> None:
        if bar is not None:
            bar(STAGES.index(name), len(STAGES), stage=name)

    run: Any
    if cell_final:
        final = stages.pop("final")
        run = generate_cells(domain, final, trace=bool(args.trace), on_stage=on_stage,
                             **stages)
    else:
        run = generate(domain, trace=bool(args.trace), on_stage=on_stage, **stages)
    on_stage("write")
    volumes = control_volumes_or_refuse(run.mesh) if args.voronoi else None
    written: list[Path] = []
    if args.start and run.start is not None:
        written += write(args.start, _start_value(run.start), None, overwrite=args.force,
                         numbers="exact")
    if args.output:
        mesh_value: Any = run.mesh
        if cell_final:
            from geomexact.mesh3d.mixed.cell_data import MixedMeshData

            mesh_value = MixedMeshData(run.mesh, {"level": run.leaf_mesh.levels})
        written += write(args.output, mesh_value, output_format, overwrite=args.force,
                         numbers=args.numbers)
    if args.trace and run.trace is not None:
        trace = attrs.evolve(run.trace, parameters={
            **dict(run.trace.parameters),
            "box": [format_rational(v) for v in (*domain.low, *domain.high)],
            "grid": list(args.grid)})
        # with a trace the mesh is built by the reference steps
        trace = with_provenance(trace, args, engine="reference", input_path=args.start)
        write_trace(args.trace, trace, overwrite=args.force)
        written.append(Path(args.trace))
    if volumes is not None:
        from geomexact.io.control_volumes import write_control_volumes

        write_control_volumes(args.voronoi, run.mesh, volumes, overwrite=args.force)
        written.append(Path(args.voronoi))
    if bar is not None:
        bar(len(STAGES), len(STAGES), stage="done")
    report: dict[str, Any] = {
        "box": [format_rational(v) for v in (*domain.low, *domain.high)],
        "grid": list(args.grid),
        "final": args.final,
        "leaves": run.octree.leaf_count,
        "levels": {str(level): count for level, count in run.octree.levels()},
        "leaves_refined": run.refined.leaf_count,
        "forced_splits": run.leaf_mesh.forced_splits,
    }
    if cell_final:
        report |= {
            "cells": run.mesh.cell_count,
            "cells_by_kind": cells_by_kind(run.mesh),
            "templates": run.leaf_mesh.templates,
            "added_points": run.leaf_mesh.added,
            "vertices": run.mesh.vertex_count,
            "conforming": run.conformity.conforming,
            "interior_faces": run.conformity.interior_faces,
            "boundary_faces": run.conformity.boundary_faces,
            "volume": format_rational(domain.volume),
        }
    else:
        quality = run.quality()
        report |= {
            "tetrahedra": run.mesh.tetrahedron_count,
            "vertices": run.mesh.vertex_count,
            "min_dihedral": quality.min_dihedral,
            "max_dihedral": quality.max_dihedral,
            "max_radius_edge": quality.max_radius_edge,
            "conforming": run.conformity.conforming,
            "interior_faces": run.conformity.interior_faces,
            "boundary_faces": run.conformity.boundary_faces,
            "volume": format_rational(run.volume),
        }
    report |= run_report(run.mesh, run.trace, run.seconds, started, written, volumes)
    if args.json:
        print_json({key: _json_number(value) for key, value in report.items()})
    else:
        title = (f"octree mesh of {domain.describe()} (grid {'x'.join(map(str, args.grid))}, "
                 f"final {args.final})")
        shown = (("cells", "cells_by_kind", "added_points") if cell_final else
                 ("tetrahedra", "vertices", "min_dihedral", "max_dihedral", "max_radius_edge"))
        rows = {key: report[key] for key in (
            "leaves", "levels", "forced_splits", *shown, "vertices", "conforming", "volume",
            "digest", "seconds", "peak_memory_mb")}
        print_table(title, rows)
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def _start_value(start: Mesh3 | MixedMesh3) -> Mesh3:
    """What ``--start`` writes: the trace's input, its vertices and no cell (a mixed
    start as the tetrahedral mesh of its vertices: the same digest, and a file the
    tetrahedral formats hold exactly)."""
    if isinstance(start, Mesh3):
        return start
    if start.cell_count:  # pragma: no cover - an octree trace starts from vertices only
        raise UsageProblem("--start: the trace's input has cells")
    from geomexact.mesh3d.transient import mesh3_from_positive_arrays

    return mesh3_from_positive_arrays(
        [start.point(vertex) for vertex in range(start.vertex_count)], ())


def add_parser(commands: Subcommands) -> None:
    """Add the ``octree`` command."""
    octree = add_command(commands, "octree", command_octree)
    octree.add_argument("--box", nargs=6, type=_exact, metavar=("X0", "Y0", "Z0", "X1", "Y1",
                                                                "Z1"),
                        help="the box, exact (default: the unit cube; with --domain, a "
                        "dyadic cube around the surfaces)")
    octree.add_argument("--grid", nargs=3, type=positive_int, metavar=("N", "M", "K"),
                        default=[1, 1, 1], help="the initial grid of boxes (default 1 1 1)")
    octree.add_argument("--level", type=non_negative, metavar="K",
                        help="the deepest level (default 3; with --max-edge, as deep as "
                        "needed, up to 16)")
    octree.add_argument("--max-edge", type=rational_argument, metavar="L",
                        help="refine a leaf while its longest edge is longer than L")
    octree.add_argument("--refine-sphere", nargs=4, type=_exact, action="append",
                        metavar=("X", "Y", "Z", "R"),
                        help="refine where the ball (or, with --surface, the sphere) of "
                        "centre X Y Z and radius R meets a leaf (repeatable)")
    octree.add_argument("--surface", action="store_true",
                        help="--refine-sphere means the sphere's surface, not the ball")
    octree.add_argument("--refine-box", nargs=6, type=_exact, action="append",
                        metavar=("X0", "Y0", "Z0", "X1", "Y1", "Z1"),
                        help="refine where this box meets a leaf (repeatable)")
    add_final_option(octree, "each leaf's tetrahedra by its pattern (default), those "
                     "improved by Joe's flips inside the leaf (delaunay), hexahedra with "
                     "wedges, pyramids and tetrahedra at transitions (mixed), or the exact "
                     "Delaunay cells with co-spherical groups kept whole (polyhedral)")
    add_run_outputs(
        octree,
        output="write the mesh (TetGen OUT.ele/.node/.face, .vtu, .vtk, Geomview .off)",
        start="with --trace: write the trace's input (the vertices), exactly",
        trace="record the run by the reference steps (one insert_cuboid per leaf, then "
              "flips) and write the trace")
    octree.add_argument("--voronoi", metavar="OUT.cv",
                        help="write the Voronoi control volumes of the mesh (exact; "
                             "specs/formats/control_volumes.md); the mesh must be "
                             "Delaunay")
    octree.add_argument("--domain", action="append", metavar="SURFACE",
                        help="mesh the inside of this closed surface (.obj, .stl, .ply, "
                        ".off; repeatable: a surface inside another is a hole); --level is "
                        "then the level where the surface is (default 5)")
    octree.add_argument("--device", metavar="DEVICE",
                        help="mesh a device of material boxes (specs/formats/device.md), "
                        "every box face fitted exactly; --level refines everywhere (default "
                        "0: the exact grid); write .vtu/.vtk/.msh (each tetrahedron's "
                        "material as cell data)")
    octree.add_argument("--interior-level", type=non_negative, default=0, metavar="K",
                        help="with --domain: refine everywhere to level K first (default 0)")
    octree.add_argument("--band", type=rational_argument, default=0, metavar="D",
                        help="with --domain: refine to --level where a leaf is within D of "
                        "a triangle's bounding box (default 0)")
    octree.add_argument("--feature-angle", metavar="DEG",
                        type=degrees_below(180, "an angle between normals"),
                        help="with --domain: refine a leaf at the surface only while the "
                        "surface's normals inside it differ by more than DEG (curved parts "
                        "and creases fine, flat parts coarse)")
    octree.add_argument("--improve-quality", metavar="DEG",
                        type=degrees_below(70.5, "a dihedral angle bound"),
                        help="with --domain: then flip tetrahedra (exact steps, the "
                        "boundary kept) while that raises any dihedral angle below DEG")
    octree.add_argument("--no-warp", action="store_true",
                        help="with --domain: keep every vertex off the surface where it "
                        "is (no snapping; thinner tetrahedra)")
    add_progress_flags(octree)

