"""``geomexact refine``: Lepp refinement (:mod:`geomexact.mesh2d.refinement.api`) of a triangle
mesh to a
criterion in a region, with its progress line, option parsing and trace streaming."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, cast

import attrs

from geomexact.cli import arguments
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_BUDGET, EXIT_FAILED, EXIT_OK
from geomexact.cli.kinds import wrong_kind
from geomexact.cli.loading import load, seed_warnings, triangulate_input
from geomexact.cli.memory import BYTES_PER_TRIANGLE, active_budget, size_text
from geomexact.cli.progress import add_progress_flags
from geomexact.cli.provenance import with_provenance
from geomexact.cli.reporting import print_json, print_table, violation_reports
from geomexact.cli.writing import distinct_outputs, write, write_output
from geomexact.errors import OverwriteError
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.delaunay.triangulation import DelaunayEngine, is_delaunay
from geomexact.mesh2d.engine_names import ENGINES, OLD_NAMES
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh2d.validation import validate
from geomexact.trace.record import Trace

if TYPE_CHECKING:
    from geomexact.mesh2d.engine_names import Engine
    from geomexact.mesh2d.refinement.driver import Method

_TRIANGULATION_ENGINE: dict[str, DelaunayEngine] = {
    "auto": "auto", "compiled": "compiled", "python": "reference", "reference": "reference",
    "fast": "auto", "transient": "reference",
}
"""``--engine`` -> the engine that triangulates a PSLG input first."""


class RefineProgress:
    """A progress line on stderr for ``refine --progress`` (issue 26, item 5): a bar over
    the work that moves -- the steps done against the steps done plus the bad triangles
    still queued, and the triangles against the criterion's estimate of the final count,
    whichever is further -- then each stage after the run by name (trace, writing,
    summary) and ``done``.  On a terminal it is redrawn in place at most ten times a
    second; otherwise a line is printed every second, and one per stage."""

    WIDTH = 24

    def __init__(self, estimate: int | None = None) -> None:
        self.estimate = estimate
        self.started = self.last = time.perf_counter()
        self.terminal = sys.stderr.isatty()
        self.interval = 0.1 if self.terminal else 1.0
        self.shown = False
        self.steps = self.triangles = 0

    def __call__(self, progress: Any) -> None:
        now = time.perf_counter()
        if now - self.last < self.interval:
            return
        self.last = now
        self.show(progress.steps, progress.triangles, progress.pending)

    def fraction(self, steps: int, triangles: int, pending: int) -> float:
        """How far the run is, below 1 while triangles are queued."""
        done = steps / (steps + pending) if steps + pending else 0.0
        if self.estimate:
            done = max(done, triangles / self.estimate)
        return min(done, 0.99) if pending else 1.0

    def show(self, steps: int, triangles: int, pending: int) -> None:
        self.steps, self.triangles = steps, triangles
        filled = int(self.WIDTH * self.fraction(steps, triangles, pending))
        bar = "#" * filled + "." * (self.WIDTH - filled)
        expected = (f" (~{self.estimate:,} expected)"
                    if self.estimate and pending else "")
        self._line(f"refine [{bar}] {steps:,} steps, {triangles:,} triangles{expected}, "
                   f"{pending:,} to fix")

    def stage(self, name: str) -> None:
        """The run is over: ``name`` is what the command does now."""
        self._line(f"refine [{'#' * self.WIDTH}] {self.steps:,} steps, "
                   f"{self.triangles:,} triangles; {name}")

    def done(self) -> None:
        self._line(f"refine [{'#' * self.WIDTH}] {self.steps:,} steps, "
                   f"{self.triangles:,} triangles; done", final=True)

    def _line(self, text: str, *, final: bool = False) -> None:
        line = f"{text}, {time.perf_counter() - self.started:.1f} s"
        if self.terminal:
            print("\r" + line + "\x1b[K", end="\n" if final else "", file=sys.stderr,
                  flush=True)
        else:
            print(line, file=sys.stderr, flush=True)
        self.shown = True


def step_limit(text: str) -> int | Literal["auto"] | None:
    """``--max-steps``: an integer >= 0, ``auto`` (the default budget) or ``none`` (no
    limit at all)."""
    word = text.strip().lower()
    if word == "none":
        return None
    if word == "auto":
        return "auto"
    return arguments.non_negative(text)


def _refine_criterion(args: argparse.Namespace, region_areas: Any = None) -> Any:
    """The criterion of the goal options: one, or several combined (a triangle is refined
    while it fails any: the minimum angle first, then the area, then the edge length, as
    Triangle's ``-q`` with ``-a``).  ``--factor`` stops the whole run, so it stands alone."""
    from geomexact.kernel.numbers import parse_rational
    from geomexact.mesh2d.refinement import criteria

    given = [name for name in ("min_angle", "max_area", "max_edge")
             if getattr(args, name) is not None]
    if args.factor is not None:
        if region_areas is not None:
            given.append("region_areas")
        if given:
            raise UsageProblem(f"--factor stops the run when the region's mean area is "
                               f"reached: it does not combine with "
                               f"{', '.join('--' + n.replace('_', '-') for n in given)}")
        return criteria.AverageAreaFactor(parse_rational(args.factor))
    if not given and region_areas is None:
        raise UsageProblem("give a goal: --min-angle, --max-area, --max-edge, "
                           "--region-areas (any of them together) or --factor")
    kinds: dict[str, Any] = {"min_angle": criteria.MinAngle, "max_area": criteria.MaxArea,
                             "max_edge": criteria.MaxEdgeLength}
    members = [kinds[name](parse_rational(getattr(args, name))) for name in given]
    if region_areas is not None:
        members.append(region_areas)
    return members[0] if len(members) == 1 else criteria.AnyOf(tuple(members))


def _region_areas(args: argparse.Namespace, value: Any) -> Any:
    """With ``--region-areas``: the maximum areas of the input PSLG's regions (Triangle's
    ``-a`` without a number); a usage problem when it has none."""
    if not args.region_areas:
        return None
    from geomexact.mesh2d.refinement.criteria import region_areas_of

    areas = [seed for seed in value.regions if seed.max_area is not None] if isinstance(
        value, PSLG) else []
    if not areas:
        raise UsageProblem(f"{args.input}: --region-areas needs a PSLG whose region list "
                           "gives maximum areas (a .poly region line 'number x y attribute "
                           "area'), and this input has none")
    return region_areas_of(value)


def _polygon_region_vertices(path: str, format: str | None, verbose: bool) -> list[Any]:
    """The vertices of a polygon file: a polygon mesh with one polygon (e.g. OFF), or a
    PSLG whose segments form one closed loop (or, without segments, its vertices in order)."""
    loaded = load(path, format, verbose)
    value = loaded.value
    if isinstance(value, PolygonMesh):
        if len(value.polygons) != 1:
            raise UsageProblem(f"{path}: a polygon region needs one polygon, the file has "
                               f"{len(value.polygons)}")
        return [value.vertices[i] for i in value.polygons[0]]
    if isinstance(value, PSLG):
        if not value.segments:
            return list(value.vertices)
        following: dict[int, int] = {}
        for u, v, _ in value.segments:
            if u in following:
                raise UsageProblem(f"{path}: the segments do not form one closed loop")
            following[u] = v
        loop = [value.segments[0][0]]
        while len(loop) <= len(following):
            nxt = following.get(loop[-1])
            if nxt is None:
                raise UsageProblem(f"{path}: the segments do not form one closed loop")
            if nxt == loop[0]:
                break
            loop.append(nxt)
        if len(loop) != len(following):
            raise UsageProblem(f"{path}: the segments do not form one closed loop")
        return [value.vertices[i] for i in loop]
    raise UsageProblem(f"{path}: a polygon region must be a polygon (OFF polygon mesh, or a "
                       "PSLG whose segments form one loop), not a triangle mesh")


def _refine_region(args: argparse.Namespace) -> Any:
    from geomexact.kernel.numbers import parse_rational
    from geomexact.mesh2d.refinement import regions

    if args.circle is not None:
        x, y, radius = (parse_rational(text) for text in args.circle)
        return regions.Circle(x, y, radius)
    if args.rectangle is not None:
        x, y, width, height = (parse_rational(text) for text in args.rectangle)
        return regions.Rectangle(x, y, width, height)
    if args.centred_rectangle is not None:
        x, y, width, height = (parse_rational(text) for text in args.centred_rectangle)
        return regions.Rectangle(x - width / 2, y - height / 2, width, height)
    if args.polygon is not None:
        return regions.Polygon(_polygon_region_vertices(args.polygon, None, args.verbose))
    return regions.Whole()


def _refine_method(args: argparse.Namespace) -> tuple[Method, str | None]:
    """The Lepp method: ``--method``, or the one that fits the criterion (centroid for a
    minimum angle, which bisection cannot meet; else bisection), with a note when it was
    chosen for the criterion."""
    if args.method is not None:
        chosen: Method = args.method
        return chosen, None
    if args.min_angle is not None:
        return "centroid", ("--min-angle without --method: using --method centroid "
                            "(Lepp-bisection does not raise angles)")
    return "bisection", None


def _delaunay_guaranteed(method: str, no_delaunay: bool, start: Mesh2, *,
                         triangulated: bool) -> bool:
    """Whether the refinement keeps the mesh (constrained) Delaunay by construction:
    Lepp-bisection and Lepp-centroid legalize around every new vertex, so they keep a
    Delaunay start Delaunay (``specs/refine.md``); quasi-Delaunay and ``--no-delaunay`` do
    not.  The start is Delaunay when this command triangulated it, else it is checked
    (exactly; the input, not the larger result)."""
    if method == "quasi" or no_delaunay:
        return False
    return triangulated or is_delaunay(start)


def _region_mesh(mesh: Mesh2, region: Any) -> Mesh2:
    """The triangles of ``mesh`` in ``region`` (a vertex inside) as a mesh of their own
    (Pineda's ``-print_region``)."""
    from geomexact.mesh2d.transient import mesh_from_triangles

    chosen = [t for t in mesh.triangles()
              if any(region.contains(mesh.point(v)) for v in t)]
    ids = {v: i for i, v in enumerate(sorted({v for t in chosen for v in t}))}
    return mesh_from_triangles([mesh.point(v) for v in ids],
                               [[ids[v] for v in t] for t in chosen])


def _second_longest_rule(args: argparse.Namespace) -> Any:
    """``--second-longest-rule``, or ``centroid`` for ``--plain-centroids``."""
    if args.plain_centroids:
        if args.second_longest_rule not in (None, "centroid"):
            raise UsageProblem("--plain-centroids contradicts --second-longest-rule "
                               f"{args.second_longest_rule}")
        return "centroid"
    return args.second_longest_rule


@attrs.frozen
class RefineOutputs:
    """The files one ``refine`` run writes (None: not asked for): ``-o`` (``mesh``), the
    trace, the Polylla meshes (of the result, of the input, its non-convex polygons and
    its convex decomposition), the region's input triangles and the directory of every
    intermediate mesh."""

    mesh: str | None
    trace: str | None
    polylla: str | None
    polylla_input: str | None = None
    polylla_reflex: str | None = None
    polylla_convex: str | None = None
    print_region: str | None = None
    print_iter: str | None = None

    def files(self, to: str | None) -> list[tuple[str, str | None, str | None]]:
        """(option, path, format) of every single file (``to``: the mesh's ``--to``), for
        the distinctness and overwrite checks."""
        return [("-o", self.mesh, to), ("--trace", self.trace, "file"),
                ("--polylla", self.polylla, None), ("--polylla", self.polylla_input, None),
                ("--polylla", self.polylla_reflex, None),
                ("--polylla", self.polylla_convex, None),
                ("--print-region", self.print_region, None)]


def _refine_outputs(args: argparse.Namespace) -> RefineOutputs:
    """The outputs asked for, checked: distinct, and none overwritten without --force.
    ``-o DIR/`` is Pineda's ``-output DIR -filename NAME``: DIR/NAME.off and, with
    ``--polylla``, the Polylla meshes of the input and of the result beside it, and as
    his program does the result's non-convex polygons and its convex decomposition."""
    outputs = RefineOutputs(args.output, args.trace, args.polylla,
                            print_region=args.print_region, print_iter=args.print_iter)
    if args.output and (args.output.endswith(("/", "\\")) or Path(args.output).is_dir()):
        stem = args.filename or Path(args.input).name.split(".")[0]
        directory = Path(args.output)
        directory.mkdir(parents=True, exist_ok=True)
        outputs = attrs.evolve(outputs, mesh=str(directory / f"{stem}.off"))
        if args.polylla is not None:
            outputs = attrs.evolve(
                outputs, polylla=str(directory / f"{stem}_polylla.off"),
                polylla_input=str(directory / f"{stem}_input_polylla.off"),
                polylla_reflex=str(directory / f"{stem}_polylla_reflex.off"),
                polylla_convex=str(directory / f"{stem}_polylla_convex.off"))
    elif args.filename:
        raise UsageProblem("--filename names the files of --output DIR (a directory)")
    if outputs.polylla == "":
        raise UsageProblem("--polylla without a file name needs --output DIR")
    files = outputs.files(args.to)
    distinct_outputs(files)
    for _, path, _ in files:
        if path and Path(path).exists() and not args.force:
            raise OverwriteError(str(path))
    if outputs.print_iter and not args.force:
        existing = sorted(Path(outputs.print_iter).glob("step-*.off"))
        if existing:
            raise OverwriteError(str(existing[0]))
    return outputs


def _refine_input(args: argparse.Namespace, loaded: Any) -> tuple[Mesh2, Any, list[str]]:
    """The mesh to refine (a PSLG triangulated first), that triangulation (or None) and
    its notes."""
    if isinstance(loaded.value, PSLG):
        construction = triangulate_input(
            loaded, engine=_TRIANGULATION_ENGINE[args.engine],
            split_hint="refine does not split them: run 'geomexact triangulate "
                       "--split-segments' first and refine its mesh",
        )
        return construction.mesh, construction, seed_warnings(loaded, construction)
    if isinstance(loaded.value, Mesh2):
        return loaded.value, None, []
    raise wrong_kind(args.input, loaded.value, "refine", "2D triangle meshes and PSLGs")


def _whole_trace(result: Any, construction: Any, args: argparse.Namespace) -> Trace:
    """The run's trace, from the PSLG's vertices when it was triangulated first, with
    the command's provenance."""
    trace: Trace = result.trace
    if construction is not None:
        first = construction.trace
        trace = Trace(first.input_digest, (*first.steps, *trace.steps),
                      (*first.digests, *trace.digests),
                      {**dict(trace.parameters), "triangulation": dict(first.parameters),
                       "triangulation_steps": len(first)}, trace.version)
    return with_provenance(trace, args, engine=args.engine, input_path=args.input)


def _write_outputs(outputs: RefineOutputs, args: argparse.Namespace, start: Mesh2,
                   result: Any, trace: Trace, region: Any,
                   progress: RefineProgress | None) -> list[Path]:
    """Write every output asked for; the paths written."""
    def stage(name: str) -> None:
        if progress is not None:
            progress.stage(name)

    def put(path: str | Path, value: Any, to: str | None = None,
            numbers: Any = args.numbers) -> list[Path]:
        return write(path, value, to, overwrite=args.force, numbers=numbers)

    if outputs.mesh:
        stage(f"writing {outputs.mesh}")
    written = write_output(args, outputs.mesh, result.mesh, "refined mesh")
    if outputs.trace:
        stage(f"writing {outputs.trace}")
        write_trace(outputs.trace, trace, overwrite=args.force)
        written.append(Path(outputs.trace))
    if outputs.polylla:
        stage("Polylla")
        written += _write_polylla(outputs, args, start, result.mesh, put)
    if outputs.print_region:
        written += put(outputs.print_region, _region_mesh(start, region))
    if outputs.print_iter:
        from geomexact.trace.playback import replay_iter

        directory = Path(outputs.print_iter)
        directory.mkdir(parents=True, exist_ok=True)
        width = max(6, len(str(len(result.trace))))
        snapshots = [result.start, *replay_iter(result.start, result.trace)]
        for index, snapshot in enumerate(snapshots):
            written += put(directory / f"step-{index:0{width}d}.off", snapshot, "off",
                           numbers="exact")
    return written


def _write_polylla(outputs: RefineOutputs, args: argparse.Namespace, start: Mesh2,
                   refined: Mesh2, put: Any) -> list[Path]:
    """The Polylla mesh of the result, and as asked of the input, its non-convex
    polygons and its convex decomposition."""
    from geomexact.mesh2d.polygonal.polylla_meshing import polylla

    assert outputs.polylla
    polygons = polylla(refined)
    written: list[Path] = put(outputs.polylla, polygons)
    if outputs.polylla_input:
        written += put(outputs.polylla_input, polylla(start))
    if outputs.polylla_reflex and outputs.polylla_convex:
        from geomexact.mesh2d.polygonal.convex import convex_decomposition
        from geomexact.mesh2d.polygonal.polygon_mesh import nonconvex_polygons

        reflex = PolygonMesh(vertices=polygons.vertices, polygons=tuple(
            polygons.polygons[index] for index in nonconvex_polygons(polygons)))
        written += put(outputs.polylla_reflex, reflex)
        convex = convex_decomposition(
            polygons, preset="pineda" if args.preset == "pineda" else None).mesh
        written += put(outputs.polylla_convex, convex)
    return written


def command_refine(args: argparse.Namespace) -> int:
    """Lepp refinement of a triangle mesh (a PSLG is triangulated first) to a criterion in
    a region; writes the mesh, the trace and optionally every intermediate mesh."""
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.refinement.budget import estimated_triangles
    from geomexact.mesh2d.refinement.presets import rules

    loaded = load(args.input, args.format, args.verbose)
    criterion = _refine_criterion(args, _region_areas(args, loaded.value))
    region = _refine_region(args)
    method, method_note = _refine_method(args)
    mesh, construction, seed_notes = _refine_input(args, loaded)
    notes = ([method_note] if method_note else []) + seed_notes
    outputs = _refine_outputs(args)
    estimate = estimated_triangles(mesh, criterion)  # O(T) exact: once for both budgets
    memory_steps = _memory_steps(mesh, estimate)  # the run stops there: exit 3
    show = args.progress if args.progress is not None else sys.stderr.isatty()
    progress = RefineProgress(estimate or None) if show else None
    chosen = rules(args.preset, centroid=args.centroid, order=args.order,
                   second_longest_rule=_second_longest_rule(args),
                   factor_stop=args.factor_stop)
    result = refine(
        mesh, criterion, region=region, method=method, delaunay=not args.no_delaunay,
        rules=chosen, max_steps=args.max_steps, step_cap=memory_steps, on_step=progress,
        engine=cast("Engine", OLD_NAMES.get(args.engine, args.engine)),  # (the API warns
        # on an old name: the command takes them as they are)
    )
    if progress is not None:
        progress.show(result.stats.steps, result.mesh.triangle_count, 0)
    if method_note:  # after the run: a refusal stays one line
        print(f"geomexact: {method_note}", file=sys.stderr)
    written = _write_outputs(outputs, args, mesh, result, _whole_trace(result, construction,
                                                                       args),
                             region, progress)
    if progress is not None:
        progress.stage("checking and summarising" if args.check else "summarising")
    violations = validate(result.mesh) if args.check else []
    checked = args.check_delaunay or not _delaunay_guaranteed(
        method, args.no_delaunay, mesh, triangulated=construction is not None)
    summary = mesh_summary(result.mesh, check_delaunay=checked)
    not_delaunay = args.check_delaunay and not summary["is_delaunay"]
    if progress is not None:
        progress.done()
    report = _refine_report(args, result, method, criterion, region, summary, checked,
                            construction is not None, violations, written, notes)
    if args.json:
        print_json(report)
    else:
        _print_refine_text(args, result, method, summary, checked, written, violations)
    memory_stop = _say_why_it_stopped(args, result, memory_steps)
    if not_delaunay:
        print("geomexact: the result is not Delaunay", file=sys.stderr)
    if violations or not_delaunay:
        return EXIT_FAILED
    return EXIT_BUDGET if result.stats.status == "budget" or memory_stop else EXIT_OK


def _refine_report(args: argparse.Namespace, result: Any, method: str, criterion: Any,
                   region: Any, summary: dict[str, Any], checked: bool, triangulated: bool,
                   violations: list[Any], written: list[Path],
                   notes: list[str]) -> dict[str, Any]:
    """The ``--json`` report of a run."""
    stats = result.stats
    report: dict[str, Any] = {
        "input": args.input,
        "triangulated": triangulated,
        "method": method,
        "criterion": criterion.parameters(),
        "region": region.parameters(),
        **summary,
        "delaunay_checked": checked,
        "steps": stats.steps,
        "seconds": round(stats.seconds, 6),
        "status": stats.status,
        "bisections": stats.bisections,
        "centroids": stats.centroids,
        "flips": stats.flips,
        "left": [list(t) for t in stats.left],
        "left_reasons": list(stats.left_reasons),
        "waiting": len(stats.waiting),
        "valid": not violations if args.check else None,
        "written": [str(path) for path in written],
        "notes": notes,
        "violations": violation_reports(violations),
    }
    return report


def _print_refine_text(args: argparse.Namespace, result: Any, method: str,
                       summary: dict[str, Any], checked: bool, written: list[Path],
                       violations: list[Any]) -> None:
    """The text report of a run."""
    stats = result.stats
    title = (f"{args.input}: Lepp-{method} refinement, {stats.steps} steps in "
             f"{stats.seconds:.3f} s, {stats.status}")
    rows = {key: value for key, value in summary.items() if key != "total_area"}
    if not checked:
        rows["is_delaunay"] = "not checked (guaranteed by the method; --check-delaunay)"
    rows["left"] = len(stats.left)
    print_table(title, rows)
    for path in written if len(written) <= 20 else written[:2]:
        print(f"wrote {path}")
    if len(written) > 20:
        print(f"wrote {len(written) - 2} more files")
    for violation in violations:
        print(f"  {violation}")


def _say_why_it_stopped(args: argparse.Namespace, result: Any, memory_steps: int) -> bool:
    """One line on stderr for a run that stopped before meeting its criterion (the memory
    budget, the default step budget, a step limit) and for the triangles left; True when
    the memory budget stopped it."""
    stats = result.stats
    memory_stop: bool = stats.status == "budget" and dict(result.trace.parameters).get(
        "step_budget") == memory_steps
    if memory_stop:
        budget = active_budget()
        print(f"geomexact: refine stopped at its memory budget ({stats.steps} steps, "
              f"{result.mesh.triangle_count} triangles: about {size_text(budget.limit)}, "
              f"{budget.source}); the partial result is written (a valid mesh, not yet "
              "meeting the criterion everywhere); give a larger --max-memory to go on",
              file=sys.stderr)
    elif stats.status == "budget":
        print(f"geomexact: refine stopped at its default step budget ({stats.steps} steps "
              "= 100 x (input triangles + the criterion's estimate) + 10000): this "
              "refinement may not end (specs/refine.md lists the known cases); the partial "
              "result is written; pass --max-steps none to lift the budget, or --max-steps "
              "N", file=sys.stderr)
    elif stats.status == "step-limit" and not stats.waiting:  # e.g. a region-wide criterion
        print(f"geomexact: refine stopped at the step limit ({args.max_steps} steps): some "
              "triangles may not meet the criterion", file=sys.stderr)
    summary_of_left = stats.left_summary()
    if summary_of_left is not None:
        print(f"geomexact: {summary_of_left}", file=sys.stderr)
    return memory_stop


def _memory_steps(mesh: Mesh2, estimate: int) -> int:
    """Refuse (exit 2) a refinement whose criterion asks for more triangles (its
    ``estimate``) than the memory budget holds; else the steps the budget allows (each
    adds at most two triangles)."""
    budget = active_budget()
    budget.refuse_beyond(
        f"refining to about {estimate + mesh.triangle_count:,} triangles",
        (estimate + mesh.triangle_count) * BYTES_PER_TRIANGLE,
        "ask for fewer triangles (a larger --max-area, --max-edge or --factor)")
    room = budget.items(BYTES_PER_TRIANGLE) - mesh.triangle_count
    return max(0, room // 2)


GOAL_LIMITS = (
    arguments.ValueOption("--max-area", "A", "largest triangle area allowed"),
    arguments.ValueOption("--factor", "F", "refine the largest triangles until the region's "
                          "mean area is at most F times its initial mean"),
    arguments.ValueOption("--min-angle", "DEG", "smallest angle allowed, in degrees (0 < DEG "
                          "< 60; centroid or quasi method, or bisection with --max-steps)"),
    arguments.ValueOption("--max-edge", "L", "longest edge allowed"),
)
"""The goal options that take a number (in ``--help`` order, before ``--region-areas``)."""

RULE_OPTIONS = (
    arguments.ChoiceOption("--order", ("worst-first", "passes"),
                           "worst-first (default: the worst bad triangle first) or passes "
                           "(the bad triangles in passes, each in vertex-id order)"),
    arguments.ChoiceOption("--second-longest-rule",
                           ("bisect-second", "centroid", "bisect-longest"),
                           "a terminal triangle whose second-longest edge is a constraint: "
                           "bisect that edge (default), ignore it (insert the centroid), or "
                           "bisect the longest edge (Mellado's literal rule; it may not end)"),
    arguments.ChoiceOption("--factor-stop", ("action", "target"),
                           "--factor: check the mean after every action (default) or after "
                           "each refined triangle (Pineda, Alg. 3)"),
    arguments.ChoiceOption("--centroid", ("area", "area-exact", "vertices", "midpoint"),
                           "point inserted in a terminal quadrilateral: area centroid rounded "
                           "to 24 bits (default), exact area centroid (slow: coordinates "
                           "grow), the mean of the four vertices, or midpoint: bisect the "
                           "terminal edge instead (Mellado's centroid=false variant)"),
)
"""The rule options (each overrides ``--preset``'s rule; None: the preset's, or the
default named in its help)."""

EXTRA_OUTPUTS = (
    arguments.ValueOption("--filename", "NAME", "with -o DIR (a directory, Pineda's -output): "
                          "the files' name, DIR/NAME.off (default: the input's name)"),
    arguments.ValueOption("--print-region", "FILE", "write the input's triangles in the "
                          "region as a mesh file (Pineda's -print_region)"),
    arguments.ValueOption("--print-iter", "DIR", "write the mesh before and after every step "
                          "to DIR/step-NNNNNN.off (exact)"),
)
"""The options of the files refine writes besides the mesh, its trace and ``--polylla``."""


def add_parser(commands: arguments.Subcommands) -> None:
    """Add the ``refine`` command."""
    refine_ = arguments.add_command(commands, "refine", command_refine)
    arguments.add_input_argument(refine_, arguments.MESH_OR_PSLG)
    arguments.add_output_option(refine_)
    goal = refine_.add_argument_group(
        "goal", "one or more of --min-angle, --max-area, --max-edge, --region-areas (a "
        "triangle is refined while it fails any, like Triangle's -q30a0.01), or --factor "
        "alone")
    arguments.add_options(goal, GOAL_LIMITS)
    goal.add_argument("--region-areas", action="store_true",
                      help="the largest area of each region of a .poly input, from its "
                           "region list (Triangle's -a without a number)")
    where = refine_.add_mutually_exclusive_group()
    where.add_argument("--circle", nargs=3, metavar=("X", "Y", "R"),
                       help="refine only triangles with a vertex in this disk")
    where.add_argument("--rectangle", nargs=4, metavar=("X", "Y", "W", "H"),
                       help="refine only triangles with a vertex in [X, X+W] x [Y, Y+H]")
    where.add_argument("--centred-rectangle", nargs=4, metavar=("CX", "CY", "W", "H"),
                       help="as --rectangle, given by its centre and full sizes (Pineda's "
                            "-rectangle)")
    where.add_argument("--polygon", metavar="FILE",
                       help="refine only triangles with a vertex in this polygon (OFF with "
                            "one polygon, or a PSLG whose segments form one loop)")
    refine_.add_argument("--method", choices=("bisection", "centroid", "quasi"),
                         help="Lepp method (default: centroid for --min-angle, which "
                              "bisection cannot meet, else bisection)")
    refine_.add_argument("--no-delaunay", action="store_true",
                         help="never flip (no legalization, no quasi-Delaunay flips)")
    refine_.add_argument("--preset", choices=("pineda", "mellado"),
                         help="the rules of a paper's program (docs/papers.md): pineda "
                              "(--second-longest-rule centroid --factor-stop target), "
                              "mellado (--centroid vertices --order passes); each rule "
                              "option below overrides it")
    arguments.add_options(refine_, RULE_OPTIONS)
    refine_.add_argument("--plain-centroids", action="store_true",
                         help="do not bisect a constraint second-longest edge of a terminal "
                              "triangle; always insert the centroid (= --second-longest-rule "
                              "centroid)")
    arguments.add_engine_option(
        refine_, (*ENGINES, *OLD_NAMES),
        "auto (default: compiled where it applies, else the pure Python engine), compiled "
        "(the kernel; an error where it does not apply), python or reference (the pure "
        "ops); all record the same trace; fast and transient are old names of auto and "
        "reference")
    refine_.add_argument("--max-steps", type=step_limit, metavar="N", default="auto",
                         help="stop after N steps (status 'step-limit'); default: a budget "
                              "of 100 x (input triangles + the criterion's estimate) + "
                              "10000 steps (status 'budget', exit code 3), also "
                              "'auto'; 'none': no limit")
    arguments.add_trace_output(refine_,
                               "write the trace (JSON Lines; from a PSLG: from its vertices)")
    refine_.add_argument("--polylla", metavar="OFF", nargs="?", const="",
                         help="also write the Polylla polygon mesh of the result (OFF); "
                              "with -o DIR and no file name: DIR/NAME_polylla.off, its "
                              "non-convex polygons (NAME_polylla_reflex.off), its convex "
                              "decomposition (NAME_polylla_convex.off) and the input's "
                              "(NAME_input_polylla.off), as Pineda's -polylla")
    arguments.add_options(refine_, EXTRA_OUTPUTS)
    arguments.add_check_flag(refine_, "validate the result (exit 1 on violations)")
    refine_.add_argument("--check-delaunay", action="store_true",
                         help="check (exactly) that the result is (constrained) Delaunay, "
                              "exit 1 when it is not; without it the check is skipped "
                              "where the method guarantees it (bisection, centroid with "
                              "flips, from a Delaunay start): is_delaunay null")
    add_progress_flags(refine_)
    arguments.add_writing_options(refine_)
