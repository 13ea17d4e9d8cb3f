"""What the pictures and the viewer draw: a :class:`Scene` (vertex doubles, cells, segments)
made from a mesh, PSLG or polygon mesh, and a :class:`History` (which triangles each step
of a trace added and removed) made by replaying the trace.

Both are display data: coordinates are the doubles nearest to the exact vertices (the
exact text travels beside them, for reading only).  Nothing here computes geometry with
floats; :mod:`geomexact.viz.pictures` and the viewer do, to draw.

Scenes are built by one function per kind of value, registered in :data:`SCENE_BUILDERS`
(3D tetrahedral meshes add their builder there).  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import itertools
import math
import sys
from array import array
from collections.abc import Callable, Iterable, Sequence
from typing import Any, TypeAlias

import attrs

from geomexact.kernel.numbers import Rational, floor_log2, format_rational, mpq
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.delaunay.triangulation import vertices_mesh
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Edge, Mesh2, Triangle, canonical_triangle
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh2d.transient import Transient2
from geomexact.trace.playback import apply_checked, check_start
from geomexact.trace.record import Trace
from geomexact.trace.step import Step

Viewable: TypeAlias = Mesh2 | PSLG | PolygonMesh

INDEX_TYPE = next(code for code in ("I", "L") if array(code).itemsize == 4)
"""The ``array`` type code of unsigned 32-bit integers on this platform."""

DEFAULT_EXACT_BUDGET = 4_000_000
"""Characters of exact coordinate text a scene carries at most (beyond it: none)."""

DRAWN_BAND = 500
"""A scene is drawn unscaled when its largest coordinate magnitude lies in
2^-DRAWN_BAND .. 2^DRAWN_BAND (every ordinary input); otherwise it is scaled exactly by a
power of two first, so that neither the doubles nor the viewer's float arithmetic on them
(extents, areas) overflows or underflows."""


def indices(values: Iterable[int] = ()) -> array[int]:
    """An array of unsigned 32-bit integers."""
    return array(INDEX_TYPE, values)


def doubles(values: Iterable[float] = ()) -> array[float]:
    """An array of doubles."""
    return array("d", values)


def little_endian(values: array[Any]) -> bytes:
    """The array's bytes in little-endian order (the viewer's typed arrays expect it)."""
    if sys.byteorder == "little":
        return values.tobytes()
    swapped = array(values.typecode, values)
    swapped.byteswap()
    return swapped.tobytes()


# ---------------------------------------------------------------------------------------
# scenes
# ---------------------------------------------------------------------------------------
@attrs.frozen(eq=False)
class Scene:
    """A value ready to draw.

    - ``kind``: ``"triangles"`` (a :class:`Mesh2`), ``"polygons"`` (a
      :class:`PolygonMesh`) or ``"pslg"`` (points, segments, holes);
    - ``xy``: the doubles of the vertices, x0 y0 x1 y1 …; ``exact``: their exact text
      ``"x y"`` per vertex, or None when over the budget;
    - ``triangles``: vertex triples (counter-clockwise, canonical, sorted); ``regions``:
      each triangle's first attribute as a double (None when no triangle has one);
    - ``polygon_offsets`` / ``polygon_vertices``: polygon i is
      ``polygon_vertices[offsets[i]:offsets[i+1]]``; ``nonconvex``: ids of polygons that
      are not convex (exact test);
    - ``segments``: vertex pairs of constrained edges (PSLG segments); ``holes`` and
      ``seeds``: hole and region seed points (doubles);
    - ``summary``: the statistics of ``geomexact info`` (JSON values);
    - ``dimension``: 2 (a 3D scene will say 3);
    - ``scale_exponent``: ``xy``, ``holes`` and ``seeds`` are the doubles of the exact
      coordinates times ``2**-scale_exponent`` (0 unless the largest coordinate is outside
      the band of :data:`DRAWN_BAND`, e.g. 1e309 or 1e-400: then it is about 1); ``exact``
      is never scaled.
    """

    kind: str
    xy: array[float]
    exact: tuple[str, ...] | None
    triangles: array[int] = attrs.field(factory=indices)
    regions: array[float] | None = None
    polygon_offsets: array[int] = attrs.field(factory=indices)
    polygon_vertices: array[int] = attrs.field(factory=indices)
    nonconvex: array[int] = attrs.field(factory=indices)
    segments: array[int] = attrs.field(factory=indices)
    holes: array[float] = attrs.field(factory=doubles)
    seeds: array[float] = attrs.field(factory=doubles)
    summary: dict[str, Any] = attrs.field(factory=dict)
    dimension: int = 2
    scale_exponent: int = 0

    @property
    def vertex_count(self) -> int:
        return len(self.xy) // 2

    @property
    def triangle_count(self) -> int:
        return len(self.triangles) // 3

    @property
    def polygon_count(self) -> int:
        return max(len(self.polygon_offsets) - 1, 0)

    def polygon(self, index: int) -> tuple[int, ...]:
        """The vertex ids of polygon ``index``."""
        start, end = self.polygon_offsets[index], self.polygon_offsets[index + 1]
        return tuple(self.polygon_vertices[start:end])


def scale_exponent_of(*groups: Sequence[Point2]) -> int:
    """The ``scale_exponent`` of a scene drawing these points: 0 when the largest
    coordinate magnitude is 0 or within 2^-DRAWN_BAND .. 2^DRAWN_BAND, else its
    ``floor_log2`` (found exactly).  O(n)."""
    low, high = 2.0**-DRAWN_BAND, 2.0**DRAWN_BAND
    largest_double = 0.0
    for point in itertools.chain(*groups):
        fx, fy = abs(point.fx), abs(point.fy)
        if not (fx <= high and fy <= high):  # beyond the band, or nan (beyond the doubles)
            break
        largest_double = max(largest_double, fx, fy)
    else:
        if largest_double >= low:
            return 0
    largest = max((max(abs(p.x), abs(p.y)) for p in itertools.chain(*groups)), default=0)
    return 0 if largest == 0 else floor_log2(largest)


def _points_xy(points: Iterable[Point2], scale_exponent: int = 0) -> array[float]:
    xy = doubles()
    if scale_exponent == 0:
        for point in points:
            xy.append(point.fx)
            xy.append(point.fy)
        return xy
    scale = mpq(2) ** -scale_exponent
    for point in points:
        # |coordinate| * scale < 2: the doubles exist, and are correctly rounded
        xy.append(float(point.x * scale))
        xy.append(float(point.y * scale))
    return xy


def _region_double(value: Rational) -> float:
    """A region attribute as a double for colouring: +-inf beyond the double range."""
    try:
        return float(value)
    except OverflowError:
        return math.copysign(math.inf, value)


def exact_text(
    points: Sequence[Point2], budget: int = DEFAULT_EXACT_BUDGET
) -> tuple[str, ...] | None:
    """``"x y"`` exact text of each point, or None when it would exceed ``budget``
    characters in all."""
    texts = []
    used = 0
    # a coordinate repeats across points (a refined grid has a few thousand distinct
    # values for a million points): each distinct value is written once
    written: dict[Rational, str] = {}
    for point in points:
        x, y = point.x, point.y
        text_x = written.get(x)
        if text_x is None:
            text_x = written[x] = format_rational(x)
        text_y = written.get(y)
        if text_y is None:
            text_y = written[y] = format_rational(y)
        text = f"{text_x} {text_y}"
        used += len(text) + 3
        if used > budget:
            return None
        texts.append(text)
    return tuple(texts)


def _mesh_points(mesh: Mesh2) -> list[Point2]:
    return mesh.point_list()


def mesh_scene(mesh: Mesh2, *, exact_budget: int = DEFAULT_EXACT_BUDGET,
               summary: bool = True) -> Scene:
    """The scene of a triangle mesh: its triangles in sorted canonical order, its
    constrained segments, its regions (first triangle attribute)."""
    points = _mesh_points(mesh)
    triangles = indices()
    regions = doubles()
    has_regions = bool(len(mesh.triangle_attributes))
    source = mesh.source
    if source is not None and not has_regions:
        # a kernel's or a bulk reader's arrays: sorted there, not as a million tuples
        import numpy as np

        rows = source.triangle_rows()
        rows = rows[np.lexsort(rows.T[::-1])]
        triangles.frombytes(rows.astype(np.dtype(INDEX_TYPE)).tobytes())
    else:
        for triangle in mesh.triangles():
            triangles.extend(triangle)
            if has_regions:
                values = mesh.triangle_attributes.get(triangle)
                regions.append(_region_double(values[0]) if values else math.nan)
    segments = indices()
    for u, v, _ in mesh.segment_list():
        segments.extend((u, v))
    exponent = scale_exponent_of(points)
    return Scene(
        kind="triangles",
        xy=_points_xy(points, exponent),
        exact=exact_text(points, exact_budget),
        triangles=triangles,
        regions=regions if has_regions else None,
        segments=segments,
        summary=mesh_summary(mesh) if summary else {},
        scale_exponent=exponent,
    )


def pslg_scene(pslg: PSLG, *, exact_budget: int = DEFAULT_EXACT_BUDGET,
               summary: bool = True) -> Scene:
    """The scene of a PSLG: its vertices, segments, hole and region seeds."""
    segments = indices()
    for u, v, _ in pslg.segments:
        segments.extend((u, v))
    seeds = [region.point for region in pslg.regions]
    exponent = scale_exponent_of(pslg.vertices, pslg.holes, seeds)
    return Scene(
        kind="pslg",
        xy=_points_xy(pslg.vertices, exponent),
        exact=exact_text(pslg.vertices, exact_budget),
        segments=segments,
        holes=_points_xy(pslg.holes, exponent),
        seeds=_points_xy(seeds, exponent),
        scale_exponent=exponent,
        summary={
            "vertices": len(pslg.vertices),
            "segments": len(pslg.segments),
            "holes": len(pslg.holes),
            "regions": len(pslg.regions),
        } if summary else {},
    )


def is_convex_polygon(points: Sequence[Point2], polygon: Sequence[int]) -> bool:
    """True when the counter-clockwise ``polygon`` turns left or goes straight at every
    corner and has no repeated vertex (exact orientation tests)."""
    if len(set(polygon)) != len(polygon):
        return False
    count = len(polygon)
    for index in range(count):
        a = points[polygon[index - 1]]
        b = points[polygon[index]]
        c = points[polygon[(index + 1) % count]]
        if orient2d(a, b, c) == Orientation.CLOCKWISE:
            return False
    return True


def polygon_mesh_scene(mesh: PolygonMesh, *, exact_budget: int = DEFAULT_EXACT_BUDGET,
                       summary: bool = True) -> Scene:
    """The scene of a polygon mesh (e.g. Polylla output), with its non-convex polygons
    found exactly."""
    offsets = indices([0])
    vertices = indices()
    nonconvex = indices()
    for index, polygon in enumerate(mesh.polygons):
        vertices.extend(polygon)
        offsets.append(len(vertices))
        if not is_convex_polygon(mesh.vertices, polygon):
            nonconvex.append(index)
    sizes = [len(polygon) for polygon in mesh.polygons]
    exponent = scale_exponent_of(mesh.vertices)
    return Scene(
        kind="polygons",
        xy=_points_xy(mesh.vertices, exponent),
        scale_exponent=exponent,
        exact=exact_text(mesh.vertices, exact_budget),
        polygon_offsets=offsets,
        polygon_vertices=vertices,
        nonconvex=nonconvex,
        summary={
            "vertices": len(mesh.vertices),
            "polygons": len(mesh.polygons),
            "nonconvex_polygons": len(nonconvex),
            "min_polygon_size": min(sizes, default=None),
            "max_polygon_size": max(sizes, default=None),
        } if summary else {},
    )


SceneBuilder: TypeAlias = Callable[..., Scene]

SCENE_BUILDERS: dict[type, SceneBuilder] = {
    Mesh2: mesh_scene,
    PSLG: pslg_scene,
    PolygonMesh: polygon_mesh_scene,
}
"""Kind of value -> its scene builder (``builder(value, *, exact_budget, summary)``).
A 3D mesh type registers its own builder here (its scene has ``dimension`` 3)."""


def scene_of(value: object, *, exact_budget: int = DEFAULT_EXACT_BUDGET,
             summary: bool = True) -> Scene:
    """The scene of a :class:`Mesh2`, :class:`PSLG` or :class:`PolygonMesh` (or of any
    type registered in :data:`SCENE_BUILDERS`); ``TypeError`` for anything else."""
    for kind, builder in SCENE_BUILDERS.items():
        if isinstance(value, kind):
            return builder(value, exact_budget=exact_budget, summary=summary)
    known = ", ".join(sorted(kind.__name__ for kind in SCENE_BUILDERS))
    raise TypeError(f"cannot draw a {type(value).__name__} (drawable: {known})")


# ---------------------------------------------------------------------------------------
# histories
# ---------------------------------------------------------------------------------------
@attrs.frozen(eq=False)
class CellChanges:
    """The cells of one kind (triangles, or constrained segments) that a trace's steps add
    and remove.

    Every cell that exists at some step gets a *slot*: ``cells[w*s : w*s + w]`` are its
    ``w`` vertex ids (canonical; a cell removed and later re-created keeps its slot).
    ``start`` lists the slots alive before step 1.  Step k (1-based) removes the slots
    ``removed[removed_offsets[k-1]:removed_offsets[k]]`` and then adds
    ``added[added_offsets[k-1]:added_offsets[k]]``; a slot in both lists is a cell the
    step re-created (e.g. a triangle with a new regional attribute)."""

    cells: array[int]
    start: array[int]
    added_offsets: array[int]
    added: array[int]
    removed_offsets: array[int]
    removed: array[int]

    def added_at(self, step: int) -> array[int]:
        """The slots step ``step`` (1-based) adds."""
        return self.added[self.added_offsets[step - 1]:self.added_offsets[step]]

    def removed_at(self, step: int) -> array[int]:
        """The slots step ``step`` (1-based) removes."""
        return self.removed[self.removed_offsets[step - 1]:self.removed_offsets[step]]

    def alive(self, step: int) -> set[int]:
        """The slots alive after ``step`` steps (0 <= step <= the step count)."""
        alive = set(self.start)
        for index in range(1, step + 1):
            alive.difference_update(self.removed_at(index))
            alive.update(self.added_at(index))
        return alive


@attrs.frozen(eq=False)
class History:
    """What each step of a trace changed, for the viewer's step slider: the
    :class:`CellChanges` of the ``triangles`` and of the constrained ``segments``;
    ``vertex_counts[k]``, the number of vertices after k steps (vertex ids only grow);
    ``final``, the mesh after the last step."""

    labels: tuple[str, ...]
    triangles: CellChanges
    segments: CellChanges
    vertex_counts: array[int]
    input_digest: str
    final_digest: str
    final: Mesh2

    @property
    def steps(self) -> int:
        return len(self.labels)

    def _check_step(self, step: int, first: int) -> None:
        if not first <= step <= self.steps:
            raise ValueError(f"step {step} is outside {first}..{self.steps}")

    def triangles_at(self, step: int) -> list[Triangle]:
        """The triangles (canonical, sorted) after ``step`` steps.  O(changes)."""
        self._check_step(step, 0)
        return _triples(self.triangles.cells, self.triangles.alive(step))

    def segments_at(self, step: int) -> list[Edge]:
        """The constrained segments (u < v, sorted) after ``step`` steps."""
        self._check_step(step, 0)
        cells = self.segments.cells
        return sorted((cells[2 * s], cells[2 * s + 1]) for s in self.segments.alive(step))

    def step_changes(self, step: int) -> tuple[list[Triangle], list[Triangle]]:
        """(added, removed) triangles of step number ``step`` (1-based)."""
        self._check_step(step, 1)
        cells = self.triangles.cells
        return (_triples(cells, self.triangles.added_at(step)),
                _triples(cells, self.triangles.removed_at(step)))


def _triples(cells: array[int], slots: Iterable[int]) -> list[Triangle]:
    return sorted((cells[3 * s], cells[3 * s + 1], cells[3 * s + 2]) for s in slots)


class _Slots:
    """Slot numbering of cells (triangles or segments) in order of first appearance, and
    the net change of one step."""

    def __init__(self, width: int) -> None:
        self.width = width
        self.ids: dict[tuple[int, ...], int] = {}
        self.cells = indices()
        self.start = indices()
        self.added_offsets = indices([0])
        self.added = indices()
        self.removed_offsets = indices([0])
        self.removed = indices()
        self.first: dict[tuple[int, ...], bool] = {}  # alive before the step?
        self.last: dict[tuple[int, ...], bool] = {}  # alive after it?

    def slot(self, cell: tuple[int, ...]) -> int:
        found = self.ids.get(cell)
        if found is None:
            found = len(self.ids)
            self.ids[cell] = found
            self.cells.extend(cell)
        return found

    def event(self, cell: tuple[int, ...], alive_after: bool) -> None:
        if cell not in self.first:
            self.first[cell] = not alive_after
        self.last[cell] = alive_after

    def close_step(self) -> int:
        """Record the step's net changes; return (added - removed) cells."""
        added = sorted(self.slot(cell) for cell, alive in self.last.items() if alive)
        removed = sorted(self.slot(cell) for cell, alive in self.first.items() if alive)
        self.added.extend(added)
        self.removed.extend(removed)
        self.added_offsets.append(len(self.added))
        self.removed_offsets.append(len(self.removed))
        self.first.clear()
        self.last.clear()
        return len(added) - len(removed)

    def changes(self) -> CellChanges:
        return CellChanges(self.cells, self.start, self.added_offsets, self.added,
                           self.removed_offsets, self.removed)


