"""``geomexact demo``: the README's main job on the bundled Lake Superior PSLG, as a
sequence of steps."""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import attrs

from geomexact import io
from geomexact.cli.arguments import Subcommands, add_command, add_force_flag, add_json_flag
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.kinds import Value
from geomexact.cli.provenance import provenance
from geomexact.cli.reporting import print_json, print_table
from geomexact.cli.summaries import pslg_summary
from geomexact.cli.writing import write
from geomexact.errors import OverwriteError
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary
from geomexact.trace.record import Trace

DEMO_INPUT = "superior.poly"
DEMO_SOURCE = "Unity-Technologies/triangle.net @ 730f6c4, Data/superior.poly"


@attrs.define
class DemoRun:
    """State shared by the demo's steps: where to write, what was made, what to report."""

    directory: Path
    force: bool
    pslg: PSLG | None = None
    mesh: Mesh2 | None = None
    start: Mesh2 | None = None  # where the trace of the last stage starts (for the viewer)
    trace: Trace | None = None  # the trace of the last stage, ending at ``mesh``
    report: dict[str, Any] = attrs.Factory(dict)
    written: list[Path] = attrs.Factory(list)
    replays: dict[str, str] = attrs.Factory(dict)  # trace file -> the file it replays on
    provenance: dict[str, Any] = attrs.Factory(dict)  # what its traces record of the run

    def write_run_trace(self, name: str, trace: Trace, input_name: str) -> None:
        """Write ``trace`` to ``directory/name``, recording the run and the file it
        replays on (``input_name``, written beside it)."""
        path = self.directory / name
        recorded = attrs.evolve(trace, parameters={**dict(trace.parameters),
                                                   **self.provenance},
                                input_name=input_name)
        write_trace(path, recorded, overwrite=self.force)
        self.written.append(path)
        self.replays[name] = input_name

    def write(self, name: str, value: Value, format: str) -> None:
        """Write ``value`` exactly to ``directory/name``."""
        self.written.extend(
            write(self.directory / name, value, format, overwrite=self.force, numbers="exact")
        )


@attrs.frozen
class DemoStep:
    """One stage of the demo: a name, the files it writes in the output directory
    (checked before anything is written) and the function doing it."""

    name: str
    outputs: tuple[str, ...]
    run: Callable[[DemoRun], None]


def _demo_read(run: DemoRun) -> None:
    source = resources.files("geomexact") / "data" / DEMO_INPUT
    with resources.as_file(source) as path:
        pslg = io.read(path, format="poly")
    if not isinstance(pslg, PSLG):  # pragma: no cover - the bundled file is a PSLG
        raise UsageProblem(f"bundled {DEMO_INPUT} did not read as a PSLG")
    run.pslg = pslg
    run.report["input"] = {"file": DEMO_INPUT, "source": DEMO_SOURCE, **pslg_summary(pslg)}


def _demo_write_input(run: DemoRun) -> None:
    if run.pslg is None:
        raise RuntimeError("the demo's read step must run before write-input")
    run.write("superior.node", run.pslg, "node")
    run.write("superior.poly", run.pslg, "poly")


def _demo_triangulate(run: DemoRun) -> None:
    if run.pslg is None:
        raise RuntimeError("the demo's read step must run before triangulate")
    started = time.perf_counter()
    construction = triangulate(run.pslg)
    run.mesh = construction.mesh
    run.start, run.trace = construction.start, construction.trace
    run.report["triangulation"] = {
        **mesh_summary(construction.mesh),
        "steps": len(construction.trace),
        "seconds": round(time.perf_counter() - started, 6),
    }
    run.write("superior.1.ele", construction.mesh, "triangle")
    run.write_run_trace("superior.1.trace.jsonl", construction.trace,
                    "superior.poly")  # its vertices start the trace


DEMO_MIN_ANGLE = 30


