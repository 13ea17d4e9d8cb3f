"""``geomexact octree --domain FILE …``: mesh the domain that closed surfaces bound (a
part, with holes), fitted exactly: every boundary vertex on a surface
(``docs/meshing-a-part.md``)."""

from __future__ import annotations

import argparse
import resource
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.memory import BYTES_PER_TETRAHEDRON, active_budget
from geomexact.cli.octree_command import (
    box_of_arguments,
    control_volumes_or_refuse,
    run_report,
)
from geomexact.cli.progress import progress_bar
from geomexact.cli.provenance import with_provenance
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.writing import check_outputs, distinct_outputs, write
from geomexact.kernel.numbers import format_rational
from geomexact.mesh3d.snapshot import Mesh3

STAGES = ("surfaces", "index", "initial", "refinement", "improvement", "final", "conformity",
          "fit", "enclosed volume", "quality", "trace", "check", "write")
DEFAULT_LEVEL = 5


def _refused_options(args: argparse.Namespace, option: str = "--domain") -> None:
    """Options of the box mesher that a domain or a device does not take (exit 2)."""
    given = [name for name, value in (("--grid", args.grid != [1, 1, 1]),
                                      ("--refine-sphere", args.refine_sphere),
                                      ("--refine-box", args.refine_box),
                                      ("--surface", args.surface)) if value]
    if given:
        raise UsageProblem(f"{', '.join(given)}: these options are for a box; a {option} "
                           "is refined by --level and --max-edge (a --domain also by "
                           "--interior-level and --band)")
    if args.final != "patterns":
        raise UsageProblem(f"--final {args.final} with {option}: its tetrahedra are fitted "
                           "(--final patterns, the default); mixed cells there are not "
                           "built yet")


def _surfaces(paths: list[str]) -> list[Any]:
    """Each file read exactly, turned outward when it faced in (said on stderr), checked
    exactly; no two may meet."""
    from geomexact.io.surface_files import read_surface
    from geomexact.mesh3d.surface.checks import (
        check_surface,
        oriented_outward,
        surfaces_intersect,
    )

    surfaces = []
    for path in paths:
        surface, flipped = oriented_outward(read_surface(path))
        if flipped:
            print(f"geomexact: note: {path}: the surface faced inward; every triangle was "
                  "turned to face out", file=sys.stderr)
        check_surface(surface, path)
        surfaces.append(surface)
    for i, first in enumerate(surfaces):
        for j in range(i + 1, len(surfaces)):
            pairs = surfaces_intersect(first, surfaces[j])
            if pairs:
                shown = ", ".join(f"{a} and {b}" for a, b in pairs[:3])
                raise UsageProblem(f"{paths[i]} and {paths[j]} meet ({len(pairs)} pairs of "
                                   f"triangles, e.g. {shown}): the surfaces of a domain "
                                   "must not touch")
    return surfaces


def _estimated_tetrahedra(surfaces: list[Any], level: int, interior_level: int) -> int:
    """About how many tetrahedra: the leaves along the surfaces (their area over the finest
    leaf's face, two leaves thick, with the coarser levels and the balance: x 4) and the
    leaves everywhere at the interior level, six tetrahedra each."""
    from geomexact.mesh3d.octree.domain import domain_box

    side = float(domain_box(surfaces).extents[0])
    area = 0.0
    for surface in surfaces:
        xyz = [[p.fx, p.fy, p.fz] for p in surface.points]
        for a, b, c in surface.triangles.tolist():
            u = [xyz[b][k] - xyz[a][k] for k in range(3)]
            v = [xyz[c][k] - xyz[a][k] for k in range(3)]
            cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                     u[0] * v[1] - u[1] * v[0])
            area += 0.5 * sum(x * x for x in cross) ** 0.5
    finest = side / 2 ** level
    near = area / finest ** 2 * 2 * 4
    return int(6 * (near + 8 ** interior_level))


