"""The store of the Python batch engines: a triangulation on plain dicts, edited by the
triangle edits of :mod:`geomexact.mesh2d.ops` without their precondition checks, with the
digest kept incrementally and every step recorded with the digest after it.

Every op is written once, against :class:`~geomexact.mesh2d.transient.Transient2`, which
checks each precondition and keeps persistent maps (an edit costs a map mutation).  An
engine that chose a step knows its preconditions hold; it edits a
:class:`BatchTriangulation` instead: a dict of half-edges (a tenth of the cost of a map
mutation), the points as a list, the cell hash of each triangle it made (a triangle is
hashed once, even when a later step removes it), sealed into a snapshot once at the end.
The store offers the edits the ops' triangle edits need (:class:`geomexact.mesh2d.ops.
TriangleEditor`), so ``ops.join_in_edge`` and the others apply to it unchanged; it makes
the flip and Lawson legalization itself.
The incremental Delaunay insertion
(:class:`geomexact.mesh2d.delaunay.triangulation.BatchDelaunay`) builds on it (the Lepp
refinement's batch engine that also did was retired: the compiled kernel and the reference
ops are its two tiers); its traces are tested equal to the compiled kernel's step by step
(``tests/engines``), and replay through the reference ops.
"""

from __future__ import annotations

from typing import Any

import attrs
import immutables

from geomexact.kernel import digest as _digest
from geomexact.kernel.dyadic_grid import grid_flags
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import CircleLocation, Orientation
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.mesh2d.snapshot import Attributes, Edge, Mesh2, Triangle, canonical_triangle
from geomexact.trace.step import Step

_CCW = Orientation.COUNTERCLOCKWISE
_INSIDE = CircleLocation.INSIDE
_MASK = _digest.MODULUS - 1
_cell_hash = _digest.cell_hash