def _demo_refine(run: DemoRun) -> None:
    """Lepp-centroid (Delaunay) refinement of the triangulation to a 30° minimum angle,
    and the Polylla polygon mesh of the result."""
    from geomexact.mesh2d.polygonal.polylla_meshing import polylla
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.refinement.criteria import MinAngle

    if run.mesh is None:
        raise RuntimeError("the demo's triangulate step must run before refine")
    result = refine(run.mesh, MinAngle(DEMO_MIN_ANGLE), method="centroid")
    run.mesh, run.start, run.trace = result.mesh, result.start, result.trace
    run.report["refinement"] = {
        "method": "centroid", "min_angle": DEMO_MIN_ANGLE,
        **mesh_summary(result.mesh), **result.stats.as_dict(),
    }
    run.write("superior.2.ele", result.mesh, "triangle")
    run.write_run_trace("superior.2.trace.jsonl", result.trace,
                    "superior.1.ele")  # the triangulation it refines
    polygons = polylla(result.mesh)
    run.report["polylla"] = {"polygons": len(polygons.polygons)}
    run.write("superior.2.polylla.off", polygons, "off")


def _demo_draw(run: DemoRun) -> None:
    """A PNG (filled by smallest angle) and the HTML viewer of the last mesh made, the
    viewer with the last stage's trace when it ends at that mesh."""
    if run.mesh is None:
        raise RuntimeError("the demo's triangulate step must run before draw")
    from geomexact.io.files import write_text_atomic
    from geomexact.viz import plot, viewer_html

    picture = run.directory / "superior.png"
    plot(run.mesh, picture, overwrite=run.force, color_by="min_angle",
         title=f"Lake Superior: {run.mesh.triangle_count:,} triangles, filled by smallest angle")
    run.written.append(picture)
    replayable = (run.start is not None and run.trace is not None
                  and run.trace.final_digest == run.mesh.digest)
    page = run.directory / "superior.html"
    text = viewer_html(
        run.start if replayable and run.start is not None else run.mesh,
        trace=run.trace if replayable else None,
        title="Lake Superior", source="superior.poly",
    )
    write_text_atomic(page, text, overwrite=run.force)
    run.written.append(page)
    run.report["draw"] = {
        "picture": str(picture),
        "viewer": str(page),
        "trace_steps": len(run.trace) if replayable and run.trace is not None else 0,
    }


DEMO_STEPS: tuple[DemoStep, ...] = (
    DemoStep("read", (), _demo_read),
    DemoStep("write-input", ("superior.node", "superior.poly"), _demo_write_input),
    DemoStep(
        "triangulate",
        ("superior.1.node", "superior.1.ele", "superior.1.neigh", "superior.1.poly",
         "superior.1.trace.jsonl"),
        _demo_triangulate,
    ),
    DemoStep(
        "refine",
        ("superior.2.node", "superior.2.ele", "superior.2.neigh", "superior.2.poly",
         "superior.2.trace.jsonl", "superior.2.polylla.off"),
        _demo_refine,
    ),
    DemoStep("draw", ("superior.png", "superior.html"), _demo_draw),
)


def command_demo(args: argparse.Namespace) -> int:
    """The README's main job on the bundled Lake Superior PSLG."""
    run = DemoRun(Path(args.output), args.force,
                  provenance=provenance(args, "auto"))  # the library's default engine
    if not args.force:
        for step in DEMO_STEPS:
            for name in step.outputs:
                if (run.directory / name).exists():
                    raise OverwriteError(str(run.directory / name))
    run.directory.mkdir(parents=True, exist_ok=True)
    for step in DEMO_STEPS:
        step.run(run)
    run.report["steps"] = [step.name for step in DEMO_STEPS]
    run.report["output_directory"] = str(run.directory)
    run.report["written"] = [str(path) for path in run.written]
    run.report["replays"] = dict(run.replays)
    if args.json:
        print_json(run.report)
        return EXIT_OK
    summary = {k: v for k, v in run.report["input"].items() if k not in {"file", "source"}}
    print_table(f"Lake Superior PSLG ({DEMO_INPUT}, from {DEMO_SOURCE})", summary)
    if "triangulation" in run.report:
        print_table("constrained Delaunay triangulation", run.report["triangulation"])
    if "refinement" in run.report:
        print_table(f"Lepp-centroid refinement to a {DEMO_MIN_ANGLE}° minimum angle",
                     run.report["refinement"])
    for path in run.written:
        print(f"wrote {path}")
    for trace, source in run.replays.items():
        print(f"{trace} replays on {source}: geomexact replay {run.directory / source} "
              f"{run.directory / trace} -o OUT")
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``demo`` command."""
    demo = add_command(commands, "demo", command_demo)
    demo.add_argument(
        "-o", "--output", default="geomexact-demo", metavar="DIR",
        help="output directory (default: geomexact-demo)",
    )
    add_force_flag(demo)
    add_json_flag(demo)
