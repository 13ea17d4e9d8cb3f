"""The ``geomexact`` command: parses arguments, calls the library, prints.

Commands: ``info``, ``check``, ``convert``, ``replay``, ``triangulate``, ``polylla``,
``refine``, ``view``, ``serve``, ``demo`` (see ``docs/cli.md``).
Exit codes: 0 success; 1 a check failed or a trace diverged; 2 bad input or usage.  Every
error geomexact raises on purpose (:class:`~geomexact.errors.GeomexactError`) and every
``OSError`` is reported as one line ``geomexact: error: …`` on stderr, never as a
traceback.  With ``--json`` a command prints exactly one JSON object on stdout.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any, NoReturn, TypeAlias

import attrs

from geomexact import __version__, io
from geomexact.delaunay import is_delaunay, make_delaunay, triangulate, vertices_mesh
from geomexact.errors import GeomexactError, OverwriteError, TraceError
from geomexact.mesh2d import Mesh2
from geomexact.numbers import format_rational
from geomexact.polymesh import PolygonMesh
from geomexact.pslg import PSLG
from geomexact.summary import mesh_summary
from geomexact.trace import Trace, read_trace, replay, write_trace
from geomexact.validate import validate

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_BROKEN_PIPE = 141  # what a shell reports for a command killed by SIGPIPE

EXIT_CODES_HELP = """\
exit codes:
  0  success
  1  check found violations, or a trace diverged during replay
  2  bad input or usage: unreadable or malformed file, wrong kind of input, refusal to
     overwrite an existing file (use --force), trace recorded on another mesh, bad option
"""

KIND_NAMES = {Mesh2: "triangle_mesh", PSLG: "pslg", PolygonMesh: "polygon_mesh"}

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh


def _kind_name(kind: type) -> str:
    return KIND_NAMES.get(kind, kind.__name__)


class UsageProblem(Exception):
    """A command given the wrong kind of input (e.g. ``check`` on a PSLG): exit 2."""


# ---------------------------------------------------------------------------------------
# output helpers
# ---------------------------------------------------------------------------------------
def _print_json(report: dict[str, Any]) -> None:
    print(json.dumps(report, indent=2, allow_nan=False))


def _print_error(message: str) -> None:
    print(f"geomexact: error: {message}", file=sys.stderr)


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that flushing it at exit raises nothing more."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # stdout without a file descriptor (e.g. captured)
        pass


def _os_error_text(error: OSError) -> str:
    if error.filename is not None and error.strerror:
        return f"{error.filename}: {error.strerror}"
    return str(error)


def _show(value: object) -> str:
    """A report value as table text (JSON keeps the value itself)."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict) and set(value) == {"x_min", "x_max", "y_min", "y_max"}:
        return f"x {value['x_min']} .. {value['x_max']}, y {value['y_min']} .. {value['y_max']}"
    return str(value)


def _print_table(title: str, rows: dict[str, Any]) -> None:
    print(title)
    width = max((len(key) for key in rows), default=0)
    for key, value in rows.items():
        print(f"  {key.replace('_', ' '):<{width}}  {_show(value)}")


# ---------------------------------------------------------------------------------------
# reading and describing inputs
# ---------------------------------------------------------------------------------------
@attrs.frozen
class Loaded:
    """A file read by :func:`io.read_with_notes`, with the format it was read as."""

    path: str
    format: str
    value: Value
    notes: tuple[str, ...]

    @property
    def kind(self) -> str:
        return _kind_name(type(self.value))


def _load(path: str, format: str | None, verbose: bool) -> Loaded:
    value, notes = io.read_with_notes(path, format=format)
    if verbose:
        for note in notes:
            print(f"geomexact: {path}: {note}", file=sys.stderr)
    return Loaded(path, format or io.detect_format(path), value, tuple(notes))


def _load_mesh(path: str, format: str | None, verbose: bool, command: str) -> Mesh2:
    loaded = _load(path, format, verbose)
    if not isinstance(loaded.value, Mesh2):
        raise UsageProblem(
            f"{path}: is a {loaded.kind.replace('_', ' ')}, but {command} needs a triangle "
            "mesh (a Triangle .ele, OFF or PSLG text file of triangles, …)"
        )
    return loaded.value


def _write(
    path: str | Path, value: Value, format: str | None, *, overwrite: bool, exact: bool
) -> list[Path]:
    """:func:`io.write`, refusing first (exit 2) a format that cannot hold ``value``."""
    name = format or io.detect_format(path)
    kinds = io.FORMATS[name].kinds
    if not isinstance(value, kinds):
        held = " or ".join(_kind_name(kind).replace("_", " ") for kind in kinds)
        kind = _kind_name(type(value)).replace("_", " ")
        raise UsageProblem(f"{path}: the {name} format holds a {held}, not a {kind}")
    return io.write(path, value, format=name, overwrite=overwrite, exact=exact)


def pslg_summary(pslg: PSLG) -> dict[str, Any]:
    """Counts and the exact bounding box (``"p/q"`` or decimal text) of a PSLG."""
    box: dict[str, str] | None = None
    if pslg.vertices:
        xs = [point.x for point in pslg.vertices]
        ys = [point.y for point in pslg.vertices]
        box = {
            "x_min": format_rational(min(xs)),
            "x_max": format_rational(max(xs)),
            "y_min": format_rational(min(ys)),
            "y_max": format_rational(max(ys)),
        }
    return {
        "vertices": len(pslg.vertices),
        "segments": len(pslg.segments),
        "holes": len(pslg.holes),
        "regions": len(pslg.regions),
        "bounding_box": box,
    }


def polygon_mesh_summary(mesh: PolygonMesh) -> dict[str, Any]:
    """Counts and the smallest and largest polygon size of a polygon mesh."""
    sizes = [len(polygon) for polygon in mesh.polygons]
    return {
        "vertices": len(mesh.vertices),
        "polygons": len(mesh.polygons),
        "min_polygon_size": min(sizes, default=None),
        "max_polygon_size": max(sizes, default=None),
    }


def summary_of(value: Value) -> dict[str, Any]:
    """The ``info`` statistics of a mesh, PSLG or polygon mesh (JSON-ready)."""
    if isinstance(value, Mesh2):
        return mesh_summary(value)
    if isinstance(value, PSLG):
        return pslg_summary(value)
    return polygon_mesh_summary(value)


def _describe(loaded: Loaded) -> dict[str, Any]:
    return {
        "file": loaded.path,
        "format": loaded.format,
        "kind": loaded.kind,
        **summary_of(loaded.value),
        "notes": list(loaded.notes),
    }


# ---------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------
def command_info(args: argparse.Namespace) -> int:
    """Statistics of each file."""
    reports = [_describe(_load(path, args.format, args.verbose)) for path in args.files]
    if args.json:
        _print_json(reports[0] if len(reports) == 1 else {"files": reports})
        return EXIT_OK
    for index, report in enumerate(reports):
        if index:
            print()
        rows = {k: v for k, v in report.items() if k not in {"file", "format", "kind", "notes"}}
        kind = report["kind"].replace("_", " ")
        _print_table(f"{report['file']} ({report['format']}, {kind})", rows)
    return EXIT_OK


def command_check(args: argparse.Namespace) -> int:
    """Validate a triangle mesh; exit 1 listing every violation."""
    mesh = _load_mesh(args.file, args.format, args.verbose, "check")
    violations = validate(mesh, allow_isolated=not args.strict)
    if args.json:
        _print_json(
            {
                "file": args.file,
                "valid": not violations,
                "vertices": mesh.vertex_count,
                "triangles": mesh.triangle_count,
                "violations": [
                    {"kind": v.kind, "message": v.message, "elements": list(v.elements)}
                    for v in violations
                ],
            }
        )
    elif violations:
        print(f"{args.file}: invalid, {len(violations)} violation(s)")
        for violation in violations:
            print(f"  {violation}")
    else:
        print(
            f"{args.file}: valid ({mesh.vertex_count} vertices, "
            f"{mesh.triangle_count} triangles, digest {mesh.digest_text})"
        )
    return EXIT_FAILED if violations else EXIT_OK


