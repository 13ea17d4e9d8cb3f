"""Delaunay property of 2D meshes (exact).

An interior edge {u, v} with triangles (u, v, w) and (v, u, x) is *locally Delaunay* when x
is not strictly inside the circle through u, v, w.  A mesh is (constrained) Delaunay when
every unconstrained interior edge is locally Delaunay; constrained segments are exempt.
Cocircular quadrilaterals count as Delaunay.  See ``specs/delaunay.md``.
"""

from __future__ import annotations

import gc
import math
import random
from collections.abc import Sequence

import attrs
import immutables

from geomexact.digest import MODULUS, cell_hash
from geomexact.errors import PreconditionError
from geomexact.mesh2d import (
    Edge,
    Mesh2,
    empty_mesh,
    next_boundary_edge,
    previous_boundary_edge,
)
from geomexact.points import Point2
from geomexact.predicates import CircleLocation, Orientation, incircle, orient2d
from geomexact.pslg import PSLG
from geomexact.step import Step
from geomexact.trace import Trace
from geomexact.transient import Transient2

_MASK = MODULUS - 1
CCW = Orientation.COUNTERCLOCKWISE
CW = Orientation.CLOCKWISE
COLLINEAR = Orientation.COLLINEAR
INSIDE = CircleLocation.INSIDE


def non_delaunay_edges(mesh: Mesh2) -> list[Edge]:
    """Sorted (u, v), u < v, of the unconstrained interior edges that are not locally
    Delaunay.  O(n) exact incircle tests."""
    halfedges, vertices, segments = mesh.halfedges, mesh.vertices, mesh.segments
    found = []
    for key, w in halfedges.items():
        u, v = key
        if u > v or key in segments:
            continue
        x = halfedges.get((v, u))
        if x is None:
            continue
        location = incircle(vertices[u], vertices[v], vertices[w], vertices[x])
        if location == CircleLocation.INSIDE:
            found.append((u, v))
    return sorted(found)


def is_delaunay(mesh: Mesh2) -> bool:
    """True when every unconstrained interior edge is locally Delaunay (exact)."""
    return not non_delaunay_edges(mesh)


# ---------------------------------------------------------------------------------------
# Delaunay triangulation of a point set (incremental, BRIO + snake order, walk)
# ---------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class Construction:
    """A triangulation run: the mesh of isolated input vertices it started from
    (``start``), the result (``mesh``), the trace replaying ``start`` to ``mesh``, and the
    duplicate input points that were merged (pairs ``(dropped id, kept id)``; the dropped
    vertex stays isolated)."""

    start: Mesh2
    mesh: Mesh2
    trace: Trace
    duplicates: tuple[tuple[int, int], ...] = ()


def vertices_mesh(pslg: PSLG) -> Mesh2:
    """The mesh of the PSLG's vertices (ids = PSLG ids, markers and attributes kept), with
    no triangles and no segments: the start of every triangulation trace."""
    transient = Transient2(empty_mesh())
    for index, point in enumerate(pslg.vertices):
        attributes = pslg.vertex_attributes[index] if pslg.vertex_attributes else ()
        transient.add_vertex(point, pslg.marker(index), attributes)
    return transient.seal()


def insertion_order(points: Sequence[Point2], *, seed: int = 0) -> list[int]:
    """A biased randomized insertion order (Amenta–Choi–Rote): a seeded shuffle cut into
    rounds of doubling size, each round sorted along a snake (boustrophedon) curve over a
    grid of about 2 points per cell.  Deterministic for given points and seed; O(n log n).
    """
    order = list(range(len(points)))
    random.Random(seed).shuffle(order)
    if not points:
        return order
    xs = [points[i].fx for i in order]
    ys = [points[i].fy for i in order]
    finite_x = [x for x in xs if math.isfinite(x)] or [0.0]
    finite_y = [y for y in ys if math.isfinite(y)] or [0.0]
    low_x, low_y = min(finite_x), min(finite_y)
    span = max(max(finite_x) - low_x, max(finite_y) - low_y) or 1.0
    rounds: list[list[int]] = []
    end = len(order)
    while end > 0:
        begin = end // 2 if end > 64 else 0
        rounds.append(order[begin:end])
        end = begin
    result: list[int] = []
    for chunk in reversed(rounds):
        cells = max(1, int(math.sqrt(len(chunk) / 2)))
        scale = cells / span

        keyed = []
        for vertex in chunk:
            point = points[vertex]
            x = point.fx if math.isfinite(point.fx) else low_x
            y = point.fy if math.isfinite(point.fy) else low_y
            column = min(cells - 1, int((x - low_x) * scale))
            keyed.append((column, (y - low_y) if column % 2 == 0 else (low_y - y), vertex))
        keyed.sort()
        result.extend(vertex for _, _, vertex in keyed)
    return result


