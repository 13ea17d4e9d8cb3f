"""The ``geomexact`` argument parser, assembled from each command's ``add_parser``."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from typing import NoReturn, cast

from geomexact._version import __version__
from geomexact.cli import (
    census,
    check,
    convert,
    cuboid,
    demo,
    info,
    octree,
    polylla,
    refine,
    replay,
    serve,
    trace_tools,
    triangulate,
    view,
)
from geomexact.cli.arguments import Subcommands
from geomexact.cli.exit_codes import EXIT_BAD_INPUT, EXIT_CODES_HELP

COMMANDS: tuple[Callable[[Subcommands], None], ...] = (
    info.add_parser,
    check.add_parser,
    convert.add_parser,
    replay.add_parser,
    trace_tools.add_parser,
    triangulate.add_parser,
    polylla.add_parser,
    refine.add_parser,
    cuboid.add_parser,
    census.add_parser,
    octree.add_parser,
    view.add_parser,
    serve.add_parser,
    demo.add_parser,
)
"""Each command's ``add_parser``, in the order ``geomexact --help`` lists them."""


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors name the program as ``geomexact: error:``."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


KERNEL_RUNS: tuple[tuple[str, str], ...] = (
    ("lepp", "refine --method bisection, centroid or quasi (centroid and quasi with "
             "--centroid area), to --max-area, --factor or --max-edge (not --min-angle), in "
             "any region, with or without --no-delaunay and --plain-centroids, on meshes "
             "without triangle attributes; any other run uses the Python engine"),
    ("delaunay", "the Delaunay triangulation of the points in triangulate (and in refine of "
                 "a PSLG); segments, holes and regions are then inserted in Python"),
    ("cuboid", "the census (census --engine auto or compiled) of boxes whose doubled corners "
               "are integers up to 2^20; other boxes, and the cuboid command, run the exact "
               "reference"),
)
"""What each compiled kernel runs, exactly (``tests/cli`` checks the claim against
``unsupported`` of :mod:`geomexact.mesh2d.refinement.engines.compiled`)."""


def version_text() -> str:
    """``geomexact X.Y.Z``, the compiled kernels this install has and exactly what each
    runs (refinement and triangulation run their pure-Python engines without them,
    slower, same results)."""
    from geomexact.mesh2d.delaunay import compiled as delaunay_compiled
    from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
    from geomexact.mesh3d.cuboid import compiled as cuboid_compiled

    available = {"lepp": compiled_engine.AVAILABLE, "delaunay": delaunay_compiled.AVAILABLE,
                 "cuboid": cuboid_compiled.AVAILABLE}
    built = [(name, runs) for name, runs in KERNEL_RUNS if available[name]]
    if not built:
        return f"geomexact {__version__}\ncompiled kernels: none (pure-Python engines)"
    lines = [f"geomexact {__version__}",
             f"compiled kernels: {', '.join(name for name, _ in built)}"]
    lines.extend(f"  {name}: {runs}" for name, runs in built)
    return "\n".join(lines)


class _Version(argparse.Action):
    """``--version``: print :func:`version_text` and exit 0 (computed only when asked, so
    that a command does not import the kernels at start)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: object, option_string: str | None = None) -> None:
        print(version_text())
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    """The ``geomexact`` argument parser."""
    parser = _Parser(
        prog="geomexact",
        description="Exact, replayable mesh refinement on rational coordinates.",
        epilog=EXIT_CODES_HELP + "\nSee docs/cli.md for every command, option and JSON key.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and which compiled kernels are built, and exit")
    commands = cast(  # its subparsers are _Parser instances, so ArgumentParsers
        Subcommands, parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    )
    for add_parser in COMMANDS:
        add_parser(commands)
    return parser