class BatchTriangulation:
    """A triangulation edited in batch by one run, started from a snapshot (its points,
    half-edges, segments, triangle attributes and digest).

    ``halfedges`` maps each directed edge (u, v) of a counter-clockwise triangle (u, v, w)
    to w, as :attr:`Mesh2.halfedges` does; ``points[i]`` is vertex i; ``grid[i]`` says whether it
    is on the dyadic grid of ``scale`` (:mod:`geomexact.kernel.dyadic_grid`); ``steps`` and
    ``digests`` are the run's record.  Subclasses
    extend the start of a step (:meth:`begin_step`: a step limit) and the recording
    (:meth:`record`: progress reports)."""

    __slots__ = (
        "attributed",
        "digest",
        "digests",
        "grid",
        "halfedges",
        "hashes",
        "points",
        "scale",
        "segments",
        "steps",
        "triangle_attrs",
    )

    def __init__(self, mesh: Mesh2) -> None:
        self.points: list[Point2] = [mesh.vertices[i] for i in range(mesh.vertex_count)]
        self.halfedges: dict[Edge, int] = dict(mesh.halfedges.items())
        self.hashes: dict[Triangle, int] = {}
        self.digest = mesh.digest
        self.steps: list[Step] = []
        self.digests: list[int] = []
        self.segments: dict[Edge, int] = dict(mesh.segments.items())
        self.triangle_attrs: dict[Triangle, Attributes] = dict(
            mesh.triangle_attributes.items()
        )
        self.attributed = bool(self.triangle_attrs)
        self.scale, self.grid = grid_flags(self.points)

    # -- reads --------------------------------------------------------------------------
    def apex(self, u: int, v: int) -> int | None:
        """Third vertex of the triangle left of (u, v), or None."""
        return self.halfedges.get((u, v))

    def segment_marker(self, u: int, v: int) -> int | None:
        """Marker of the constrained segment {u, v}, or None when it is not constrained."""
        return self.segments.get((u, v) if u < v else (v, u))

    def is_segment(self, u: int, v: int) -> bool:
        return ((u, v) if u < v else (v, u)) in self.segments

    def attributes(self, triangle: Triangle) -> Attributes | None:
        return self.triangle_attrs.get(canonical_triangle(*triangle))

    def different_attributes(self, u: int, v: int, w: int, x: int) -> bool:
        """True when the triangles (u, v, w) and (v, u, x) carry different attributes."""
        return self.attributes((u, v, w)) != self.attributes((v, u, x))

    # -- the record ---------------------------------------------------------------------
    def begin_step(self) -> None:
        """Called before a step changes anything (subclasses refuse a step here)."""

    def record(self, op: str, args: tuple[Any, ...]) -> None:
        """Append the step just completed and the digest after it."""
        self.steps.append(Step(op, args))
        self.digests.append(self.digest)

    # -- triangles ----------------------------------------------------------------------
    def _enter(self, a: int, b: int, c: int, attributes: Attributes | None) -> None:
        """Account for the new triangle (a, b, c): its cell hash (cached), its attributes,
        the digest."""
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        value = self.hashes[key] = _cell_hash(key)
        total = self.digest + value
        if attributes:
            self.triangle_attrs[key] = attributes
            total += _digest.attribute_hash("ta", key, attributes)
        self.digest = total & _MASK

    def _leave(self, a: int, b: int, c: int) -> Attributes | None:
        """Account for the removed triangle (a, b, c); return its attributes."""
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        value = self.hashes.pop(key, None)
        total = self.digest - (_cell_hash(key) if value is None else value)
        attributes = None
        if self.attributed:
            attributes = self.triangle_attrs.pop(key, None)
            if attributes is not None:
                total -= _digest.attribute_hash("ta", key, attributes)
        self.digest = total & _MASK
        return attributes

    def add_triangle(
        self, a: int, b: int, c: int, attributes: Attributes | None = None
    ) -> None:
        """Add the counter-clockwise triangle (a, b, c) (its half-edges are free)."""
        halfedges = self.halfedges
        halfedges[(a, b)] = c
        halfedges[(b, c)] = a
        halfedges[(c, a)] = b
        self._enter(a, b, c, attributes)

    def remove_triangle(self, a: int, b: int, c: int) -> Attributes | None:
        """Remove the triangle (a, b, c); return its attributes."""
        halfedges = self.halfedges
        del halfedges[(a, b)]
        del halfedges[(b, c)]
        del halfedges[(c, a)]
        return self._leave(a, b, c)

    # -- segments -----------------------------------------------------------------------
    def set_segment(self, u: int, v: int, marker: int = 0) -> None:
        """Mark the unconstrained edge {u, v} as a segment with ``marker``."""
        key = (u, v) if u < v else (v, u)
        self.segments[key] = marker
        self.digest = (self.digest + _digest.segment_hash(key[0], key[1], marker)) & _MASK

    def remove_segment(self, u: int, v: int) -> int:
        """Unconstrain {u, v}; return its marker."""
        key = (u, v) if u < v else (v, u)
        marker = self.segments.pop(key)
        self.digest = (self.digest - _digest.segment_hash(key[0], key[1], marker)) & _MASK
        return marker

    # -- the steps the store makes itself ------------------------------------------------
    # (the other triangle edits are the ops' own: ops.join_in_edge, join_in_triangle and
    # join_in_quadrilateral take this store as they take a transient)
    def flip(self, u: int, v: int) -> None:
        """The step :func:`geomexact.mesh2d.ops.flip_in`: the triangles (u, v, w) and
        (v, u, x) of an unconstrained interior edge with a strictly convex quadrilateral
        become (x, w, u) and (w, x, v)."""
        self.begin_step()
        halfedges = self.halfedges
        w, x = halfedges[(u, v)], halfedges[(v, u)]
        # not flip_in's remove and add: the four outer half-edges keep their dict entries,
        # with a new apex, because the Delaunay engine's outgoing hints come from the
        # dict's insertion order (and the compiled kernel keeps that order)
        del halfedges[(u, v)]
        del halfedges[(v, u)]
        halfedges[(x, w)] = u
        halfedges[(w, u)] = x
        halfedges[(u, x)] = w
        halfedges[(w, x)] = v
        halfedges[(x, v)] = w
        halfedges[(v, w)] = x
        attributes = self._leave(u, v, w)
        self._leave(v, u, x)
        self._enter(x, w, u, attributes)
        self._enter(w, x, v, attributes)
        self.record("flip", (u, v))

    def legalize_edges(self, vertex: int, pending: list[Edge]) -> None:
        """Lawson flips around ``vertex``, as :func:`geomexact.mesh2d.ops.legalize_in`
        makes them, from the stack ``pending`` of edges (a, b) opposite ``vertex`` in
        triangles (vertex, a, b): pop one; when that triangle still exists, the edge is
        unconstrained and interior, its other apex q lies strictly inside the circle
        through vertex, a, b, the quadrilateral is strictly convex and both triangles carry
        the same attributes, flip it and push (q, b) then (a, q).  Cocircular points never
        cause a flip."""
        get = self.halfedges.get
        points, grid, segments = self.points, self.grid, self.segments
        attributed = self.attributed
        p = points[vertex]
        px, py = p[2], p[3]
        on_grid = grid[vertex]
        while pending:
            a, b = pending.pop()
            if get((vertex, a)) != b:
                continue
            q = get((b, a))
            if q is None or ((a, b) if a < b else (b, a)) in segments:
                continue
            pa, pb, pq = points[a], points[b], points[q]
            # q is strictly inside the circle through p, a, b exactly when the angles at p
            # and q facing {a, b} sum to more than 180°.  Two right or acute angles (dot
            # products >= 0, exact in floats on the dyadic grid) settle it without
            # incircle, whose filter cannot decide the cocircular case (common on the grid:
            # squares) and falls back to slower exact arithmetic.  Off the grid the exact
            # dot products cost more than the filter they would save.
            if on_grid and grid[a] and grid[b] and grid[q]:
                ax, ay, bx, by, qx, qy = pa[2], pa[3], pb[2], pb[3], pq[2], pq[3]
                if (ax - px) * (bx - px) + (ay - py) * (by - py) >= 0 and (
                    (ax - qx) * (bx - qx) + (ay - qy) * (by - qy) >= 0
                ):
                    continue
            if incircle(p, pa, pb, pq) != _INSIDE:
                continue
            if orient2d(pq, p, pa) != _CCW or orient2d(p, pq, pb) != _CCW:
                continue
            if attributed and self.different_attributes(a, b, vertex, q):
                continue
            self.flip(a, b)
            pending.append((q, b))
            pending.append((a, q))

    # -- sealing ------------------------------------------------------------------------
    def sealed(self, start: Mesh2, **tables: Any) -> Mesh2:
        """The snapshot of this triangulation: ``start`` with the run's half-edges,
        segments, triangle attributes, triangle count and digest, and ``tables`` (the
        vertex tables and ``outgoing``, which the engines keep in their own ways)."""
        return attrs.evolve(
            start,
            halfedges=immutables.Map(self.halfedges),
            segments=immutables.Map(self.segments),
            triangle_attributes=immutables.Map(self.triangle_attrs)
            if self.attributed
            else start.triangle_attributes,
            triangle_count=len(self.halfedges) // 3,
            digest=self.digest,
            **tables,
        )
