"""The ``geomexact`` argument parser, assembled from each command's ``add_parser``: a
command's module (and the library it imports) is loaded only to parse that command;
``geomexact --help`` lists every command from ``COMMAND_TABLE`` alone."""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, NoReturn, cast

from geomexact._version import __version__
from geomexact.cli.command_table import COMMAND_TABLE
from geomexact.cli.exit_codes import EXIT_BAD_INPUT, EXIT_CODES_HELP

if TYPE_CHECKING:
    from geomexact.cli.arguments import Subcommands


def command_adder(module: str) -> Callable[[Subcommands], None]:
    """The ``add_parser`` of the command module ``module`` (imported now)."""
    loaded = importlib.import_module(f"geomexact.cli.{module}")
    adder: Callable[[Subcommands], None] = loaded.add_parser
    return adder


TRIANGLE_SWITCHES = {
    "q": "--min-angle DEG (refine; -q alone: 20)",
    "a": "--max-area A (refine; -a alone: --region-areas, each region's own)",
    "p": "none: a .poly or .pslg input is read as a PSLG (triangulate, refine)",
    "c": "--keep-convex-hull (triangulate)", "j": "none: unused vertices are kept and noted",
    "e": "none: geomexact writes edges as segments", "n": "none: the .neigh is always written",
    "Q": "none: geomexact prints a summary, --json for one object",
    "V": "-v (the reader's notes)", "z": "none: ids are read from the files as they are",
}
"""Triangle's one-letter switches, and what a geomexact command does instead."""


def triangle_switch_hint(words: Sequence[str]) -> str | None:
    """A line for users of Triangle (``-pq30a0.1``), when a word looks like its switches:
    each letter's geomexact option; None otherwise."""
    for word in words:
        glued = (len(word) > 2 and word[0] == "-" and word[1].isalpha()
                 and any(c.isdigit() or c == "." for c in word[2:]))  # -q30, -pq30a0.1
        if glued or word in ("-pq", "-pc", "-pa", "-q", "-pqa"):
            letters = [c for c in word[1:] if c.isalpha()]
            known = [f"-{c}: {TRIANGLE_SWITCHES[c]}" for c in dict.fromkeys(letters)
                     if c in TRIANGLE_SWITCHES]
            if known:
                suggestion = _refine_suggestion(word[1:])
                return (f"geomexact: {word} looks like Triangle's switches; here: "
                        + "; ".join(known) + " (see geomexact COMMAND --help)"
                        + (f"; try: geomexact refine INPUT {suggestion}" if suggestion
                           else ""))
    return None


def _refine_suggestion(switches: str) -> str:
    """The refine options of Triangle's ``q`` and ``a`` switches (``q30a0.01`` ->
    ``--min-angle 30 --max-area 0.01``; ``q`` alone is Triangle's 20°, ``a`` alone the
    region list's areas), or empty when it has neither."""
    options = []
    position = 0
    while position < len(switches):
        letter = switches[position]
        end = position + 1
        while end < len(switches) and (switches[end].isdigit() or switches[end] == "."):
            end += 1
        number = switches[position + 1:end]
        if letter == "q":
            options.append(f"--min-angle {number or '20'}")
        elif letter == "a":
            options.append(f"--max-area {number}" if number else "--region-areas")
        position = end
    return " ".join(options)


TOP_LEVEL_MORE = """
examples:
  geomexact demo
  geomexact refine superior.poly --min-angle 30 --max-area 0.01 -o superior.1.ele
  geomexact view superior.1.ele -o superior.html

more help: geomexact help TOPIC -- a command (geomexact help refine), or commands,
formats, exit-codes, triangle (Triangle's switches and the options that replace them)
"""
"""The end of ``geomexact --help``: examples and where the rest of the help is."""


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors name the program as ``geomexact: error:``."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


KERNEL_RUNS: tuple[tuple[str, str], ...] = (
    ("lepp", "refine --method bisection, centroid or quasi (with every --centroid), to "
             "--max-area, --factor, --max-edge, --min-angle or --region-areas, or several "
             "of them (the sizes together, with or without --min-angle), in any region, "
             "with or without --no-delaunay and --plain-centroids, with every --preset and "
             "rule (--order, --second-longest-rule, --factor-stop), with triangle or vertex "
             "attributes or without; and replay of the traces it records; any other run "
             "(an API criterion of another angle) uses the reference engine"),
    ("delaunay", "the Delaunay triangulation of the points in triangulate (and in refine of "
                 "a PSLG), then its segments (recovered by flips), the Lawson pass and the "
                 "carving of the exterior and holes; crossing segments to split and region "
                 "seeds run in Python"),
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


def chosen_command(argv: Sequence[str]) -> str | None:
    """The command named on the command line ``argv`` (its first word that is not an
    option: the top-level options take no value), or None."""
    for word in argv:
        if not word.startswith("-"):
            return word
    return None


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """The ``geomexact`` argument parser.  Without ``argv`` every command is complete;
    with it, only the command it names is (its module imported) and the others are listed
    with their help line only, enough to parse ``argv``."""
    parser = _Parser(
        prog="geomexact",
        description="Exact, replayable mesh refinement on rational coordinates.",
        epilog=EXIT_CODES_HELP + TOP_LEVEL_MORE,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and which compiled kernels are built, and exit")
    commands = cast(  # its subparsers are _Parser instances, so ArgumentParsers
        "Subcommands", parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    )
    wanted = None if argv is None else chosen_command(argv)
    for spec in COMMAND_TABLE:
        if argv is None or spec.name == wanted:
            command_adder(spec.module)(commands)
        else:
            commands.add_parser(spec.name, help=spec.summary)
    return parser