class _DelaunayBuilder:
    """The batch builder of :func:`triangulate_points`: a plain half-edge dict, the
    incremental digest and the steps, owned by one call (same step semantics as
    :mod:`geomexact.ops`, checked by replaying the trace in the tests)."""

    __slots__ = ("apex", "digest", "digests", "hashes", "last", "points", "steps")

    def __init__(self, points: Sequence[Point2], digest: int) -> None:
        self.points = points
        self.apex: dict[tuple[int, int], int] = {}
        # cell hash of each live triangle, keyed by its canonical form: a triangle is
        # hashed once even when a later flip removes it
        self.hashes: dict[tuple[int, int, int], int] = {}
        self.digest = digest
        self.steps: list[Step] = []
        self.digests: list[int] = []
        self.last: tuple[int, int] = (0, 0)

    def _add(self, a: int, b: int, c: int) -> None:
        apex = self.apex
        apex[(a, b)] = c
        apex[(b, c)] = a
        apex[(c, a)] = b
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        value = self.hashes[key] = cell_hash(key)
        self.digest = (self.digest + value) & _MASK

    def _remove(self, a: int, b: int, c: int) -> None:
        apex = self.apex
        del apex[(a, b)]
        del apex[(b, c)]
        del apex[(c, a)]
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        self.digest = (self.digest - self.hashes.pop(key)) & _MASK

    def _record(self, op: str, args: tuple[int, ...]) -> None:
        self.steps.append(Step(op, args))
        self.digests.append(self.digest)

    def make_triangle(self, a: int, b: int, c: int) -> None:
        pa, pb, pc = self.points[a], self.points[b], self.points[c]
        if orient2d(pa, pb, pc) == CCW:
            self._add(a, b, c)
        else:
            self._add(a, c, b)
        self._record("make_triangle", (a, b, c))
        self.last = (a, b) if (a, b) in self.apex else (a, c)

    def locate(self, p: Point2) -> tuple[str, tuple[int, int, int]]:
        """Walk from the last triangle to ``p``: ("inside", (a, b, c)), ("edge", (u, v, _))
        or ("outside", (u, v, _)) for a boundary half-edge (u, v) with p strictly right."""
        apex, points = self.apex, self.points
        a, b = self.last
        c = apex[(a, b)]
        if orient2d(points[a], points[b], p) == CW:
            d = apex.get((b, a))
            if d is None:
                return "outside", (a, b, -1)
            a, b, c = b, a, d
        while True:
            pa, pb, pc = points[a], points[b], points[c]
            o1 = orient2d(pb, pc, p)
            if o1 == CW:
                d = apex.get((c, b))
                if d is None:
                    return "outside", (b, c, -1)
                a, b, c = c, b, d
                continue
            o2 = orient2d(pc, pa, p)
            if o2 == CW:
                d = apex.get((a, c))
                if d is None:
                    return "outside", (c, a, -1)
                a, b, c = a, c, d
                continue
            o0 = orient2d(pa, pb, p)
            if o0 == CW:  # only possible in the first triangle
                d = apex.get((b, a))
                if d is None:
                    return "outside", (a, b, -1)
                a, b, c = b, a, d
                continue
            if o1 == COLLINEAR:
                return "edge", (b, c, a)
            if o2 == COLLINEAR:
                return "edge", (c, a, b)
            if o0 == COLLINEAR:
                return "edge", (a, b, c)
            return "inside", (a, b, c)

    def insert(self, vertex: int) -> None:
        p = self.points[vertex]
        where, (a, b, c) = self.locate(p)
        apex = self.apex
        pending: list[tuple[int, int]]
        if where == "inside":
            self._remove(a, b, c)
            self._add(a, b, vertex)
            self._add(b, c, vertex)
            self._add(c, a, vertex)
            self._record("attach_in_triangle", (vertex, a, b, c))
            pending = [(c, a), (b, c), (a, b)]
        elif where == "edge":
            u, v = a, b
            w, x = apex.get((u, v)), apex.get((v, u))
            pending = []
            if w is not None:
                self._remove(u, v, w)
                self._add(u, vertex, w)
                self._add(vertex, v, w)
                pending += [(v, w), (w, u)]
            if x is not None:
                self._remove(v, u, x)
                self._add(v, vertex, x)
                self._add(vertex, u, x)
                pending += [(u, x), (x, v)]
            self._record("attach_in_edge", (vertex, u, v))
        else:
            pending = self._attach_outside(vertex, a, b)
        self.last = (vertex, pending[0][0])
        self._legalize(vertex, pending)

    def _attach_outside(self, vertex: int, u: int, v: int) -> list[tuple[int, int]]:
        apex, points = self.apex, self.points
        p = points[vertex]
        visible = [(u, v)]

        def find(a: int, b: int) -> int | None:
            return apex.get((a, b))

        edge = next_boundary_edge(find, u, v)
        while orient2d(points[edge[0]], points[edge[1]], p) == CW:
            visible.append(edge)
            edge = next_boundary_edge(find, *edge)
        edge = previous_boundary_edge(find, u, v)
        while orient2d(points[edge[0]], points[edge[1]], p) == CW:
            visible.insert(0, edge)
            edge = previous_boundary_edge(find, *edge)
        for a, b in visible:
            self._add(b, a, vertex)
        self._record("attach_outside", (vertex, u, v))
        return [(b, a) for a, b in visible]

    def _legalize(self, vertex: int, pending: list[tuple[int, int]]) -> None:
        """Lawson flips of the edges (a, b) opposite ``vertex`` in triangles
        (vertex, a, b)... given as (a, b) with apex(a, b) == vertex."""
        apex, points, hashes = self.apex, self.points, self.hashes
        steps, digests = self.steps, self.digests
        p = points[vertex]
        digest = self.digest
        while pending:
            a, b = pending.pop()
            q = apex.get((b, a))
            if q is None or apex.get((a, b)) != vertex:
                continue
            if incircle(points[a], points[b], p, points[q]) != INSIDE:
                continue
            # flip (a, b): triangles (a, b, vertex), (b, a, q) -> (q, vertex, a), (vertex, q, b)
            for key in (
                (a, b, vertex) if a < b and a < vertex else
                (b, vertex, a) if b < vertex else (vertex, a, b),
                (b, a, q) if b < a and b < q else (a, q, b) if a < q else (q, b, a),
            ):
                digest = (digest - hashes.pop(key)) & _MASK
            del apex[(a, b)]
            del apex[(b, a)]
            apex[(q, vertex)] = a
            apex[(vertex, a)] = q
            apex[(a, q)] = vertex
            apex[(vertex, q)] = b
            apex[(q, b)] = vertex
            apex[(b, vertex)] = q
            for key in (
                (q, vertex, a) if q < vertex and q < a else
                (vertex, a, q) if vertex < a else (a, q, vertex),
                (vertex, q, b) if vertex < q and vertex < b else
                (q, b, vertex) if q < b else (b, vertex, q),
            ):
                value = hashes[key] = cell_hash(key)
                digest = (digest + value) & _MASK
            steps.append(Step("flip", (a, b)))
            digests.append(digest)
            pending.append((q, b))
            pending.append((a, q))
        self.digest = digest

    def seal(self, start: Mesh2) -> Mesh2:
        apex = self.apex
        outgoing = {u: v for u, v in apex}
        return attrs.evolve(
            start,
            halfedges=immutables.Map(apex),
            outgoing=immutables.Map(outgoing),
            triangle_count=len(apex) // 3,
            digest=self.digest,
        )