class _RecordingTransient(Transient2):
    """A transient that also reports every triangle and segment it adds or removes."""

    __slots__ = ("segment_slots", "triangle_slots")

    def __init__(self, mesh: Mesh2, triangles: _Slots, segments: _Slots) -> None:
        super().__init__(mesh)
        self.triangle_slots = triangles
        self.segment_slots = segments

    def add_triangle(self, a: int, b: int, c: int,
                     attributes: tuple[Any, ...] | None = None) -> None:
        super().add_triangle(a, b, c, attributes)
        self.triangle_slots.event(canonical_triangle(a, b, c), True)

    def remove_triangle(self, a: int, b: int, c: int) -> tuple[Any, ...] | None:
        attributes = super().remove_triangle(a, b, c)
        self.triangle_slots.event(canonical_triangle(a, b, c), False)
        return attributes

    def set_segment(self, u: int, v: int, marker: int = 0) -> None:
        key = (u, v) if u < v else (v, u)
        existed = self.segment_marker(u, v) is not None
        super().set_segment(u, v, marker)
        if existed:
            self.segment_slots.event(key, False)
        self.segment_slots.event(key, True)

    def remove_segment(self, u: int, v: int) -> int:
        marker = super().remove_segment(u, v)
        self.segment_slots.event((u, v) if u < v else (v, u), False)
        return marker


