"""What ``--help`` says of each command besides its options: its summary and examples,
in one table read without importing any command module (so ``geomexact --help`` stays
fast)."""

from __future__ import annotations

from typing import NamedTuple


class CommandSpec(NamedTuple):
    """A command (or a subcommand of ``subcommands``' parent): its help line and
    description ``summary``, the ``examples`` ending its ``--help``, and whether it takes
    ``--max-memory`` (the server bounds each job by its own ``--memory-limit-mb``)."""

    name: str
    module: str
    """Its module in ``geomexact.cli``, imported only to parse this command."""
    summary: str
    examples: tuple[str, ...]
    max_memory: bool = True
    subcommands: tuple[CommandSpec, ...] = ()


def _trace_tool(name: str, summary: str, examples: tuple[str, ...]) -> CommandSpec:
    return CommandSpec(name, "trace_tools", summary, examples)


COMMAND_TABLE: tuple[CommandSpec, ...] = (
    CommandSpec("info", "info", "print statistics of meshes, PSLGs and polygon meshes", (
        "geomexact info superior.1.ele",
        "geomexact info a.off b.vtu --json",
        "geomexact info part.stl",
    )),
    CommandSpec("check", "check", "validate a triangle, tetrahedral, mixed-cell or polygon "
                "mesh, or a PSLG (exit 1 on violations)", (
        "geomexact check superior.1.ele",
        "geomexact check mesh.vtu --strict --json",
    )),
    CommandSpec("convert", "convert", "convert a file to another format", (
        "geomexact convert superior.1.ele superior.vtu",
        "geomexact convert mesh.off mesh.pslg --exact",
        "geomexact convert input.msh output.ele --from meshio",
    )),
    CommandSpec("replay", "replay", "replay a trace on its input mesh, checking digests", (
        "geomexact replay square.off run.trace -o result.off --exact",
        "geomexact replay run.trace --until 100 -o step100.ele",
    )),
    CommandSpec("trace", "trace_tools",
                "debug with traces: show a trace, diff two, bisect a failing property", (
        "geomexact trace show run.trace",
        "geomexact trace diff input.off a.trace b.trace",
        "geomexact trace bisect input.off run.trace --fails delaunay",
    ), max_memory=False, subcommands=(
        _trace_tool("show", "the header, step counts and chosen steps of a trace", (
            "geomexact trace show run.trace",
            "geomexact trace show run.trace --steps 10-20 --json",
        )),
        _trace_tool("diff", "the first step where two traces of the same input differ", (
            "geomexact trace diff input.off a.trace b.trace",
            "geomexact trace diff input.off a.trace b.trace --picture diff.png",
        )),
        _trace_tool("bisect", "the first step after which a property fails (binary search)", (
            "geomexact trace bisect input.off run.trace --fails delaunay",
            "geomexact trace bisect input.off run.trace --fails min-angle:20 -o bisect/",
        )),
    )),
    CommandSpec("triangulate", "triangulate", "(constrained) Delaunay triangulation of "
                "points / a PSLG, or Lawson flips of a mesh", (
        "geomexact triangulate superior.poly -o superior.1.ele",
        "geomexact triangulate points.node -o points.off --trace run.trace",
        "geomexact triangulate crossing.poly --split-segments --check -o crossing.1.ele",
    )),
    CommandSpec("polylla", "polylla",
                "Polylla polygon mesh of a triangle mesh, optionally made convex", (
        "geomexact polylla superior.1.ele -o superior.polylla.off",
        "geomexact polylla mesh.off --convex --picture polylla.png -o convex.off",
    )),
    CommandSpec("refine", "refine",
                "Lepp refinement (bisection, centroid, quasi-Delaunay) to a criterion", (
        "geomexact refine superior.poly --min-angle 30 --max-area 0.01 -o superior.1.ele",
        "geomexact refine mesh.off --max-area 0.001 --circle 0.5 0.5 0.2 -o fine.off "
        "--trace run.trace",
        "geomexact refine mesh.ele --min-angle 30 --preset mellado --method quasi -o "
        "mellado.ele",
    )),
    CommandSpec("cuboid", "cuboid", "partition a 1-irregular cuboid pattern into tetrahedra "
                "(optionally improved by Joe's flips)", (
        "geomexact cuboid 5 -o pattern5.ele",
        "geomexact cuboid 4095 --improve --json",
        "geomexact cuboid 7 --final mixed -o pattern7.vtu",
    )),
    CommandSpec("census", "census", "census of 1-irregular cuboid patterns: Joe's "
                "configurations of each partition and what the improvement does", (
        "geomexact census --patterns 0-4095 --improve -o census.csv",
        "geomexact census --shape 1 1 2 --cells --json",
        "geomexact census --dask tcp://scheduler:8786 --workers 8",
    )),
    CommandSpec("octree", "octree", "mesh a box with tetrahedra by the octree mesher (refined "
                "where asked, balanced 2:1, each leaf partitioned by its pattern)", (
        "geomexact octree --refine-sphere 0.5 0.5 0.5 0.3 --surface --level 5 -o ball.ele",
        "geomexact octree --domain part.stl --level 5 --improve-quality 15 -o part.vtu",
        "geomexact octree --device mos.device --final mixed -o mos.vtu",
    )),
    CommandSpec("view", "view", "write the offline HTML viewer or a PNG/SVG/PDF picture of a "
                "mesh (and trace)", (
        "geomexact view superior.1.ele -o superior.png --color-by min-angle",
        "geomexact view superior.poly --trace run.trace -o run.html",
        "geomexact view part.vtu --clip z 0.5 -o part.png",
    )),
    CommandSpec("serve", "serve",
                "serve a directory's meshes in the viewer and refine uploads (local HTTP)", (
        "geomexact serve meshes/",
        "geomexact serve . --port 8765 --jobs 2",
    ), max_memory=False),
    CommandSpec("demo", "demo", "run the main job on the bundled Lake Superior PSLG", (
        "geomexact demo",
        "geomexact demo -o superior-run --force",
    )),
    CommandSpec("help", "help",
                "explain a command or a topic (commands, formats, exit-codes, triangle)", (
        "geomexact help refine",
        "geomexact help formats",
        "geomexact help triangle",
    ), max_memory=False),
)
"""Every command, in the order ``geomexact --help`` lists them (``tests/cli`` checks it
against what each module's ``add_parser`` registers)."""


def command_spec(path: str) -> CommandSpec:
    """The command ``path`` of :data:`COMMAND_TABLE`: a name (``"refine"``) or a command
    and its subcommand (``"trace show"``)."""
    command, *subcommands = path.split()
    spec = next(spec for spec in COMMAND_TABLE if spec.name == command)
    for name in subcommands:
        spec = next(inner for inner in spec.subcommands if inner.name == name)
    return spec
