"""``geomexact replay``: replay a trace on its input mesh, checking every digest: a 2D
trace on its triangle mesh (or the PSLG it triangulated), a 3D trace on its tetrahedral
mesh, a mixed-cell trace on its mixed mesh (or the tetrahedral mesh of the same cells:
an octree's start is its vertices), and a cuboid trace also on the start mesh rebuilt
from its own parameters."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_format_option,
    add_input_argument,
    add_output_option,
    add_to_option,
    add_trace_argument,
    add_writing_options,
    format_names,
    non_negative,
)
from geomexact.cli.errors import UsageProblem, cli_wording
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.loading import load
from geomexact.cli.reporting import print_json
from geomexact.cli.writing import check_outputs, write
from geomexact.errors import PreconditionError, TraceError
from geomexact.io.trace_file import read_trace
from geomexact.kernel.digest import digest_text
from geomexact.mesh2d.delaunay.triangulation import vertices_mesh
from geomexact.mesh2d.ops import OPERATIONS as OPERATIONS_2D
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.cuboid.cell_templates import recorded_cell_start
from geomexact.mesh3d.cuboid.partition import recorded_start
from geomexact.mesh3d.mixed.cells import CellKind
from geomexact.mesh3d.mixed.conversion import from_tetrahedral, to_tetrahedral
from geomexact.mesh3d.mixed.ops import OPERATIONS as OPERATIONS_MIXED
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.trace.playback import replay
from geomexact.trace.protocols import kind_of
from geomexact.trace.record import Trace

_ALGORITHM_DIMENSIONS = {"delaunay": 2, "lepp": 2, "lawson": 2, "cuboid": 3, "octree": 3}
"""The dimension of the mesh each recording algorithm (the trace's ``algorithm``
parameter) works on."""

_DIMENSION_WORDS = {2: "a 2D trace (of a triangle mesh)", 3: "a 3D trace (of a tetrahedral mesh)"}


def trace_dimension(trace: Trace) -> int | None:
    """2 or 3: the dimension of the mesh ``trace`` replays on, from its ``algorithm``
    parameter, else from its step names (each step table's own); None when neither
    tells (no steps and no known algorithm)."""
    known = _ALGORITHM_DIMENSIONS.get(trace.parameter("algorithm"))
    if known is not None:
        return known
    ops = {step.op for step in trace.steps}
    if ops and (ops <= kind_of(Mesh3).operations.keys() or ops <= OPERATIONS_MIXED.keys()):
        return 3
    if ops and ops <= OPERATIONS_2D.keys():
        return 2
    return None


def is_mixed_trace(trace: Trace) -> bool:
    """True when ``trace`` edits a mixed-cell mesh: its steps are the mixed step table's
    and not all the tetrahedral one's."""
    ops = {step.op for step in trace.steps}
    return bool(ops) and ops <= OPERATIONS_MIXED.keys() and not (
        ops <= kind_of(Mesh3).operations.keys())


def command_replay(args: argparse.Namespace) -> int:
    """Replay a trace on its input mesh (on the PSLG a triangulation trace started from;
    on the start a cuboid trace records when INPUT is not given), checking every digest,
    and write the result."""
    trace = read_trace(args.trace)
    dimension = trace_dimension(trace)
    rebuilt = args.input is None
    if rebuilt:
        start: Mesh2 | Mesh3 | MixedMesh3 = _rebuilt_start(args.trace, trace)
        value: Any = start
    else:
        loaded = load(args.input, args.format, args.verbose)
        value = loaded.value
        start = start_of(args.input, value, args.trace, dimension, is_mixed_trace(trace))
    check_outputs([("-o", args.output, args.to)], _result_type(start, trace, args.until),
                  force=args.force)
    if start.digest != trace.input_digest:
        raise UsageProblem(wrong_input(args.input, value, start, args.trace, trace))
    try:
        result = replay(start, trace, until=args.until)
    except TraceError as error:
        if args.until is not None and not 0 <= args.until <= len(trace):
            raise  # the inputs do not belong together: bad input, exit 2
        message = f"{args.trace}: {cli_wording(str(error))}"
        print(f"geomexact: trace diverged: {message}", file=sys.stderr)
        if args.json:
            print_json(
                {"input": args.input, "trace": args.trace, "diverged": True,
                 "error": message, "step": error.step,
                 "expected_digest": _digest_or_none(error.expected),
                 "found_digest": _digest_or_none(error.found)}
            )
        return EXIT_FAILED
    applied = len(trace) if args.until is None else args.until
    if isinstance(result, MixedMesh3) and result.cell_count and all(
            cell.kind == CellKind.TETRA for cell in result.cell_list()):
        result = to_tetrahedral(result)  # the same digest, and the tetrahedral formats
    written = write(args.output, result, args.to, overwrite=args.force, numbers=args.numbers)
    cells, count = (("tetrahedra", result.tetrahedron_count) if isinstance(result, Mesh3)
                    else ("cells", result.cell_count) if isinstance(result, MixedMesh3)
                    else ("triangles", result.triangle_count))
    if args.json:
        print_json(
            {
                "input": args.input,
                "trace": args.trace,
                "diverged": False,
                "dimension": 2 if isinstance(result, Mesh2) else 3,
                "rebuilt_start": rebuilt,
                "trace_steps": len(trace),
                "steps_applied": applied,
                "input_digest": start.digest_text,
                "final_digest": result.digest_text,
                "vertices": result.vertex_count,
                cells: count,
                "written": [str(path) for path in written],
            }
        )
    else:
        if rebuilt:
            print(f"rebuilt the start mesh from the parameters of {args.trace}: "
                  f"digest {start.digest_text}")
        print(
            f"replayed {applied} of {len(trace)} steps: {result.vertex_count} vertices, "
            f"{count} {cells}, digest {result.digest_text} (all digests match)"
        )
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def _result_type(start: Mesh2 | Mesh3 | MixedMesh3, trace: Trace, until: int | None) -> type:
    """The type of mesh the replay gives: a mixed trace whose steps add tetrahedra only
    gives a tetrahedral mesh (it is written as one)."""
    steps = trace.steps if until is None else trace.steps[:until]
    if isinstance(start, MixedMesh3) and steps and all(
            step.op == "add_cell" and step.args[:1] == (int(CellKind.TETRA),)
            for step in steps):
        return Mesh3
    return type(start)


def _digest_or_none(value: int | None) -> str | None:
    return None if value is None else digest_text(value)


def rebuilt_start(trace: Trace) -> Mesh3 | MixedMesh3:
    """The start a cuboid trace records how to rebuild (its cell final's, or its
    tetrahedral partition's); :class:`PreconditionError` for any other trace."""
    if trace.parameter("final") in ("mixed", "polyhedral"):
        return recorded_cell_start(trace)
    return recorded_start(trace)


def _rebuilt_start(trace_path: str, trace: Trace) -> Mesh3 | MixedMesh3:
    """The start mesh of a cuboid trace given without INPUT (exit 2 for any other)."""
    try:
        return rebuilt_start(trace)
    except PreconditionError as error:
        raise UsageProblem(
            f"{trace_path}: give the INPUT mesh the trace was recorded on "
            f"(geomexact replay INPUT {trace_path} -o OUT); {error.problem}"
        ) from error


def start_of(input_path: str, value: Any, trace_path: str, dimension: int | None,
             mixed: bool = False) -> Mesh2 | Mesh3 | MixedMesh3:
    """The mesh to replay on: ``value`` itself (the isolated vertices of a PSLG; for a
    ``mixed`` trace a tetrahedral mesh as the mixed mesh of its cells, the same digest);
    a :class:`UsageProblem` for another kind of value or a trace of the other
    dimension."""
    start: Mesh2 | Mesh3 | MixedMesh3
    if isinstance(value, Mesh3 | MixedMesh3):
        found, start = 3, value
    elif isinstance(value, PSLG):
        found, start = 2, vertices_mesh(value)
    elif isinstance(value, Mesh2):
        found, start = 2, value
    else:
        raise UsageProblem(f"{input_path}: replay needs a triangle mesh, a PSLG, a "
                           "tetrahedral mesh or a mixed-cell mesh")
    if dimension is not None and dimension != found:
        what = ("a tetrahedral mesh (3D)" if isinstance(value, Mesh3) else
                "a mixed-cell mesh (3D)") if found == 3 else (
            "a PSLG (2D)" if isinstance(value, PSLG) else "a triangle mesh (2D)")
        hint = ("; a cuboid trace also replays without INPUT: geomexact replay "
                f"{trace_path} -o OUT" if dimension == 3 else "")
        raise UsageProblem(
            f"{trace_path} is {_DIMENSION_WORDS[dimension]}, but {input_path} is {what}: "
            f"a trace replays only on a mesh of its own dimension{hint}"
        )
    if mixed and isinstance(start, Mesh3):
        return from_tetrahedral(start)
    return start


def wrong_input(
    input_path: str | None, value: Any, start: Mesh2 | Mesh3 | MixedMesh3, trace_path: str,
    trace: Trace
) -> str:
    """Why ``trace`` does not replay on ``input_path``: the input it was recorded on (its
    name when the trace header has it, and digest), this one's digest, which step of the
    trace ``start`` is when it is one of its meshes, and what kind of input the trace
    wants."""
    recorded = f"{trace.input_name!r} " if trace.input_name else ""
    given = input_path if input_path is not None else "the start rebuilt from its parameters"
    wants = ""
    algorithm = trace.parameter("algorithm")
    if start.digest in trace.digests:
        step = trace.digests.index(start.digest) + 1
        last = " (its final mesh)" if step == len(trace) else ""
        wants = (f"; {given} is the mesh after step {step} of {len(trace)}{last}, "
                 "not the one it starts from")
    if algorithm == "delaunay" and not isinstance(value, PSLG):
        wants += ("; it is a triangulation trace, which replays on the PSLG or point set it "
                  "triangulated (the .poly or .node), not on a mesh")
    elif algorithm in ("lepp", "lawson") and isinstance(value, PSLG):
        wants += (f"; it is a {'refinement' if algorithm == 'lepp' else 'Lawson flip'} "
                  "trace, which replays on the mesh it started from, not on a PSLG")
    elif algorithm == "cuboid" and input_path is not None:
        wants += ("; it is a cuboid trace, which replays on the start mesh that "
                  "'geomexact cuboid --start FILE' writes, or with no INPUT at all (the "
                  "start rebuilt from the trace's parameters)")
    return (
        f"{trace_path} was recorded on {recorded}(digest {trace.input_digest:032x}), but "
        f"{given} gives digest {start.digest_text}: not the trace's input (step 0 "
        f"differs){wants}"
    )


def add_parser(commands: Subcommands) -> None:
    """Add the ``replay`` command."""
    names = ", ".join(format_names())
    replay_ = add_command(commands, "replay", command_replay)
    add_input_argument(
        replay_, "the mesh the trace was recorded on (2D or tetrahedral); may be left out "
        "for a cuboid trace, whose start is rebuilt from the trace's parameters",
        optional=True)
    add_trace_argument(replay_, "trace file (JSON Lines)")
    replay_.add_argument(
        "--until", type=non_negative, metavar="K", help="replay only the first K steps"
    )
    add_output_option(replay_, "result file", required=True)
    add_format_option(replay_, f"format of INPUT, one of {names}")
    add_to_option(replay_, f"format of OUT, one of {names}")
    add_writing_options(replay_, formats=False)