def step_label(step: Step) -> str:
    """``op(arg, …)`` with rationals as exact text (decimal when finite)."""
    shown = [str(a) if isinstance(a, int) else format_rational(a) for a in step.args]
    return f"{step.op}({', '.join(shown)})"


def history_of(start: Mesh2, trace: Trace) -> History:
    """Replay ``trace`` on ``start`` once, checking every digest (as
    :func:`geomexact.trace.record.replay` does), and record what each step changed and the final
    mesh.
    O(total changes); raises :class:`TraceError` when ``start`` is not the trace's input
    or a step diverges."""
    check_start(start, trace)
    triangles, segments = _Slots(3), _Slots(2)
    for triangle in start.triangles():
        triangles.start.append(triangles.slot(triangle))
    for u, v, _ in start.segment_list():
        segments.start.append(segments.slot((u, v)))
    transient = _RecordingTransient(start, triangles, segments)
    vertex_counts = indices([start.vertex_count])
    labels = []
    alive = start.triangle_count
    for index, step in enumerate(trace.steps):
        apply_checked(transient, trace, index)
        alive += triangles.close_step()
        segments.close_step()
        if alive != transient.triangle_count:  # an op edited the tables behind our back
            raise RuntimeError(f"step {index + 1} ({step}) changed triangles unrecorded")
        vertex_counts.append(transient.vertex_count)
        labels.append(step_label(step))
    return History(
        labels=tuple(labels),
        triangles=triangles.changes(),
        segments=segments.changes(),
        vertex_counts=vertex_counts,
        input_digest=f"{trace.input_digest:032x}",
        final_digest=f"{trace.final_digest:032x}",
        final=transient.seal(),
    )


def trace_start(value: Viewable) -> Mesh2:
    """The mesh a trace on ``value`` starts from: the mesh itself, or for a PSLG the mesh
    of its isolated vertices (where a triangulation trace starts)."""
    if isinstance(value, Mesh2):
        return value
    if isinstance(value, PSLG):
        return vertices_mesh(value)
    raise TypeError(f"a trace cannot start from a {type(value).__name__}")

