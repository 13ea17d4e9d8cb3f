"""``geomexact replay``: replay a trace on its input mesh, checking every digest."""

from __future__ import annotations

import argparse
import sys

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_writing_options,
    format_names,
    non_negative,
)
from geomexact.cli.errors import UsageProblem, cli_wording
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.loading import load
from geomexact.cli.reporting import print_json
from geomexact.cli.writing import write
from geomexact.errors import TraceError
from geomexact.io.trace_file import read_trace
from geomexact.mesh2d.delaunay.triangulation import vertices_mesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace


def command_replay(args: argparse.Namespace) -> int:
    """Replay a trace on its input mesh (or on the PSLG a triangulation trace started
    from), checking every digest, and write the result."""
    loaded = load(args.input, args.format, args.verbose)
    if isinstance(loaded.value, PSLG):
        start = vertices_mesh(loaded.value)
    elif isinstance(loaded.value, Mesh2):
        start = loaded.value
    else:
        raise UsageProblem(f"{args.input}: replay needs a triangle mesh or a PSLG")
    trace = read_trace(args.trace)
    if start.digest != trace.input_digest:
        raise UsageProblem(wrong_input(args.input, loaded.value, start, args.trace, trace))
    try:
        result = replay(start, trace, until=args.until)
    except TraceError as error:
        if args.until is not None and not 0 <= args.until <= len(trace):
            raise  # the inputs do not belong together: bad input, exit 2
        print(f"geomexact: trace diverged: {cli_wording(str(error))}", file=sys.stderr)
        if args.json:
            print_json(
                {"input": args.input, "trace": args.trace, "diverged": True,
                 "error": cli_wording(str(error))}
            )
        return EXIT_FAILED
    applied = len(trace) if args.until is None else args.until
    written = write(args.output, result, args.to, overwrite=args.force, numbers=args.numbers)
    if args.json:
        print_json(
            {
                "input": args.input,
                "trace": args.trace,
                "diverged": False,
                "trace_steps": len(trace),
                "steps_applied": applied,
                "input_digest": start.digest_text,
                "final_digest": result.digest_text,
                "vertices": result.vertex_count,
                "triangles": result.triangle_count,
                "written": [str(path) for path in written],
            }
        )
    else:
        print(
            f"replayed {applied} of {len(trace)} steps: {result.vertex_count} vertices, "
            f"{result.triangle_count} triangles, digest {result.digest_text} (all digests match)"
        )
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def wrong_input(
    input_path: str, value: PSLG | Mesh2, start: Mesh2, trace_path: str, trace: Trace
) -> str:
    """Why ``trace`` does not replay on ``input_path``: the input it was recorded on (its
    name when the trace header has it, and digest), this one's digest, and what kind of
    input the trace wants."""
    recorded = f"{trace.input_name!r} " if trace.input_name else ""
    wants = ""
    algorithm = trace.parameter("algorithm")
    if algorithm == "delaunay" and not isinstance(value, PSLG):
        wants = ("; it is a triangulation trace, which replays on the PSLG or point set it "
                 "triangulated (the .poly or .node), not on a mesh")
    elif algorithm in ("lepp", "lawson") and isinstance(value, PSLG):
        wants = (f"; it is a {'refinement' if algorithm == 'lepp' else 'Lawson flip'} "
                 "trace, which replays on the mesh it started from, not on a PSLG")
    return (
        f"{trace_path} was recorded on {recorded}(digest {trace.input_digest:032x}), but "
        f"{input_path} gives digest {start.digest_text}: not the trace's input{wants}"
    )


def add_parser(commands: Subcommands) -> None:
    """Add the ``replay`` command."""
    formats = format_names()
    names = ", ".join(formats)
    replay_ = add_command(commands, "replay", command_replay,
                          "replay a trace on its input mesh, checking digests")
    replay_.add_argument("input", metavar="INPUT", help="the mesh the trace was recorded on")
    replay_.add_argument("trace", metavar="TRACE", help="trace file (JSON Lines)")
    replay_.add_argument(
        "--until", type=non_negative, metavar="K", help="replay only the first K steps"
    )
    replay_.add_argument("-o", "--output", required=True, metavar="OUT", help="result file")
    replay_.add_argument(
        "--format", choices=formats, metavar="F", help=f"format of INPUT, one of {names}"
    )
    replay_.add_argument(
        "--to", choices=formats, metavar="F", help=f"format of OUT, one of {names}"
    )
    add_writing_options(replay_, formats=False)
