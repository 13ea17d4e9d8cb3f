"""``geomexact triangulate``: (constrained) Delaunay triangulation of points or a PSLG, or
Lawson flips of a triangle mesh."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from geomexact.cli.arguments import (
    Subcommands,
    add_check_flag,
    add_command,
    add_engine_option,
    add_input_argument,
    add_output_option,
    add_trace_output,
    add_writing_options,
)
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.kinds import wrong_kind
from geomexact.cli.loading import load, seed_warnings, triangulate_input
from geomexact.cli.provenance import with_provenance
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.writing import distinct_outputs, refuse_existing, write_output
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.delaunay.triangulation import make_delaunay
from geomexact.mesh2d.engine_names import OLD_NAMES
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh2d.validation import validate


def command_triangulate(args: argparse.Namespace) -> int:
    """(Constrained) Delaunay triangulation of a point set or PSLG, or Lawson flips of a
    triangle mesh into a Delaunay one; writes the mesh and optionally the trace."""
    outputs = [("-o", args.output, args.to), ("--trace", args.trace, "file")]
    refuse_existing(outputs, force=args.force)  # before the work, not after it
    loaded = load(args.input, args.format, args.verbose)
    distinct_outputs(outputs)
    started = time.perf_counter()
    warnings: list[str] = []
    if isinstance(loaded.value, Mesh2):
        mesh, trace = make_delaunay(loaded.value)
        algorithm = "lawson flips"
    elif isinstance(loaded.value, PSLG):
        construction = triangulate_input(
            loaded,
            split_hint="use --split-segments to split them there",
            keep_convex_hull=args.keep_convex_hull,
            split_segments=args.split_segments,
            merge_duplicates=args.merge_duplicates,
            engine=OLD_NAMES.get(args.engine, args.engine),  # the API warns on old names
        )
        warnings = seed_warnings(loaded, construction)
        mesh, trace = construction.mesh, construction.trace
        algorithm = "constrained delaunay" if loaded.value.segments else "delaunay"
    else:
        raise wrong_kind(args.input, loaded.value, "triangulate",
                         "2D PSLGs and triangle meshes (made Delaunay by flips)")
    seconds = time.perf_counter() - started
    written = write_output(args, args.output, mesh, "triangulation")
    if args.trace:
        trace_path = Path(args.trace)
        trace = with_provenance(trace, args, engine=args.engine, input_path=args.input)
        write_trace(trace_path, trace, overwrite=args.force)
        written.append(trace_path)
    violations = validate(mesh) if args.check else []
    summary = mesh_summary(mesh)
    delaunay_ok = summary["is_delaunay"]
    report = {
        "input": args.input,
        "algorithm": algorithm,
        **summary,
        "steps": len(trace),
        "seconds": round(seconds, 6),
        "valid": not violations,
        "written": [str(path) for path in written],
        "warnings": warnings,
    }
    if args.json:
        print_json(report)
    else:
        print_table(f"{args.input}: {algorithm} in {seconds:.3f} s, {len(trace)} steps",
                    {k: v for k, v in report.items() if k not in {"input", "algorithm",
                                                                   "written", "seconds",
                                                                   "warnings"}})
        for path in written:
            print(f"wrote {path}")
        for violation in violations:
            print(f"  {violation}")
    if args.check and (violations or not delaunay_ok):
        return EXIT_FAILED
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``triangulate`` command."""
    triangulate_ = add_command(commands, "triangulate", command_triangulate)
    add_input_argument(triangulate_, ".node, .poly, PSLG text or a triangle mesh (OFF, .ele…)")
    add_output_option(triangulate_)
    triangulate_.add_argument("--keep-convex-hull", action="store_true",
                              help="keep the triangles between the segments and the convex hull")
    triangulate_.add_argument("--split-segments", action="store_true",
                              help="split segments at vertices on them and at crossings "
                                   "(default: such input is an error)")
    triangulate_.add_argument("--merge-duplicates", action="store_true",
                              help="keep the first of duplicate points (default: an error)")
    add_check_flag(triangulate_, "validate the result and check Delaunay-ness (exit 1 if not)")
    add_trace_output(triangulate_, "write the trace (JSON Lines)")
    add_engine_option(
        triangulate_, ("auto", "compiled", "reference", "python", "fast", "transient"),
        "auto (default: compiled when built, else reference), compiled (the kernel; an "
        "error when not built) or reference (the ops on a transient; python names it too); "
        "all record the same trace; fast and transient are the old names of auto and "
        "reference")
    add_writing_options(triangulate_)