def triangulate_points(
    points: PSLG | Sequence[Point2], *, merge_duplicates: bool = False, seed: int = 0
) -> Construction:
    """The Delaunay triangulation of a point set (a PSLG's segments, holes and regions are
    ignored here; see :func:`triangulate`).

    Incremental insertion in a biased randomized order with a visibility walk: expected
    O(n log n).  Vertex ids are the input positions.  Points outside the current hull are
    joined to every hull edge they see strictly, so the result covers the convex hull;
    cocircular points are resolved by the tie rule of :func:`geomexact.ops.legalize_in`
    (no flip on a tie), which makes the result depend on the insertion order only there.
    Raises :class:`PreconditionError` for fewer than 3 distinct points, all points
    collinear, or duplicate points unless ``merge_duplicates`` (then every copy after the
    first stays isolated and is listed in ``Construction.duplicates``).
    """
    pslg = points if isinstance(points, PSLG) else PSLG(vertices=tuple(points))
    vertices = pslg.vertices
    first_copy: dict[Point2, int] = {}
    duplicates: list[tuple[int, int]] = []
    for index, point in enumerate(vertices):
        kept = first_copy.setdefault(point, index)
        if kept != index:
            duplicates.append((index, kept))
    if duplicates and not merge_duplicates:
        shown = ", ".join(f"{d} = {k}" for d, k in duplicates[:10])
        more = f" and {len(duplicates) - 10} more" if len(duplicates) > 10 else ""
        raise PreconditionError(
            "triangulate",
            f"{len(duplicates)} duplicate points (vertex = earlier vertex): {shown}{more}; "
            "pass merge_duplicates=True (--merge-duplicates) to keep only the first copy",
            duplicates=tuple(duplicates),
        )
    dropped = {d for d, _ in duplicates}
    order = [v for v in insertion_order(vertices, seed=seed) if v not in dropped]
    if len(order) < 3:
        raise PreconditionError("triangulate", f"{len(order)} distinct points: need at least 3")
    a, b = order[0], order[1]
    third = next(
        (k for k in range(2, len(order))
         if orient2d(vertices[a], vertices[b], vertices[order[k]]) != COLLINEAR),
        None,
    )
    if third is None:
        raise PreconditionError("triangulate", "all points are collinear: no triangle exists")
    start = vertices_mesh(pslg)
    builder = _DelaunayBuilder(vertices, start.digest)
    c = order.pop(third)
    builder.make_triangle(a, b, c)
    previous = gc.isenabled()
    gc.disable()  # millions of small tuples: the cyclic collector would walk them all
    try:
        for vertex in order[2:]:
            builder.insert(vertex)
    finally:
        if previous:
            gc.enable()
    mesh = builder.seal(start)
    from geomexact import __version__

    trace = Trace(start.digest, builder.steps, builder.digests,
                  {"algorithm": "delaunay", "seed": seed,
                   "merge_duplicates": merge_duplicates}, __version__)
    return Construction(start, mesh, trace, tuple(duplicates))
