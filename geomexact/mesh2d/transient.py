"""The batch builder: a mutable editor of one :class:`Mesh2`, sealed into a new snapshot.

A :class:`Transient2` holds ``immutables`` map mutations of a snapshot's tables, so edits
cost what a dict edit costs and sealing costs O(1); the snapshot it started from never
changes.  Every op of :mod:`geomexact.mesh2d.ops` is written once against this editor: the pure
function ``flip(mesh, edge)`` is "open a transient, flip, seal".  A transient belongs to
the function that opened it: it is sealed (and unusable) before that function returns.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence

import immutables

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.snapshot import (
    Attributes,
    Edge,
    Mesh2,
    Triangle,
    canonical_triangle,
    empty_mesh,
)
from geomexact.trace.recording import RecordingTransient
from geomexact.trace.tables import open_table, sealed_table, table_snapshot

_cell_hash = _digest.cell_hash
_MASK = _digest.MODULUS - 1


class Transient2(RecordingTransient[Point2]):
    """Mutable editor of a 2D mesh.  Low-level edits keep the digest and the adjacency
    tables consistent; geometric preconditions are checked by the ops, not here.  Its
    steps go through the 2D step table (:data:`geomexact.mesh2d.ops.OPERATIONS`)."""

    __slots__ = (
        "_halfedges",
        "_outgoing",
        "_segments",
        "_triangle_attributes",
        "_triangle_count",
        "_vertex_attributes",
        "_vertex_markers",
        "stale_outgoing",
    )

    snapshot_type = Mesh2

    def __init__(self, mesh: Mesh2, *, batch: bool = False) -> None:
        """Open on ``mesh``; ``batch`` edits plain dicts instead of the maps' mutations
        (O(n) to open and seal, cheaper writes: for long runs, :mod:`geomexact.trace.
        tables`)."""
        self._open_record(mesh.vertices, mesh.digest, batch)
        self._halfedges = open_table(mesh.halfedges, batch)
        self._outgoing = open_table(mesh.outgoing, batch)
        self._segments = open_table(mesh.segments, batch)
        self._vertex_markers = open_table(mesh.vertex_markers, batch)
        self._vertex_attributes = open_table(mesh.vertex_attributes, batch)
        self._triangle_attributes = open_table(mesh.triangle_attributes, batch)
        self._triangle_count = mesh.triangle_count
        self.stale_outgoing: set[int] = set()

    # -- reads --------------------------------------------------------------------------
    @property
    def triangle_count(self) -> int:
        return self._triangle_count

    def apex(self, u: int, v: int) -> int | None:
        """Third vertex of the triangle left of (u, v), or None."""
        return self._halfedges.get((u, v))

    def segment_marker(self, u: int, v: int) -> int | None:
        """Marker of the constrained segment {u, v}, or None when it is not constrained."""
        return self._segments.get((u, v) if u < v else (v, u))

    def vertex_marker(self, vertex: int) -> int:
        return self._vertex_markers.get(vertex, 0)

    def vertex_attributes(self, vertex: int) -> Attributes:
        """The attributes of ``vertex`` (``()`` when it has none)."""
        if not len(self._vertex_attributes):
            return ()
        return self._vertex_attributes.get(vertex, ())

    def triangle_attributes(self, triangle: Triangle) -> Attributes | None:
        if not len(self._triangle_attributes):
            return None
        return self._triangle_attributes.get(canonical_triangle(*triangle))

    def outgoing(self, vertex: int) -> int | None:
        """Some w with (vertex, w) a half-edge, or None."""
        w = self._outgoing.get(vertex)
        if w is not None and (vertex, w) in self._halfedges:
            return w
        return None

    def halfedges_snapshot(self) -> immutables.Map[Edge, int]:
        """The current half-edge table as an immutable map (to iterate over it).  O(1):
        the mutation is finished and reopened; later writes copy the trie paths they touch.
        """
        snapshot, self._halfedges = table_snapshot(self._halfedges)
        return snapshot

    def iter_edges(self) -> Iterator[tuple[int, int]]:
        """Every edge once, as (u, v) with u < v, in table order.  O(n)."""
        halfedges = self.halfedges_snapshot()
        for key in halfedges:
            u, v = key
            if u < v or (v, u) not in halfedges:
                yield (u, v) if u < v else (v, u)

    # -- edits --------------------------------------------------------------------------
    def add_vertex(
        self, point: Point2, marker: int = 0, attributes: Attributes = ()
    ) -> int:
        """Append a vertex (in no triangle yet) and return its id."""
        vertex = self._append_vertex(point, point[:2])
        if marker:
            self._vertex_markers[vertex] = marker
            self._digest = _digest.combine(
                self._digest, _digest.attribute_hash("vm", (vertex,), (marker,))
            )
        if attributes:
            self._vertex_attributes[vertex] = tuple(attributes)
            self._digest = _digest.combine(
                self._digest, _digest.attribute_hash("va", (vertex,), attributes)
            )
        return vertex

    def set_vertex_marker(self, vertex: int, marker: int) -> None:
        """Replace the boundary marker of ``vertex``."""
        self._check_open()
        old = self._vertex_markers.get(vertex, 0)
        if old == marker:
            return
        if old:
            del self._vertex_markers[vertex]
            self._digest = _digest.remove(
                self._digest, _digest.attribute_hash("vm", (vertex,), (old,))
            )
        if marker:
            self._vertex_markers[vertex] = marker
            self._digest = _digest.combine(
                self._digest, _digest.attribute_hash("vm", (vertex,), (marker,))
            )

    def add_triangle(
        self, a: int, b: int, c: int, attributes: Attributes | None = None
    ) -> None:
        """Add the counter-clockwise triangle (a, b, c); its half-edges must be free."""
        if self._sealed:
            self._check_open()
        halfedges = self._halfedges
        ab, bc, ca = (a, b), (b, c), (c, a)
        if ab in halfedges or bc in halfedges or ca in halfedges:
            raise PreconditionError(
                "add_triangle",
                f"triangle {(a, b, c)} overlaps an existing triangle on one of its edges",
                triangle=(a, b, c),
            )
        halfedges[ab] = c
        halfedges[bc] = a
        halfedges[ca] = b
        outgoing = self._outgoing
        outgoing[a] = b
        outgoing[b] = c
        outgoing[c] = a
        self._triangle_count += 1
        # canonical_triangle and digest.combine, inlined: the hot path of every step
        canonical = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        self._digest = (self._digest + _cell_hash(canonical)) & _MASK
        if attributes:
            self._triangle_attributes[canonical] = attributes
            self._digest = _digest.combine(
                self._digest, _digest.attribute_hash("ta", canonical, attributes)
            )

    def remove_triangle(self, a: int, b: int, c: int) -> Attributes | None:
        """Remove the triangle (a, b, c) (any rotation); return its attributes."""
        if self._sealed:
            self._check_open()
        halfedges = self._halfedges
        ab = (a, b)
        if halfedges.get(ab) != c:
            raise PreconditionError(
                "remove_triangle", f"{(a, b, c)} is not a triangle", triangle=(a, b, c)
            )
        del halfedges[ab]
        del halfedges[(b, c)]
        del halfedges[(c, a)]
        self.stale_outgoing.update((a, b, c))
        self._triangle_count -= 1
        canonical = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        self._digest = (self._digest - _cell_hash(canonical)) & _MASK
        if len(self._triangle_attributes):
            attributes = self._triangle_attributes.get(canonical)
            if attributes is not None:
                del self._triangle_attributes[canonical]
                self._digest = _digest.remove(
                    self._digest, _digest.attribute_hash("ta", canonical, attributes)
                )
                return attributes
        return None

    def set_triangle_attributes(self, triangle: Triangle, attributes: Attributes) -> None:
        """Replace the attributes of an existing triangle (any rotation); ``()`` clears."""
        self._check_open()
        a, b, c = triangle
        old = self.remove_triangle(a, b, c)
        del old
        self.add_triangle(a, b, c, tuple(attributes) or None)

    def set_segment(self, u: int, v: int, marker: int = 0) -> None:
        """Mark {u, v} as a constrained segment with ``marker`` (replacing any marker)."""
        self._check_open()
        if u == v:
            raise PreconditionError("set_segment", f"segment ({u}, {v}) has equal ends")
        key = (u, v) if u < v else (v, u)
        old = self._segments.get(key)
        if old is not None:
            self._digest = _digest.remove(
                self._digest, _digest.segment_hash(min(u, v), max(u, v), old)
            )
        self._segments[key] = marker
        self._digest = _digest.combine(
            self._digest, _digest.segment_hash(min(u, v), max(u, v), marker)
        )

    def remove_segment(self, u: int, v: int) -> int:
        """Unconstrain {u, v}; return its marker."""
        self._check_open()
        key = (u, v) if u < v else (v, u)
        marker = self._segments.pop(key)
        self._digest = _digest.remove(
            self._digest, _digest.segment_hash(min(u, v), max(u, v), marker)
        )
        return marker

    # -- sealing ------------------------------------------------------------------------
    def _repair_outgoing(self) -> None:
        halfedges, outgoing = self._halfedges, self._outgoing
        broken = []
        for vertex in self.stale_outgoing:
            w = outgoing.get(vertex)
            if w is not None and (vertex, w) not in halfedges:
                broken.append(vertex)
        if not broken:
            self.stale_outgoing.clear()
            return
        # rare (triangles removed without replacement, e.g. carving a hole): one scan; the
        # new hint is the smallest neighbour, so it does not depend on the table's order
        wanted = set(broken)
        for vertex in broken:
            del outgoing[vertex]
        best: dict[int, int] = {}
        for u, w in self.halfedges_snapshot():
            if u in wanted and (u not in best or w < best[u]):
                best[u] = w
        for vertex, w in best.items():
            outgoing[vertex] = w
        self.stale_outgoing.clear()

    def seal(self) -> Mesh2:
        """Finish the edits and return the new snapshot; the transient is then unusable."""
        self._check_open()
        self._repair_outgoing()
        self._sealed = True
        return Mesh2(
            vertices=sealed_table(self._vertices),
            halfedges=sealed_table(self._halfedges),
            outgoing=sealed_table(self._outgoing),
            segments=sealed_table(self._segments),
            vertex_markers=sealed_table(self._vertex_markers),
            vertex_attributes=sealed_table(self._vertex_attributes),
            triangle_attributes=sealed_table(self._triangle_attributes),
            triangle_count=self._triangle_count,
            digest=self._digest,
        )


def mesh_from_triangles(
    points: Sequence[Point2 | tuple[object, object]],
    triangles: Iterable[Sequence[int]],
    segments: Iterable[Sequence[int]] = (),
    *,
    vertex_markers: Sequence[int] | None = None,
    vertex_attributes: Sequence[Attributes] | None = None,
    triangle_attributes: Sequence[Attributes] | None = None,
    orient: bool = False,
) -> Mesh2:
    """Build a snapshot from vertex and triangle tables.

    ``points`` are :class:`Point2` or coordinate pairs (converted exactly); ``triangles``
    are vertex-index triples, counter-clockwise unless ``orient=True`` (then each clockwise
    triangle is reversed); ``segments`` are (u, v) or (u, v, marker).  Raises
    :class:`PreconditionError` for an index out of range, a degenerate (collinear)
    triangle, a clockwise triangle when ``orient`` is false, or two triangles on the same
    side of an edge.  O(n) map updates.
    """
    transient = Transient2(empty_mesh())
    for index, raw in enumerate(points):
        point = raw if isinstance(raw, Point2) else point2(*raw)
        marker = vertex_markers[index] if vertex_markers is not None else 0
        attributes = vertex_attributes[index] if vertex_attributes is not None else ()
        transient.add_vertex(point, marker, attributes)
    count = transient.vertex_count
    for index, raw_triangle in enumerate(triangles):
        a, b, c = (int(i) for i in raw_triangle)
        for vertex in (a, b, c):
            if not 0 <= vertex < count:
                raise PreconditionError(
                    "mesh_from_triangles",
                    f"triangle #{index} {(a, b, c)} refers to vertex {vertex}, "
                    f"but there are {count} vertices",
                    triangle=index,
                )
        if len({a, b, c}) != 3:
            raise PreconditionError(
                "mesh_from_triangles", f"triangle #{index} {(a, b, c)} repeats a vertex"
            )
        orientation = orient2d(transient.point(a), transient.point(b), transient.point(c))
        if orientation == Orientation.COLLINEAR:
            raise PreconditionError(
                "mesh_from_triangles",
                f"triangle #{index} {(a, b, c)} is degenerate (its vertices are collinear)",
                triangle=index,
            )
        if orientation == Orientation.CLOCKWISE:
            if not orient:
                raise PreconditionError(
                    "mesh_from_triangles",
                    f"triangle #{index} {(a, b, c)} is clockwise",
                    triangle=index,
                )
            b, c = c, b
        values = triangle_attributes[index] if triangle_attributes is not None else None
        try:
            transient.add_triangle(a, b, c, values or None)
        except PreconditionError as error:
            raise PreconditionError(
                "mesh_from_triangles",
                f"triangle #{index} {(a, b, c)} shares a directed edge with an earlier "
                "triangle (overlapping or inconsistently oriented triangles)",
                triangle=index,
            ) from error
    for raw_segment in segments:
        u, v = int(raw_segment[0]), int(raw_segment[1])
        marker = int(raw_segment[2]) if len(raw_segment) > 2 else 0
        for vertex in (u, v):
            if not 0 <= vertex < count:
                raise PreconditionError(
                    "mesh_from_triangles", f"segment {(u, v)} refers to a missing vertex"
                )
        transient.set_segment(u, v, marker)
    return transient.seal()