def _print_report(args: argparse.Namespace, report: dict[str, Any], title: str,
                  keys: Sequence[str], *, problems: Sequence[str], written: Sequence[Path],
                  details: Sequence[str] = ()) -> None:
    """``report`` as JSON with ``--json``; else ``title`` over the table of its ``keys``,
    then the lines ``details``, each problem and each file written."""
    if args.json:
        print_json(report)
        return
    print_table(title, {key: report[key] for key in keys})
    for line in details:
        print(line)
    for problem in problems:
        print(f"  {problem}")
    for path in written:
        print(f"wrote {path}")


def _material_line(material: str, row: dict[str, Any]) -> str:
    """The text report's line of one material of a device: its name, cells and volume."""
    label = f" ({row['name']})" if row["name"] else ""
    return (f"  material {material}{label}: {row['cells']} cells, volume "
            f"{row['volume']}{' (exact)' if row['exact'] else ''}")


def command_octree_domain(args: argparse.Namespace) -> int:
    """Read and check the surfaces, mesh their domain, check it, report it, write it."""
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.measures import total_volume
    from geomexact.mesh3d.octree.domain import generate_domain, merged_surface
    from geomexact.mesh3d.octree.domain_fit import WARP_FRACTION
    from geomexact.mesh3d.quality import quality_summary
    from geomexact.mesh3d.quality_improvement import QualityCriterion
    from geomexact.mesh3d.surface.queries import surface_index
    from geomexact.mesh3d.validation import validate3

    started = time.perf_counter()
    _refused_options(args)
    outputs = [("-o", args.output, args.to), ("--start", args.start, None),
               ("--trace", args.trace, "file"), ("--voronoi", args.voronoi, "file")]
    distinct_outputs(outputs)
    check_outputs(outputs, Mesh3, force=args.force)
    if args.start and not args.trace:
        raise UsageProblem("--start writes the input of the trace: give --trace too")
    level = DEFAULT_LEVEL if args.level is None else args.level
    interior = args.interior_level
    if interior > level:
        raise UsageProblem(f"--interior-level {interior} is above --level {level}")
    surfaces = _surfaces(args.domain)
    box = None
    if args.box is not None:
        box = box_of_arguments(args)
    active_budget().refuse_beyond(
        f"the domain of {', '.join(args.domain)} to level {level}",
        _estimated_tetrahedra(surfaces, level, interior) * BYTES_PER_TETRAHEDRON,
        "ask for a coarser mesh (a smaller --level or --interior-level, a larger --max-edge)")
    bar = progress_bar(args, "octree")

    def on_stage(name: str) -> None:
        if bar is not None and name in STAGES:
            bar(STAGES.index(name), len(STAGES), stage=name)

    try:
        criterion = (None if args.improve_quality is None
                     else QualityCriterion(min_dihedral=args.improve_quality))
        run = generate_domain(surfaces, level=level, interior_level=interior,
                              max_edge=args.max_edge, band=args.band, box=box,
                              feature_angle=args.feature_angle,
                              warp=None if args.no_warp else WARP_FRACTION, quality=criterion,
                              trace=bool(args.trace), on_stage=on_stage)
    except ValueError as error:  # pragma: no cover - a PreconditionError is one
        raise UsageProblem(str(error)) from None
    on_stage("check")
    mesh = run.mesh
    violations = validate3(mesh)
    index = surface_index(merged_surface(surfaces))
    boundary = sorted({v for face in mesh.boundary_faces() for v in face})
    off_surface = [v for v in boundary if not index.on_surface(mesh.point(v))]
    empty = ["no tetrahedron lies inside the surfaces: the leaves are too coarse for the "
             "domain"] if mesh.tetrahedron_count == 0 else []
    problems = empty + [str(v) for v in violations] + [
        f"boundary vertex {v} is not on a surface" for v in off_surface[:3]] + list(
        run.fit.pinches) + [f"tetrahedron {row} of the octree could not be cut" for row in
                            run.fit.unfit[:3]]
    volumes = None
    if args.voronoi and not problems:
        volumes = control_volumes_or_refuse(mesh)
    on_stage("write")
    written: list[Path] = []
    if not problems:
        if args.start and run.start is not None:
            from geomexact.mesh3d.transient import mesh3_from_positive_arrays

            start = run.start if isinstance(run.start, Mesh3) else mesh3_from_positive_arrays(
                [run.start.point(v) for v in range(run.start.vertex_count)], ())
            written += write(args.start, start, None, overwrite=args.force, numbers="exact")
        if args.output:
            written += write(args.output, mesh, args.to, overwrite=args.force,
                             numbers=args.numbers)
        if args.trace and run.trace is not None:
            trace = with_provenance(run.trace, args, engine="reference",
                                    input_path=args.start)
            write_trace(args.trace, trace, overwrite=args.force)
            written.append(Path(args.trace))
        if volumes is not None:
            from geomexact.io.control_volumes import write_control_volumes

            write_control_volumes(args.voronoi, mesh, volumes, overwrite=args.force)
            written.append(Path(args.voronoi))
    if bar is not None:
        bar(len(STAGES), len(STAGES), stage="done")
    volume = total_volume(mesh)
    xyz = np.array([[p.fx, p.fy, p.fz] for p in mesh.point_list()], dtype=np.float64)
    quality = quality_summary(xyz, np.array(mesh.tetrahedra(), dtype=np.int64).reshape(-1, 4))
    report: dict[str, Any] = {
        "domain": list(args.domain),
        "box": [format_rational(v) for v in (*run.box.low, *run.box.high)],
        "final": "patterns",
        "leaves": run.octree.leaf_count,
        "levels": {str(k): n for k, n in run.octree.levels()},
        "tetrahedra": mesh.tetrahedron_count,
        "vertices": mesh.vertex_count,
        "surface_vertices": len(run.fit.surface_vertices),
        "cut_points": run.fit.cut_points,
        "warped": run.fit.warped,
        "improvement": None if run.improvement is None else {
            "min_dihedral": args.improve_quality, "flips": run.improvement.flip_count,
            "edge_removals": run.improvement.edge_removals,
            "rounds": run.improvement.rounds,
            "worst_before": run.improvement.worst_before,
            "worst_after": run.improvement.worst_after,
            "failing_before": run.improvement.failing_before,
            "failing_after": run.improvement.failing_after},
        "min_dihedral": quality.min_dihedral,
        "max_dihedral": quality.max_dihedral,
        "max_radius_edge": quality.max_radius_edge,
        "valid": not problems,
        "problems": problems,
        "boundary_on_surface": not off_surface,
        "boundary_faces": len(mesh.boundary_faces()),
        "volume": format_rational(volume),
        "enclosed_volume": format_rational(run.enclosed_volume),
        "volume_error": abs(float((volume - run.enclosed_volume) / run.enclosed_volume)),
        **run_report(mesh, run.trace, run.seconds, started, written, volumes),
    }
    _print_report(
        args, report,
        f"octree mesh of the domain of {', '.join(args.domain)} in {run.box.describe()}",
        ("leaves", "levels", "tetrahedra", "vertices", "surface_vertices", "warped",
         "min_dihedral", "max_dihedral", "valid", "volume_error", "digest", "seconds",
         "peak_memory_mb"),
        problems=problems, written=written)
    if problems:
        print("geomexact: the mesh of the domain is not valid (above); nothing was written "
              "(a finer --level resolves parts thinner than the leaves)", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK



def command_octree_device(args: argparse.Namespace) -> int:
    """Read the device, mesh it with every box face fitted exactly, check it (validity,
    each material's exact volume against its painted volume), report it, write it with
    each tetrahedron's material."""
    from geomexact.io.device_file import read_device
    from geomexact.mesh3d.mixed.cell_data import MixedMeshData
    from geomexact.mesh3d.mixed.conversion import from_tetrahedral
    from geomexact.mesh3d.mixed.snapshot import MixedMesh3
    from geomexact.mesh3d.mixed.validation import validate_mixed
    from geomexact.mesh3d.octree.device import generate_device, painted_volumes
    from geomexact.mesh3d.quality import quality_summary
    from geomexact.mesh3d.validation import validate3

    started = time.perf_counter()
    final = args.final
    if final == "delaunay":
        raise UsageProblem("--final delaunay with --device: the Delaunay final needs equal "
                           "grid cells; a device takes patterns, mixed or polyhedral")
    args.final = "patterns"  # the other options are checked as for a domain
    _refused_options(args, "--device")
    args.final = final
    if args.domain:
        raise UsageProblem("--device and --domain: give one of them")
    for name, given in (("--trace", args.trace), ("--start", args.start),
                        ("--voronoi", args.voronoi), ("--interior-level", args.interior_level),
                        ("--band", args.band), ("--no-warp", args.no_warp),
                        ("--feature-angle", args.feature_angle is not None),
                        ("--improve-quality", args.improve_quality is not None)):
        if given:
            raise UsageProblem(f"{name} does not apply to --device yet")
    outputs = [("-o", args.output, args.to)]
    distinct_outputs(outputs)
    check_outputs(outputs, MixedMesh3, force=args.force)  # the materials need cell data
    device = read_device(args.device)
    level = 0 if args.level is None else args.level
    run = generate_device(device, level=level, max_edge=args.max_edge, final=final)
    mesh = run.mesh
    violations = [str(v) for v in (validate3(mesh) if isinstance(mesh, Mesh3) else
                                   validate_mixed(mesh, check_digest=False))]
    expected = painted_volumes(device)
    names = dict(device.names)
    materials = {
        str(material): {"name": names.get(material), "cells": int(
            (run.materials == material).sum()), "volume": format_rational(volume),
            "painted_volume": format_rational(expected[material]),
            "exact": volume == expected[material]}
        for material, volume in run.volumes.items()}
    problems = violations + [f"material {m}: volume {v['volume']} is not its painted "
                             f"volume {v['painted_volume']}" for m, v in materials.items()
                             if not v["exact"]]
    written: list[Path] = []
    if args.output and not problems:
        if isinstance(mesh, Mesh3):
            mixed = from_tetrahedral(mesh)
            by_cell = {tuple(sorted(t)): int(m) for t, m in zip(
                mesh.tetrahedra(), run.materials.tolist(), strict=True)}
            cell_materials = np.array([by_cell[tuple(sorted(cell.vertices))]
                                       for cell in mixed.cell_list()], dtype=np.int64)
        else:
            mixed, cell_materials = mesh, np.asarray(run.materials)
        written += write(args.output, MixedMeshData(mixed, {"material": cell_materials}),
                         args.to, overwrite=args.force, numbers=args.numbers)
    angles: tuple[float | None, float | None] = (None, None)
    if isinstance(mesh, Mesh3):
        xyz = np.array([[p.fx, p.fy, p.fz] for p in mesh.point_list()], dtype=np.float64)
        quality = quality_summary(xyz, np.array(mesh.tetrahedra(),
                                                dtype=np.int64).reshape(-1, 4))
        angles = (quality.min_dihedral, quality.max_dihedral)
    bounds = device.bounds()
    report: dict[str, Any] = {
        "device": args.device,
        "box": [format_rational(v) for v in (*bounds.low, *bounds.high)],
        "grid": list(run.grid),
        "leaves": run.octree.leaf_count,
        "levels": {str(k): n for k, n in run.octree.levels()},
        "final": final,
        "cells": mesh.tetrahedron_count if isinstance(mesh, Mesh3) else mesh.cell_count,
        "vertices": mesh.vertex_count,
        "materials": materials,
        "min_dihedral": angles[0],
        "max_dihedral": angles[1],
        "valid": not problems,
        "problems": problems,
        "digest": mesh.digest_text,
        "stage_seconds": {name: round(value, 4) for name, value in run.seconds.items()},
        "seconds": round(time.perf_counter() - started, 4),
        "peak_memory_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
        "written": [str(path) for path in written],
    }
    _print_report(
        args, report, f"octree mesh of the device {args.device} ({bounds.describe()})",
        ("grid", "leaves", "cells", "vertices", "min_dihedral", "max_dihedral", "valid",
         "digest", "seconds"),
        details=[_material_line(material, row) for material, row in materials.items()],
        problems=problems, written=written)
    if problems:
        print("geomexact: the device mesh is not valid (above); nothing was written",
              file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK
