"""Reading a command's input files: the value, the format read, the reader's notes and the
line of each item; and triangulating a PSLG input with errors that name those lines."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import attrs

from geomexact import io
from geomexact.cli.errors import UsageProblem, print_warning
from geomexact.cli.kinds import Value, kind_name
from geomexact.cli.memory import BYTES_PER_POINT, active_budget, refuse_large_file
from geomexact.errors import FormatError, PreconditionError, SegmentError
from geomexact.io.registry import SourceLines, clipped
from geomexact.kernel.numbers import format_rational
from geomexact.kernel.points import Point2
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.segments import crossing_point
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

if TYPE_CHECKING:
    import numpy as np

    from geomexact.mesh2d.delaunay.triangulation import Construction

SHOWN = 10
"""The most offending items a message lists one by one."""


@attrs.frozen
class Loaded:
    """A file read by :func:`io.read_with_sources`, with the format it was read as."""

    path: str
    format: str
    value: Value
    notes: tuple[str, ...]
    sources: SourceLines | None = None

    @property
    def kind(self) -> str:
        return kind_name(type(self.value))


def load(path: str, format: str | None, verbose: bool) -> Loaded:
    """Read ``path`` (``format`` or by its extension); with ``verbose`` print the reader's
    notes on stderr."""
    if format is None:
        try:
            format = io.detect_format(path)
        except FormatError as error:
            raise UsageProblem(
                f"{error.path}: {error.problem.partition('; pass format=')[0]}; use "
                "--format F to name one"
            ) from None
    refuse_large_file(path)
    reading = io.read_with_sources(path, format=format)
    assert not isinstance(reading.value, MixedMeshData), "readers return a bare mesh"
    if verbose:
        for note in reading.notes:
            print(f"geomexact: {path}: {note}", file=sys.stderr)
    return Loaded(path, format, reading.value, tuple(reading.notes), reading.sources)


def material_cells(loaded: Loaded) -> tuple[str, np.ndarray] | None:
    """The material array of a 3D mesh file (the first of
    :data:`~geomexact.io.cell_arrays.MATERIAL_ARRAYS`): (its name, each cell's id aligned
    with the mesh's cells), or None (no such array, or not a 3D mesh)."""
    if not isinstance(loaded.value, Mesh3 | MixedMesh3):
        return None
    # imported here: the cell arrays come through meshio, for 3D files only
    from geomexact.io.cell_arrays import material_array, read_cell_arrays

    return material_array(read_cell_arrays(loaded.path, format=loaded.format,
                                           mesh=loaded.value))


def load_mesh(path: str, format: str | None, verbose: bool, command: str) -> Mesh2:
    """:func:`load` a triangle mesh; any other kind is a :class:`UsageProblem` of
    ``command``."""
    loaded = load(path, format, verbose)
    if not isinstance(loaded.value, Mesh2):
        raise UsageProblem(
            f"{path}: is a {loaded.kind.replace('_', ' ')}, but {command} needs a triangle "
            "mesh (a Triangle .ele, OFF or PSLG text file of triangles, …)"
        )
    return loaded.value


# -----------------------------------------------------------------------------------------
# triangulating an input, in the words of its file
# -----------------------------------------------------------------------------------------
def _point(point: Point2) -> str:
    """The exact coordinates, each at most about 100 characters (huge numbers clipped)."""
    return f"({clipped(format_rational(point.x), 100)}, {clipped(format_rational(point.y), 100)})"


def _listed(items: list[str]) -> str:
    more = f"; and {len(items) - SHOWN} more" if len(items) > SHOWN else ""
    return "; ".join(items[:SHOWN]) + more


def segment_problems(pslg: PSLG, sources: SourceLines, pairs: Any) -> list[str]:
    """Each offending pair of a :class:`~geomexact.errors.SegmentError` as
    ``"file:line and file:line: segments (a, b) and (c, d) cross at (x, y)"``, vertices
    in the file's numbering."""
    base = sources.base
    index_of: dict[tuple[int, int], list[int]] = {}
    for index, (u, v, _) in enumerate(pslg.segments):
        index_of.setdefault((min(u, v), max(u, v)), []).append(index)

    def segment_index(ends: tuple[int, int], other: int = -1) -> int:
        found = index_of.get((min(ends), max(ends)), [-1])
        return next((i for i in found if i != other), found[0])

    def shown(index: int, ends: tuple[int, int]) -> str:
        return f"{index + base} ({ends[0] + base}, {ends[1] + base})"

    points = pslg.vertices
    problems = []
    for first, second in pairs:
        one = segment_index(first)
        if not isinstance(second, tuple):  # a segment through a vertex
            w = int(second)
            problems.append(
                f"{sources.segment(one)} and {sources.vertex(w)}: segment {shown(one, first)} "
                f"passes through vertex {w + base} {_point(points[w])}"
            )
            continue
        two = segment_index(second, one)
        where = f"{sources.segment(one)} and {sources.segment(two)}"
        both = f"segments {shown(one, first)} and {shown(two, second)}"
        (u, v), (a, b) = first, second
        if {u, v} == {a, b}:
            problems.append(f"{where}: {both} are the same segment")
            continue
        pu, pv, pa, pb = points[u], points[v], points[a], points[b]
        if (pv.x - pu.x) * (pb.y - pa.y) == (pv.y - pu.y) * (pb.x - pa.x):
            problems.append(f"{where}: {both} overlap")
            continue
        at = crossing_point(pu, pv, pa, pb)
        verb = "meet" if at in (pu, pv, pa, pb) else "cross"
        problems.append(f"{where}: {both} {verb} at {_point(at)}")
    return problems


def triangulation_problems(
    error: PreconditionError, loaded: Loaded
) -> tuple[str, str, list[str]] | None:
    """A triangulation refusal of the input as (kind, headline, one sentence per
    offending item naming its file and line), or None when ``error`` is no refusal of the
    input or the file has no lines.  Kinds: ``segments-meet``, ``duplicate-points``,
    ``collinear-points``, ``too-few-points``."""
    sources, pslg = loaded.sources, loaded.value
    if sources is None or not isinstance(pslg, PSLG):
        return None
    base = sources.base
    if isinstance(error, SegmentError):
        return ("segments-meet", "segments cross or pass through vertices",
                segment_problems(pslg, sources, error.pairs))
    details = error.details
    if "duplicates" in details:
        items = [
            f"{sources.vertex(dropped)} and {sources.vertex(kept)}: vertex {dropped + base} "
            f"repeats vertex {kept + base} {_point(pslg.vertices[kept])}"
            for dropped, kept in details["duplicates"]
        ]
        return ("duplicate-points", f"{len(items)} duplicate points", items)
    if "collinear" in details:
        ids = details["collinear"]
        shown = ", ".join(sources.vertex(v) for v in ids[:SHOWN])
        more = ", …" if len(ids) > SHOWN else ""
        return ("collinear-points", "no triangle exists",
                [f"{loaded.path}: all {len(ids)} distinct points are collinear ({shown}{more})"])
    if "distinct" in details:
        ids = details["distinct"]
        shown = ", ".join(sources.vertex(v) for v in ids)
        return ("too-few-points", "a triangulation needs at least 3 distinct points",
                [f"{loaded.path}: {len(ids)} distinct points ({shown or 'none'})"])
    return None


_REMEDIES = {"duplicate-points": "use --merge-duplicates to keep only the first copy"}


def triangulation_problem(
    error: PreconditionError, loaded: Loaded, split_hint: str
) -> str | None:
    """The message of a triangulation refusal naming the input's lines (None when
    ``error`` is no refusal of the input or the file has no lines).  ``split_hint``: what
    the command offers against crossing segments."""
    found = triangulation_problems(error, loaded)
    if found is None:
        return None
    kind, headline, items = found
    remedy = split_hint if kind == "segments-meet" else _REMEDIES.get(kind)
    if kind in ("collinear-points", "too-few-points"):
        return f"{_listed(items)}: {headline}"
    return f"{headline}{f' ({remedy})' if remedy else ''}: {_listed(items)}"


def triangulate_input(loaded: Loaded, *, split_hint: str, **options: Any) -> Construction:
    """:func:`triangulate` the PSLG of ``loaded`` (``options`` are its own); a refusal
    of the input is a :class:`UsageProblem` naming the file and line of each offending
    item, and each ignored hole or region seed is a warning on stderr."""
    # imported here: the Delaunay kernel loads NumPy, which reading a mesh does not need
    from geomexact.mesh2d.delaunay.triangulation import triangulate

    pslg = loaded.value
    assert isinstance(pslg, PSLG)
    count = len(pslg.vertices)
    active_budget().refuse_beyond(f"triangulating {count:,} points", count * BYTES_PER_POINT,
                                  "triangulate fewer points")
    try:
        construction = triangulate(pslg, **options)
    except PreconditionError as error:
        message = triangulation_problem(error, loaded, split_hint)
        if message is None:
            raise
        raise UsageProblem(message) from error
    for warning in seed_warnings(loaded, construction):
        print_warning(warning)
    return construction


def seed_warnings(loaded: Loaded, construction: Construction) -> list[str]:
    """One sentence per seed the triangulation ignored, naming its file and line."""
    pslg = loaded.value
    assert isinstance(pslg, PSLG)
    sources = loaded.sources
    warnings = []
    for kind, index in construction.ignored_seeds:
        if kind == "hole":
            point, where = pslg.holes[index], sources.hole(index) if sources else loaded.path
        else:
            point = pslg.regions[index].point
            where = sources.region(index) if sources else loaded.path
        warnings.append(
            f"{where}: {kind} {index + 1} at {_point(point)} is in no triangle (outside the "
            f"domain{', or in a hole carved before' if pslg.holes else ''}); ignored"
        )
    return warnings


def surface_instead(path: str, format: str | None, error: Exception) -> Any:
    """A triangulated surface in ``path`` when the mesh readers refused it and it is not
    planar (a 3D OBJ, STL, PLY or OFF: a part's surface), read exactly; None otherwise
    (the caller re-raises ``error``)."""
    from geomexact.io.surface_files import SURFACE_FORMATS, read_surface

    if format is not None or Path(path).suffix.lower() not in SURFACE_FORMATS:
        return None
    try:
        surface = read_surface(path)
    except FormatError:
        return None
    # a planar file the mesh readers refused is a bad planar mesh: their error stands
    return surface if any(point.z != 0 for point in surface.points) else None
