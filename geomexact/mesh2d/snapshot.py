"""Persistent 2D triangle meshes: the :class:`Mesh2` snapshot value and its queries.

A :class:`Mesh2` is immutable.  Its tables are persistent hash maps (``immutables.Map``,
a HAMT), so a step that changes k triangles builds the next snapshot in O(k log n) time and
shares everything else with the previous one.  Vertices are numbered by insertion order
(0, 1, 2, …); a triangle is identified by its counter-clockwise vertex triple rotated to
start at its smallest id (:func:`canonical_triangle`); adjacency is a half-edge map: the
directed edge (u, v) of a counter-clockwise triangle (u, v, w) maps to its apex w.
Model, digest and invariants: ``specs/snapshot.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import TYPE_CHECKING, TypeAlias

import attrs
import immutables

from geomexact.kernel import digest as _digest
from geomexact.kernel.derived import Derived
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.trace.protocols import kind_of
from geomexact.trace.recording import MAX_VERTICES as MAX_VERTICES
from geomexact.trace.sourced_snapshot import SourcedSnapshot

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from geomexact.mesh2d.transient import Transient2
    from geomexact.trace.step import Step

Triangle: TypeAlias = tuple[int, int, int]
Edge: TypeAlias = tuple[int, int]
Attributes: TypeAlias = tuple[Rational, ...]



def canonical_triangle(a: int, b: int, c: int) -> Triangle:
    """The rotation of the cyclic triple (a, b, c) that starts at its smallest id."""
    if a < b and a < c:
        return a, b, c
    if b < c:
        return b, c, a
    return c, a, b


def undirected(u: int, v: int) -> Edge:
    """The edge {u, v} as the pair (min, max)."""
    return (u, v) if u < v else (v, u)


IdArray: TypeAlias = "npt.NDArray[np.int64]"
"""Vertex ids as an int64 array (NumPy is imported where arrays are made, not here)."""


@attrs.frozen(slots=True, eq=False)
class TableSource:
    """The content of a snapshot's vertex, half-edge and outgoing tables as arrays, as a
    compiled kernel leaves them: a :class:`Mesh2` given one builds its persistent tables
    from it on first use.

    - ``points``: the :class:`Point2` of each vertex id 0..n-1;
    - ``halfedges``: (H x 3) int64 rows (u, v, w), one per half-edge, in any order;
    - ``hints``: (n,) int64, the ``outgoing`` hint of each vertex, -1 for none;
    - ``base``: a snapshot whose tables the built ones are derived from (sharing their
      structure), or None.
    """

    points: Sequence[Point2]
    halfedges: IdArray
    hints: IdArray
    base: Mesh2 | None = None

    def triangle_rows(self) -> IdArray:
        """The (T x 3) canonical triangles (u, v, w with u smallest), in row order."""
        rows = self.halfedges
        first = (rows[:, 0] < rows[:, 1]) & (rows[:, 0] < rows[:, 2])
        return rows[first]

    def tables(self) -> tuple[immutables.Map[int, Point2], immutables.Map[Edge, int],
                              immutables.Map[int, int]]:
        """(vertices, halfedges, outgoing) as persistent maps."""
        count = len(self.points)
        # one int object per vertex id, shared by every key and value naming it (a
        # million-triangle mesh names ~10^7 ids: 28 bytes each would be ~300 MB)
        ids = list(range(count))
        name = ids.__getitem__
        u, v, w = (list(map(name, column)) for column in self.halfedges.T.tolist())
        keys = list(zip(u, v, strict=True))
        base = self.base
        if base is None:
            vertices = immutables.Map(zip(ids, self.points, strict=True))
            halfedges = immutables.Map(zip(keys, w, strict=True))
        else:
            vertex_table = base.vertices.mutate()
            for vertex in range(len(base.vertices), count):
                vertex_table[ids[vertex]] = self.points[vertex]
            vertices = vertex_table.finish()
            old = base.halfedges
            new = dict(zip(keys, w, strict=True))
            table = old.mutate()
            for key in old:
                if key not in new:
                    del table[key]
            get = old.get
            for key, apex in new.items():
                if get(key) != apex:
                    table[key] = apex
            halfedges = table.finish()
        hints = self.hints.tolist()
        outgoing = immutables.Map(
            (ids[vertex], ids[hint]) for vertex, hint in enumerate(hints) if hint >= 0
        )
        return vertices, halfedges, outgoing


_Tables2: TypeAlias = tuple[immutables.Map[int, Point2], immutables.Map[Edge, int],
                           immutables.Map[int, int]]


@attrs.frozen(slots=True, eq=False)
class Mesh2(SourcedSnapshot[Point2, _Tables2]):
    """An immutable 2D triangle mesh with exact rational vertices.

    Tables (all persistent maps):

    - ``vertices``: id -> :class:`Point2`, ids 0..n-1 in insertion order;
    - ``halfedges``: ``(u, v)`` -> apex w, for each counter-clockwise triangle
      (u, v, w) and each of its three directed edges;
    - ``outgoing``: vertex -> some w such that (vertex, w) is a half-edge (a hint to walk
      the star of a vertex; absent for a vertex in no triangle);
    - ``segments``: ``(min, max)`` -> boundary marker of a constrained segment;
    - ``vertex_markers`` / ``vertex_attributes`` / ``triangle_attributes``: the Triangle
      program's boundary markers and attributes, stored only where non-default.

    ``digest`` is the order-independent content digest kept up to date by every step.
    Equality (``==``) compares content: vertices, triangles, segments, markers, attributes.
    """

    # the three large tables are built on first use (kept in ``_derived``) when the
    # snapshot was given a ``source`` (a kernel's arrays) instead: a command that only
    # summarizes and writes the result never pays for them
    _vertices: immutables.Map[int, Point2] | None
    _halfedges: immutables.Map[Edge, int] | None
    _outgoing: immutables.Map[int, int] | None
    segments: immutables.Map[Edge, int]
    vertex_markers: immutables.Map[int, int]
    vertex_attributes: immutables.Map[int, Attributes]
    triangle_attributes: immutables.Map[Triangle, Attributes]
    triangle_count: int
    digest: int
    _source: TableSource | None = attrs.field(default=None, kw_only=True, repr=False)
    """The arrays the tables are built from when they are None (:class:`TableSource`)."""
    _derived: Derived = attrs.field(init=False, factory=Derived, repr=False)
    """The tables built from ``source`` (:class:`~geomexact.kernel.derived.Derived`)."""

    # -- tables (``vertices``: :class:`SourcedSnapshot`) ---------------------------------
    @property
    def halfedges(self) -> immutables.Map[Edge, int]:
        """``(u, v)`` -> apex w of the counter-clockwise triangle (u, v, w)."""
        table = self._halfedges
        return self._built()[1] if table is None else table

    @property
    def outgoing(self) -> immutables.Map[int, int]:
        """vertex -> some w such that (vertex, w) is a half-edge."""
        table = self._outgoing
        return self._built()[2] if table is None else table

    @property
    def source(self) -> TableSource | None:
        """The arrays this snapshot's tables come from, while they are not built yet
        (None once built, or when it was built from tables)."""
        if self._halfedges is not None or self._derived.known("tables"):
            return None
        return self._source

    # -- size (``vertex_count``, ``digest_text``: :class:`SourcedSnapshot`) -------------
    def transient(self, *, batch: bool = False) -> Transient2:
        """A batch editor opened on this snapshot (:class:`~geomexact.mesh2d.transient.
        Transient2`); the snapshot itself never changes."""
        transient: Transient2 = kind_of(Mesh2).transient(self, batch=batch)
        return transient

    def replayed_by_engine(self, steps: Sequence[Step], digests: Sequence[int]
                           ) -> Mesh2 | None:
        """The mesh after ``steps`` replayed on this one by the compiled Lepp kernel (each
        step's preconditions and digest checked), or None when it cannot (then replay
        with the reference ops: :func:`geomexact.trace.playback.replay` does)."""
        engine = kind_of(Mesh2).replay_engine
        replayed: Mesh2 | None = None if engine is None else engine(self, steps, digests)
        return replayed

    # -- elements (``point``, ``point_list``: :class:`SourcedSnapshot`) -----------------
    def apex(self, u: int, v: int) -> int | None:
        """The third vertex of the triangle left of the directed edge (u, v), or None."""
        return self.halfedges.get((u, v))

    def has_triangle(self, triangle: Triangle) -> bool:
        """True when (a, b, c) is a counter-clockwise triangle of the mesh."""
        a, b, c = triangle
        return self.halfedges.get((a, b)) == c

    def iter_triangles(self) -> Iterator[Triangle]:
        """Triangles in canonical form, in table order (not sorted; see :meth:`triangles`)."""
        source = self.source
        if source is not None:
            yield from map(tuple, source.triangle_rows().tolist())  # type: ignore[misc]
            return
        for key, c in self.halfedges.items():
            a, b = key
            if a < b and a < c:
                yield a, b, c

    def triangles(self) -> list[Triangle]:
        """All triangles in canonical form, sorted.  O(n log n)."""
        return sorted(self.iter_triangles())

    def cells(self) -> list[Triangle]:
        """The cells (:meth:`triangles`): what the trace tools compare between steps."""
        return self.triangles()

    def edges(self) -> list[Edge]:
        """All edges as sorted (min, max) pairs.  O(n log n)."""
        found = set()
        for key in self.halfedges:
            u, v = key
            found.add((u, v) if u < v else (v, u))
        return sorted(found)

    def boundary_edges(self) -> list[Edge]:
        """Directed edges (u, v) of triangles with no triangle on their right, sorted."""
        halfedges = self.halfedges
        return sorted((u, v) for u, v in halfedges if (v, u) not in halfedges)

    def is_boundary_edge(self, u: int, v: int) -> bool:
        """True when {u, v} is an edge with a triangle on exactly one side."""
        forward = (u, v) in self.halfedges
        backward = (v, u) in self.halfedges
        return forward != backward

    def is_edge(self, u: int, v: int) -> bool:
        """True when {u, v} is an edge of some triangle."""
        return (u, v) in self.halfedges or (v, u) in self.halfedges

    def segment_list(self) -> list[tuple[int, int, int]]:
        """Constrained segments as sorted (u, v, marker) with u < v."""
        return sorted((u, v, marker) for (u, v), marker in self.segments.items())

    def is_constrained(self, u: int, v: int) -> bool:
        """True when {u, v} is a constrained segment."""
        a, b = (u, v) if u < v else (v, u)
        return (a, b) in self.segments

    def star(self, vertex: int) -> list[Triangle]:
        """Triangles around ``vertex`` in counter-clockwise order, each rotated to start at
        ``vertex`` (see :func:`walk_star`).  O(degree)."""
        return walk_star(self.apex, vertex, self.outgoing.get(vertex))

    # -- comparison ---------------------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Mesh2):
            return NotImplemented
        return (
            self.digest == other.digest
            and self.triangle_count == other.triangle_count
            and self.vertices == other.vertices
            and _same_triangles(self.halfedges, other.halfedges)
            and self.segments == other.segments
            and self.vertex_markers == other.vertex_markers
            and self.vertex_attributes == other.vertex_attributes
            and self.triangle_attributes == other.triangle_attributes
        )

    def __hash__(self) -> int:
        return self.digest

    def __repr__(self) -> str:
        return (
            f"Mesh2(vertices={self.vertex_count}, triangles={self.triangle_count}, "
            f"segments={len(self.segments)}, digest={self.digest_text})"
        )


def walk_star(
    apex: Callable[[int, int], int | None], vertex: int, start: int | None
) -> list[Triangle]:
    """Triangles (vertex, w, x) around ``vertex`` in counter-clockwise order.

    ``apex(u, v)`` gives the third vertex left of (u, v); ``start`` is any w with (vertex, w)
    a half-edge (or None for an isolated vertex).  For a boundary vertex the list starts
    just after the boundary gap; for an interior vertex it starts at ``start``.
    """
    if start is None:
        return []
    first = start
    while True:  # walk clockwise to the boundary, or all the way round
        previous = apex(first, vertex)
        if previous is None:
            break
        if previous == start:
            first = start
            break
        first = previous
    result: list[Triangle] = []
    w = first
    while True:
        x = apex(vertex, w)
        if x is None:
            break
        result.append((vertex, w, x))
        w = x
        if w == first:
            break
    return result


def _last_neighbour(apex: Callable[[int, int], int | None], u: int, v: int, around: int) -> int:
    """Turn around ``around`` (v or u) from the boundary half-edge (u, v) through the
    triangles there, and return the last neighbour reached before the boundary."""
    x = apex(u, v)
    while x is not None:
        y = apex(x, v) if around == v else apex(u, x)
        if y is None:
            return x
        x = y
    raise ValueError(f"({u}, {v}) is not a boundary half-edge")


def next_boundary_edge(apex: Callable[[int, int], int | None], u: int, v: int) -> Edge:
    """The boundary half-edge (v, z) that follows the boundary half-edge (u, v) (a
    half-edge with a triangle on its left and none on its right), found by turning around
    v.  O(degree of v)."""
    return v, _last_neighbour(apex, u, v, around=v)


def previous_boundary_edge(apex: Callable[[int, int], int | None], u: int, v: int) -> Edge:
    """The boundary half-edge (z, u) that precedes the boundary half-edge (u, v).
    O(degree of u)."""
    return _last_neighbour(apex, u, v, around=u), u


def _same_triangles(a: Mapping[Edge, int], b: Mapping[Edge, int]) -> bool:
    return len(a) == len(b) and all(b.get(key) == apex for key, apex in a.items())


def empty_mesh() -> Mesh2:
    """The mesh with no vertices and no triangles."""
    return Mesh2(
        vertices=immutables.Map(),
        halfedges=immutables.Map(),
        outgoing=immutables.Map(),
        segments=immutables.Map(),
        vertex_markers=immutables.Map(),
        vertex_attributes=immutables.Map(),
        triangle_attributes=immutables.Map(),
        triangle_count=0,
        digest=0,
    )


def full_digest(mesh: Mesh2) -> int:
    """The digest recomputed from the mesh's content (O(n)); equals ``mesh.digest`` for
    every valid snapshot."""
    total = 0
    for vertex, point in mesh.vertices.items():
        total = _digest.combine(total, _digest.vertex_hash(vertex, point[:2]))
    for triangle in mesh.iter_triangles():
        total = _digest.combine(total, _digest.cell_hash(triangle))
    for key, marker in mesh.segments.items():
        u, v = key
        total = _digest.combine(total, _digest.segment_hash(u, v, marker))
    for vertex, marker in mesh.vertex_markers.items():
        total = _digest.combine(total, _digest.attribute_hash("vm", (vertex,), (marker,)))
    for vertex, values in mesh.vertex_attributes.items():
        total = _digest.combine(total, _digest.attribute_hash("va", (vertex,), values))
    for triangle, values in mesh.triangle_attributes.items():
        total = _digest.combine(total, _digest.attribute_hash("ta", triangle, values))
    return total