def command_convert(args: argparse.Namespace) -> int:
    """Read a file in one format and write it in another."""
    loaded = _load(args.input, args.source_format, args.verbose)
    written = _write(
        args.output, loaded.value, args.target_format, overwrite=args.force, exact=args.exact
    )
    if args.json:
        _print_json(
            {
                "input": args.input,
                "format": loaded.format,
                "kind": loaded.kind,
                "written": [str(path) for path in written],
            }
        )
    else:
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def command_replay(args: argparse.Namespace) -> int:
    """Replay a trace on its input mesh (or on the PSLG a triangulation trace started
    from), checking every digest, and write the result."""
    loaded = _load(args.input, args.format, args.verbose)
    if isinstance(loaded.value, PSLG):
        start = vertices_mesh(loaded.value)
    elif isinstance(loaded.value, Mesh2):
        start = loaded.value
    else:
        raise UsageProblem(f"{args.input}: replay needs a triangle mesh or a PSLG")
    trace = read_trace(args.trace)
    try:
        result = replay(start, trace, until=args.until)
    except TraceError as error:
        wrong_start = start.digest != trace.input_digest
        bad_until = args.until is not None and not 0 <= args.until <= len(trace)
        if wrong_start or bad_until:
            raise  # the inputs do not belong together: bad input, exit 2
        print(f"geomexact: trace diverged: {error}", file=sys.stderr)
        if args.json:
            _print_json(
                {"input": args.input, "trace": args.trace, "diverged": True, "error": str(error)}
            )
        return EXIT_FAILED
    applied = len(trace) if args.until is None else args.until
    written = _write(args.output, result, args.to, overwrite=args.force, exact=args.exact)
    if args.json:
        _print_json(
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


def command_triangulate(args: argparse.Namespace) -> int:
    """(Constrained) Delaunay triangulation of a point set or PSLG, or Lawson flips of a
    triangle mesh into a Delaunay one; writes the mesh and optionally the trace."""
    loaded = _load(args.input, args.format, args.verbose)
    started = time.perf_counter()
    if isinstance(loaded.value, Mesh2):
        mesh, trace = make_delaunay(loaded.value)
        algorithm = "lawson flips"
    elif isinstance(loaded.value, PSLG):
        construction = triangulate(
            loaded.value,
            keep_convex_hull=args.keep_convex_hull,
            split_segments=args.split_segments,
            merge_duplicates=args.merge_duplicates,
        )
        mesh, trace = construction.mesh, construction.trace
        algorithm = "constrained delaunay" if loaded.value.segments else "delaunay"
    else:
        raise UsageProblem(f"{args.input}: a polygon mesh cannot be triangulated here")
    seconds = time.perf_counter() - started
    written: list[Path] = []
    if args.output:
        written += _write(args.output, mesh, args.to, overwrite=args.force, exact=args.exact)
    if args.trace:
        trace_path = Path(args.trace)
        write_trace(trace_path, trace, overwrite=args.force)
        written.append(trace_path)
    violations = validate(mesh) if args.check else []
    delaunay_ok = is_delaunay(mesh)
    report = {
        "input": args.input,
        "algorithm": algorithm,
        **mesh_summary(mesh),
        "steps": len(trace),
        "seconds": round(seconds, 6),
        "valid": not violations,
        "written": [str(path) for path in written],
    }
    if args.json:
        _print_json(report)
    else:
        _print_table(f"{args.input}: {algorithm} in {seconds:.3f} s, {len(trace)} steps",
                     {k: v for k, v in report.items() if k not in {"input", "algorithm",
                                                                    "written", "seconds"}})
        for path in written:
            print(f"wrote {path}")
        for violation in violations:
            print(f"  {violation}")
    if args.check and (violations or not delaunay_ok):
        return EXIT_FAILED
    return EXIT_OK


# -- polylla: polygonal meshes and their convex decomposition ----------------------------
def command_polylla(args: argparse.Namespace) -> int:
    """Polylla polygon mesh of a triangle mesh (a PSLG is triangulated first), optionally
    decomposed into convex polygons; writes the polygons and optionally a picture."""
    from geomexact.convex import convex_decomposition
    from geomexact.polylla import polylla_run
    from geomexact.polymesh import mesh_stats, nonconvex_polygons

    loaded = _load(args.input, args.format, args.verbose)
    if isinstance(loaded.value, PSLG):
        mesh = triangulate(loaded.value).mesh
    elif isinstance(loaded.value, Mesh2):
        mesh = loaded.value
    else:
        raise UsageProblem(f"{args.input}: is already a polygon mesh; polylla needs a "
                           "triangle mesh (or a PSLG, which is triangulated first)")
    convex = args.convex or args.no_opt
    for path in (args.output, args.picture):
        if path and Path(path).exists() and not args.force:
            raise OverwriteError(str(path))
    started = time.perf_counter()
    run = polylla_run(mesh)
    result = run.mesh
    inserted: tuple[tuple[int, int], ...] = ()
    if convex:
        decomposition = convex_decomposition(run.mesh, criterion_one=not args.no_opt)
        result, inserted = decomposition.mesh, decomposition.inserted_edges
    seconds = time.perf_counter() - started
    violations = result.validate(mesh) if args.check else []
    written: list[Path] = []
    if args.output:
        written += _write(args.output, result, args.to, overwrite=args.force, exact=args.exact)
    if args.picture:
        from geomexact.viz import pictures

        if Path(args.picture).suffix.lower() not in pictures.PICTURE_FORMATS:
            raise UsageProblem(f"{args.picture}: the picture must end in .png, .svg or .pdf")
        title = f"{Path(args.input).name}: {'convex ' if convex else ''}Polylla mesh"
        pictures.plot(result, args.picture, overwrite=args.force, title=title,
                      highlight_edges=inserted)
        written.append(Path(args.picture))
    nonconvex = len(nonconvex_polygons(run.mesh))
    report = {
        "input": args.input,
        "triangulated": isinstance(loaded.value, PSLG),
        "vertices": mesh.vertex_count,
        "triangles": mesh.triangle_count,
        "regions": run.regions,
        "barrier_tips": len(run.barrier_tips),
        "repair_edges": len(run.repair_edges),
        "polygons": len(run.mesh.polygons),
        "nonconvex": nonconvex,
        "convex_decomposition": convex,
        "criterion_one": convex and not args.no_opt,
        "inserted_edges": len(inserted) if convex else None,
        "polygons_after": len(result.polygons) if convex else None,
        "nonconvex_after": len(nonconvex_polygons(result)) if convex else None,
        "seconds": round(seconds, 6),
        "valid": not violations if args.check else None,
        "stats": mesh_stats(result, inserted_edges=len(inserted) if convex else None),
        "written": [str(path) for path in written],
    }
    if args.json:
        report["violations"] = [{"kind": v.kind, "message": v.message,
                                 "elements": list(v.elements)} for v in violations]
        _print_json(report)
    else:
        what = "Polylla + convex decomposition" if convex else "Polylla"
        rows = {key: value for key, value in report.items()
                if key not in {"input", "stats", "written", "seconds", "convex_decomposition"}
                and value is not None}
        _print_table(f"{args.input}: {what} in {seconds:.3f} s", rows)
        for path in written:
            print(f"wrote {path}")
        for violation in violations:
            print(f"  {violation}")
    return EXIT_FAILED if violations else EXIT_OK


# -- refine: Lepp refinement (geomexact.refine) ----------------------------------------------
class _RefineProgress:
    """A progress line on stderr for ``refine --progress``: steps, triangles, queue and
    time, with a bouncing bar (the number of steps ahead is unknown).  On a terminal it is
    redrawn in place at most ten times a second; otherwise a line is printed every second."""

    WIDTH = 24

    def __init__(self) -> None:
        self.started = self.last = time.perf_counter()
        self.terminal = sys.stderr.isatty()
        self.interval = 0.1 if self.terminal else 1.0
        self.shown = False

    def __call__(self, progress: Any) -> None:
        now = time.perf_counter()
        if now - self.last < self.interval:
            return
        self.last = now
        self.show(progress.steps, progress.triangles, progress.pending)

    def show(self, steps: int, triangles: int, pending: int, *, final: bool = False) -> None:
        elapsed = time.perf_counter() - self.started
        if final:
            bar = "#" * self.WIDTH
        else:
            position = int(elapsed * 8) % (2 * self.WIDTH - 6)
            position = position if position < self.WIDTH - 3 else 2 * self.WIDTH - 6 - position
            bar = " " * position + "###" + " " * (self.WIDTH - 3 - position)
        line = (f"refine [{bar}] {steps:,} steps, {triangles:,} triangles, "
                f"{pending:,} queued, {elapsed:.1f} s")
        if self.terminal:
            print("\r" + line, end="\n" if final else "", file=sys.stderr, flush=True)
        else:
            print(line, file=sys.stderr, flush=True)
        self.shown = True


def _refine_criterion(args: argparse.Namespace) -> Any:
    from geomexact import criteria
    from geomexact.numbers import parse_rational

    if args.max_area is not None:
        return criteria.MaxArea(parse_rational(args.max_area))
    if args.factor is not None:
        return criteria.AverageAreaFactor(parse_rational(args.factor))
    if args.min_angle is not None:
        return criteria.MinAngle(parse_rational(args.min_angle))
    return criteria.MaxEdgeLength(parse_rational(args.max_edge))


def _polygon_region_vertices(path: str, format: str | None, verbose: bool) -> list[Any]:
    """The vertices of a polygon file: a polygon mesh with one polygon (e.g. OFF), or a
    PSLG whose segments form one closed loop (or, without segments, its vertices in order)."""
    loaded = _load(path, format, verbose)
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
    from geomexact import regions
    from geomexact.numbers import parse_rational

    if args.circle is not None:
        x, y, radius = (parse_rational(text) for text in args.circle)
        return regions.Circle(x, y, radius)
    if args.rectangle is not None:
        x, y, width, height = (parse_rational(text) for text in args.rectangle)
        return regions.Rectangle(x, y, width, height)
    if args.polygon is not None:
        return regions.Polygon(_polygon_region_vertices(args.polygon, None, args.verbose))
    return regions.Whole()


def _write_trace_stream(path: Path, trace: Trace, *, overwrite: bool) -> None:
    """Write a trace file line by line through a temporary file and a rename (big runs
    never hold the file's text in memory); never replaces a file unless ``overwrite``."""
    import tempfile

    from geomexact.trace import trace_lines

    if path.exists() and not overwrite:
        raise OverwriteError(str(path))
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise FileNotFoundError(2, f"cannot write {path}: directory {directory} does not exist")
    descriptor, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp",
                                             dir=directory)
    try:
        with os.fdopen(descriptor, "w", encoding="utf-8", newline="\n") as handle:
            for line in trace_lines(trace):
                handle.write(line)
                handle.write("\n")
        umask = os.umask(0o022)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        if overwrite:
            os.replace(temporary, path)
        else:
            try:
                os.link(temporary, path)
            except FileExistsError as error:
                raise OverwriteError(str(path)) from error
            os.unlink(temporary)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def command_refine(args: argparse.Namespace) -> int:
    """Lepp refinement of a triangle mesh (a PSLG is triangulated first) to a criterion in
    a region; writes the mesh, the trace and optionally every intermediate mesh."""
    from geomexact.refine import refine

    loaded = _load(args.input, args.format, args.verbose)
    criterion = _refine_criterion(args)
    region = _refine_region(args)
    construction = None
    if isinstance(loaded.value, PSLG):
        construction = triangulate(loaded.value)
        mesh = construction.mesh
    elif isinstance(loaded.value, Mesh2):
        mesh = loaded.value
    else:
        raise UsageProblem(f"{args.input}: a polygon mesh cannot be refined; give a triangle "
                           "mesh or a PSLG")
    outputs = [args.output, args.trace, args.polylla]
    for path in outputs:
        if path and Path(path).exists() and not args.force:
            raise OverwriteError(str(path))
    if args.print_iter and not args.force:
        existing = sorted(Path(args.print_iter).glob("step-*.off"))
        if existing:
            raise OverwriteError(str(existing[0]))
    progress = _RefineProgress() if args.progress else None
    result = refine(
        mesh, criterion, region=region, method=args.method, delaunay=not args.no_delaunay,
        centroid=args.centroid, constraint_midpoints=not args.plain_centroids,
        max_steps=args.max_steps, on_step=progress,
    )
    if progress is not None:
        progress.show(result.stats.steps, result.mesh.triangle_count, 0, final=True)
    trace = result.trace
    if construction is not None:  # one trace from the PSLG's vertices to the result
        first = construction.trace
        trace = Trace(first.input_digest, (*first.steps, *trace.steps),
                      (*first.digests, *trace.digests),
                      {**dict(trace.parameters), "triangulation": dict(first.parameters),
                       "triangulation_steps": len(first)}, trace.version)
    written: list[Path] = []
    if args.output:
        written += _write(args.output, result.mesh, args.to, overwrite=args.force,
                          exact=args.exact)
    if args.trace:
        _write_trace_stream(Path(args.trace), trace, overwrite=args.force)
        written.append(Path(args.trace))
    if args.polylla:
        from geomexact.polylla import polylla

        written += _write(args.polylla, polylla(result.mesh), None, overwrite=args.force,
                          exact=args.exact)
    if args.print_iter:
        from geomexact.trace import replay_iter

        directory = Path(args.print_iter)
        directory.mkdir(parents=True, exist_ok=True)
        width = max(6, len(str(len(result.trace))))
        snapshots = [result.start, *replay_iter(result.start, result.trace)]
        for index, snapshot in enumerate(snapshots):
            written += _write(directory / f"step-{index:0{width}d}.off", snapshot, "off",
                              overwrite=args.force, exact=True)
    violations = validate(result.mesh) if args.check else []
    summary = mesh_summary(result.mesh)
    stats = result.stats
    report: dict[str, Any] = {
        "input": args.input,
        "triangulated": construction is not None,
        "method": args.method,
        "criterion": criterion.parameters(),
        "region": region.parameters(),
        **summary,
        "steps": stats.steps,
        "seconds": round(stats.seconds, 6),
        "status": stats.status,
        "bisections": stats.bisections,
        "centroids": stats.centroids,
        "flips": stats.flips,
        "left": [list(t) for t in stats.left],
        "valid": not violations if args.check else None,
        "written": [str(path) for path in written],
    }
    not_delaunay = args.check_delaunay and not summary["is_delaunay"]
    if args.json:
        report["violations"] = [{"kind": v.kind, "message": v.message,
                                 "elements": list(v.elements)} for v in violations]
        _print_json(report)
    else:
        title = (f"{args.input}: Lepp-{args.method} refinement, {stats.steps} steps in "
                 f"{stats.seconds:.3f} s, {stats.status}")
        rows = {key: value for key, value in summary.items() if key != "total_area"}
        rows["left"] = len(stats.left)
        _print_table(title, rows)
        for path in written if len(written) <= 20 else written[:2]:
            print(f"wrote {path}")
        if len(written) > 20:
            print(f"wrote {len(written) - 2} more files")
        for violation in violations:
            print(f"  {violation}")
    if stats.status == "step-limit":
        print(f"geomexact: refine stopped at the step limit ({args.max_steps} steps): some "
              "triangles may not meet the criterion", file=sys.stderr)
    if stats.left:
        print(f"geomexact: {len(stats.left)} triangle(s) left below the minimum angle at "
              "input angles sharper than it", file=sys.stderr)
    if not_delaunay:
        print("geomexact: the result is not Delaunay", file=sys.stderr)
    return EXIT_FAILED if violations or not_delaunay else EXIT_OK


# -- view and serve: pictures, the HTML viewer, the local server (geomexact.viz) -----------
VIEW_FILL_CHOICES = ("none", "min-angle", "area", "region")


def command_view(args: argparse.Namespace) -> int:
    """Write the HTML viewer (``.html``) or a picture (``.png``, ``.svg``, ``.pdf``) of a
    mesh, PSLG or polygon mesh; with ``--trace``, of the trace replayed on it."""
    from geomexact.io.files import write_text_atomic
    from geomexact.viz import pictures, viewer
    from geomexact.viz.scene import DEFAULT_EXACT_BUDGET

    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix not in (".html", ".htm", *pictures.PICTURE_FORMATS):
        raise UsageProblem(f"{output}: the output must end in .html, .png, .svg or .pdf")
    if args.step is not None and not args.trace:
        raise UsageProblem("--step needs --trace")
    loaded = _load(args.input, args.format, args.verbose)
    trace = read_trace(args.trace) if args.trace else None
    fill = args.color_by.replace("-", "_")
    try:
        if suffix in (".html", ".htm"):
            text = viewer.viewer_html(
                loaded.value, trace=trace, title=args.title, source=Path(args.input).name,
                trace_source=Path(args.trace).name if args.trace else None, fill=fill,
                step=args.step, exact_budget=0 if args.no_exact else DEFAULT_EXACT_BUDGET,
                notes=loaded.notes,
            )
            write_text_atomic(output, text, overwrite=args.force)
        elif trace is not None:
            pictures.plot_step(loaded.value, trace, args.step, output, overwrite=args.force,
                               title=args.title, color_by=fill)
        else:
            pictures.plot(loaded.value, output, overwrite=args.force, title=args.title,
                          color_by=fill)
    except (TypeError, ValueError) as error:
        if isinstance(error, GeomexactError):
            raise
        raise UsageProblem(f"{args.input}: {error}") from None
    report = {
        "input": args.input,
        "format": loaded.format,
        "kind": loaded.kind,
        "trace": args.trace,
        "steps": len(trace) if trace is not None else None,
        "step": args.step if args.step is not None else (
            len(trace) if trace is not None else None),
        "output": str(output),
        "bytes": output.stat().st_size,
    }
    if args.json:
        _print_json(report)
    else:
        print(f"wrote {output}")
    return EXIT_OK


def command_serve(args: argparse.Namespace) -> int:
    """Serve a directory's meshes in the viewer, and refine uploads, until Ctrl-C."""
    from geomexact.viz import serve as serving

    options = serving.ServeOptions(
        Path(args.directory), host=args.host, port=args.port,
        max_upload_bytes=int(args.max_upload_mb * 1024 * 1024),
        time_limit=args.time_limit, jobs=args.jobs,
    )
    if not serving.is_loopback(args.host):
        print(f"geomexact: warning: listening on {args.host}: other machines can read the "
              "served files and run jobs (there is no authentication)", file=sys.stderr)

    def announce(url: str) -> None:
        print(f"serving {options.directory} at {url} (Ctrl-C stops)", flush=True)

    try:
        serving.serve(options, announce=announce)
    except KeyboardInterrupt:
        print("stopped", file=sys.stderr)
    return EXIT_OK


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"{text} is not a positive number")
    return value


# -- demo: the README's main job ----------------------------------------------------------
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

    def write(self, name: str, value: Value, format: str) -> None:
        """Write ``value`` exactly to ``directory/name``."""
        self.written.extend(
            _write(self.directory / name, value, format, overwrite=self.force, exact=True)
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
    trace_path = run.directory / "superior.1.trace.jsonl"
    write_trace(trace_path, construction.trace, overwrite=run.force)
    run.written.append(trace_path)


DEMO_MIN_ANGLE = 30


def _demo_refine(run: DemoRun) -> None:
    """Lepp-centroid (Delaunay) refinement of the triangulation to a 30° minimum angle,
    and the Polylla polygon mesh of the result."""
    from geomexact.criteria import MinAngle
    from geomexact.polylla import polylla
    from geomexact.refine import refine

    if run.mesh is None:
        raise RuntimeError("the demo's triangulate step must run before refine")
    result = refine(run.mesh, MinAngle(DEMO_MIN_ANGLE), method="centroid")
    run.mesh, run.start, run.trace = result.mesh, result.start, result.trace
    run.report["refinement"] = {
        "method": "centroid", "min_angle": DEMO_MIN_ANGLE,
        **mesh_summary(result.mesh), **result.stats.as_dict(),
    }
    run.write("superior.2.ele", result.mesh, "triangle")
    trace_path = run.directory / "superior.2.trace.jsonl"
    write_trace(trace_path, result.trace, overwrite=run.force)
    run.written.append(trace_path)
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
    run = DemoRun(Path(args.output), args.force)
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
    if args.json:
        _print_json(run.report)
        return EXIT_OK
    summary = {k: v for k, v in run.report["input"].items() if k not in {"file", "source"}}
    _print_table(f"Lake Superior PSLG ({DEMO_INPUT}, from {DEMO_SOURCE})", summary)
    if "triangulation" in run.report:
        _print_table("constrained Delaunay triangulation", run.report["triangulation"])
    if "refinement" in run.report:
        _print_table(f"Lepp-centroid refinement to a {DEMO_MIN_ANGLE}° minimum angle",
                     run.report["refinement"])
    for path in run.written:
        print(f"wrote {path}")
    return EXIT_OK


# ---------------------------------------------------------------------------------------
# parser
# ---------------------------------------------------------------------------------------
def _non_negative(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} is negative")
    return value


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors name the program as ``geomexact: error:``."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The ``geomexact`` argument parser."""
    formats = sorted(io.FORMATS)
    names = ", ".join(formats)
    format_help = f"file format, one of {names} (default: from the extension)"
    parser = _Parser(
        prog="geomexact",
        description="Exact, replayable mesh refinement on rational coordinates.",
        epilog=EXIT_CODES_HELP + "\nSee docs/cli.md for every command, option and JSON key.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"geomexact {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    def add(name: str, run: Callable[[argparse.Namespace], int], summary: str) -> Any:
        sub = commands.add_parser(
            name, help=summary, description=summary, epilog=EXIT_CODES_HELP,
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        sub.set_defaults(run=run)
        return sub

    def verbose(sub: argparse.ArgumentParser) -> None:
        sub.add_argument(
            "-v", "--verbose", action="store_true",
            help="print the reader's notes (e.g. orientation fixed) on stderr",
        )

    def json_flag(sub: argparse.ArgumentParser) -> None:
        sub.add_argument("--json", action="store_true", help="print one JSON object on stdout")

    info = add("info", command_info, "print statistics of meshes, PSLGs and polygon meshes")
    info.add_argument("files", nargs="+", metavar="FILE", help="mesh, PSLG or polygon mesh file")
    info.add_argument("--format", choices=formats, metavar="F", help=format_help)
    json_flag(info)
    verbose(info)

    check = add("check", command_check, "validate a triangle mesh (exit 1 on violations)")
    check.add_argument("file", metavar="FILE", help="triangle mesh file")
    check.add_argument("--format", choices=formats, metavar="F", help=format_help)
    check.add_argument(
        "--strict",
        action="store_true",
        help="also report vertices in no triangle (isolated-vertex)",
    )
    json_flag(check)
    verbose(check)

    convert = add("convert", command_convert, "convert a file to another format")
    convert.add_argument("input", metavar="IN", help="file to read")
    convert.add_argument("output", metavar="OUT", help="file to write")
    convert.add_argument(
        "--from", dest="source_format", choices=formats, metavar="F",
        help=f"format of IN, one of {names} (default: from its extension)",
    )
    convert.add_argument(
        "--to", dest="target_format", choices=formats, metavar="F",
        help=f"format of OUT, one of {names} (default: from its extension)",
    )
    convert.add_argument(
        "--exact", action="store_true",
        help="write exact rationals even in float formats (default: nearest doubles there)",
    )
    convert.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(convert)
    verbose(convert)

    replay_ = add("replay", command_replay, "replay a trace on its input mesh, checking digests")
    replay_.add_argument("input", metavar="INPUT", help="the mesh the trace was recorded on")
    replay_.add_argument("trace", metavar="TRACE", help="trace file (JSON Lines)")
    replay_.add_argument(
        "--until", type=_non_negative, metavar="K", help="replay only the first K steps"
    )
    replay_.add_argument("-o", "--output", required=True, metavar="OUT", help="result file")
    replay_.add_argument(
        "--format", choices=formats, metavar="F", help=f"format of INPUT, one of {names}"
    )
    replay_.add_argument(
        "--to", choices=formats, metavar="F", help=f"format of OUT, one of {names}"
    )
    replay_.add_argument(
        "--exact", action="store_true", help="write exact rationals even in float formats"
    )
    replay_.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(replay_)
    verbose(replay_)

    triangulate_ = add(
        "triangulate", command_triangulate,
        "(constrained) Delaunay triangulation of points / a PSLG, or Lawson flips of a mesh",
    )
    triangulate_.add_argument("input", metavar="INPUT",
                              help=".node, .poly, PSLG text or a triangle mesh (OFF, .ele…)")
    triangulate_.add_argument("-o", "--output", metavar="OUT", help="mesh file to write")
    triangulate_.add_argument("--format", choices=formats, metavar="F", help=format_help)
    triangulate_.add_argument("--to", choices=formats, metavar="F",
                              help="format of OUT (default: by its extension)")
    triangulate_.add_argument("--keep-convex-hull", action="store_true",
                              help="keep the triangles between the segments and the convex hull")
    triangulate_.add_argument("--split-segments", action="store_true",
                              help="split segments at vertices on them and at crossings "
                                   "(default: such input is an error)")
    triangulate_.add_argument("--merge-duplicates", action="store_true",
                              help="keep the first of duplicate points (default: an error)")
    triangulate_.add_argument("--check", action="store_true",
                              help="validate the result and check Delaunay-ness (exit 1 if not)")
    triangulate_.add_argument("--trace", metavar="FILE", help="write the trace (JSON Lines)")
    triangulate_.add_argument("--exact", action="store_true",
                              help="write exact coordinates (p/q) instead of doubles")
    triangulate_.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(triangulate_)
    verbose(triangulate_)

    polylla_ = add("polylla", command_polylla,
                   "Polylla polygon mesh of a triangle mesh, optionally made convex")
    polylla_.add_argument("input", metavar="INPUT",
                          help="triangle mesh (.ele, OFF, …) or a PSLG (triangulated first)")
    polylla_.add_argument("-o", "--output", metavar="OUT",
                          help="polygon mesh file to write (e.g. OUT.off)")
    polylla_.add_argument("--convex", action="store_true",
                          help="split every polygon into convex ones by edges of the "
                               "triangulation")
    polylla_.add_argument("--no-opt", action="store_true",
                          help="convex decomposition without criterion 1 (angle-first mode; "
                               "implies --convex)")
    polylla_.add_argument("--picture", metavar="PNG",
                          help="draw the result (.png, .svg or .pdf; inserted edges in "
                               "orange, non-convex polygons filled)")
    polylla_.add_argument("--check", action="store_true",
                          help="validate the polygons against the triangulation (exit 1 if "
                               "invalid)")
    polylla_.add_argument("--format", choices=formats, metavar="F", help=format_help)
    polylla_.add_argument("--to", choices=formats, metavar="F",
                          help="format of OUT (default: by its extension)")
    polylla_.add_argument("--exact", action="store_true",
                          help="write exact coordinates (p/q) instead of doubles")
    polylla_.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(polylla_)
    verbose(polylla_)

    refine_ = add("refine", command_refine,
                  "Lepp refinement (bisection, centroid, quasi-Delaunay) to a criterion")
    refine_.add_argument("input", metavar="INPUT",
                         help="triangle mesh (.ele, OFF, …) or a PSLG (triangulated first)")
    refine_.add_argument("-o", "--output", metavar="OUT", help="mesh file to write")
    goal = refine_.add_mutually_exclusive_group(required=True)
    goal.add_argument("--max-area", metavar="A", help="largest triangle area allowed")
    goal.add_argument("--factor", metavar="F",
                      help="refine the largest triangles until the region's mean area is at "
                           "most F times its initial mean")
    goal.add_argument("--min-angle", metavar="DEG",
                      help="smallest angle allowed, in degrees (0 < DEG < 60; centroid or "
                           "quasi method, or bisection with --max-steps)")
    goal.add_argument("--max-edge", metavar="L", help="longest edge allowed")
    where = refine_.add_mutually_exclusive_group()
    where.add_argument("--circle", nargs=3, metavar=("X", "Y", "R"),
                       help="refine only triangles with a vertex in this disk")
    where.add_argument("--rectangle", nargs=4, metavar=("X", "Y", "W", "H"),
                       help="refine only triangles with a vertex in [X, X+W] x [Y, Y+H]")
    where.add_argument("--polygon", metavar="FILE",
                       help="refine only triangles with a vertex in this polygon (OFF with "
                            "one polygon, or a PSLG whose segments form one loop)")
    refine_.add_argument("--method", choices=("bisection", "centroid", "quasi"),
                         default="bisection", help="Lepp method (default: bisection)")
    refine_.add_argument("--no-delaunay", action="store_true",
                         help="never flip (no legalization, no quasi-Delaunay flips)")
    refine_.add_argument("--centroid", choices=("area", "area-exact", "vertices"),
                         default="area",
                         help="point inserted in a terminal quadrilateral: area centroid "
                              "rounded to 24 bits (default), exact area centroid (slow: "
                              "coordinates grow), or the mean of the four vertices")
    refine_.add_argument("--plain-centroids", action="store_true",
                         help="do not bisect a constraint second-longest edge of a terminal "
                              "triangle; always insert the centroid")
    refine_.add_argument("--max-steps", type=_non_negative, metavar="N",
                         help="stop after N steps (status 'step-limit')")
    refine_.add_argument("--trace", metavar="FILE",
                         help="write the trace (JSON Lines; from a PSLG: from its vertices)")
    refine_.add_argument("--polylla", metavar="OFF",
                         help="also write the Polylla polygon mesh of the result (OFF)")
    refine_.add_argument("--print-iter", metavar="DIR",
                         help="write the mesh before and after every step to "
                              "DIR/step-NNNNNN.off (exact)")
    refine_.add_argument("--check", action="store_true",
                         help="validate the result (exit 1 on violations)")
    refine_.add_argument("--check-delaunay", action="store_true",
                         help="exit 1 when the result is not (constrained) Delaunay")
    refine_.add_argument("--progress", action="store_true",
                         help="show progress on stderr")
    refine_.add_argument("--format", choices=formats, metavar="F", help=format_help)
    refine_.add_argument("--to", choices=formats, metavar="F",
                         help="format of OUT (default: by its extension)")
    refine_.add_argument("--exact", action="store_true",
                         help="write exact coordinates (p/q) instead of doubles")
    refine_.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(refine_)
    verbose(refine_)

    view = add("view", command_view,
               "write the offline HTML viewer or a PNG/SVG/PDF picture of a mesh (and trace)")
    view.add_argument("input", metavar="INPUT",
                      help="mesh, PSLG or polygon mesh (with --trace: the trace's input)")
    view.add_argument("-o", "--output", required=True, metavar="OUT",
                      help="OUT.html: the viewer; OUT.png, .svg or .pdf: a picture")
    view.add_argument("--trace", metavar="TRACE",
                      help="a trace recorded on INPUT: the viewer gets a step slider")
    view.add_argument("--step", type=_non_negative, metavar="K",
                      help="with --trace: the step shown first (viewer) or drawn (picture); "
                           "default: the last")
    view.add_argument("--color-by", choices=VIEW_FILL_CHOICES, default="none",
                      help="fill triangles by smallest angle, area or region attribute")
    view.add_argument("--title", help="title of the page or picture")
    view.add_argument("--no-exact", action="store_true",
                      help="leave the exact coordinates out of the page (smaller file)")
    view.add_argument("--format", choices=formats, metavar="F", help=format_help)
    view.add_argument("--force", action="store_true", help="replace an existing OUT")
    json_flag(view)
    verbose(view)

    serve_ = add("serve", command_serve,
                 "serve a directory's meshes in the viewer and refine uploads (local HTTP)")
    serve_.add_argument("directory", nargs="?", default=".", metavar="DIR",
                        help="directory whose mesh files are listed (default: .)")
    serve_.add_argument("--host", default="127.0.0.1",
                        help="interface to listen on (default 127.0.0.1, this machine only; "
                             "0.0.0.0 or an address opens it to the network)")
    serve_.add_argument("--port", type=_non_negative, default=8765,
                        help="port (default 8765; 0 picks a free one)")
    serve_.add_argument("--max-upload-mb", type=_positive_float, default=16, metavar="MB",
                        help="largest upload accepted (default 16)")
    serve_.add_argument("--time-limit", type=_positive_float, default=60, metavar="SECONDS",
                        help="a job (reading, refining, building a page) is stopped after "
                             "this long (default 60)")
    serve_.add_argument("--jobs", type=_non_negative, default=2, metavar="N",
                        help="jobs run at once; more requests are told the server is busy "
                             "(default 2)")

    demo = add("demo", command_demo, "run the main job on the bundled Lake Superior PSLG")
    demo.add_argument(
        "-o", "--output", default="geomexact-demo", metavar="DIR",
        help="output directory (default: geomexact-demo)",
    )
    demo.add_argument("--force", action="store_true", help="replace existing files")
    json_flag(demo)
    return parser


# ---------------------------------------------------------------------------------------
# entry point
# ---------------------------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``geomexact`` command with ``argv`` (default: ``sys.argv[1:]``); return the
    exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:  # --help, --version and usage errors
        return stop.code if isinstance(stop.code, int) else EXIT_BAD_INPUT
    try:
        return int(args.run(args))
    except (GeomexactError, UsageProblem) as error:
        _print_error(str(error))
    except BrokenPipeError:
        _silence_stdout()  # the reader went away (e.g. `| head`): stop quietly, as SIGPIPE
        return EXIT_BROKEN_PIPE
    except OSError as error:
        _print_error(_os_error_text(error))
    except KeyboardInterrupt:
        _print_error("interrupted")
        return 130
    return EXIT_BAD_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
