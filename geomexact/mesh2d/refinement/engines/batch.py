"""The Python batch engine: the refinement loop of
:class:`~geomexact.mesh2d.refinement.driver.Refinement` on a
:class:`~geomexact.mesh2d.batch_store.BatchTriangulation`, with exact float paths on the
dyadic grid for the Lepp search, the rating by ``MaxArea`` and legalization."""

from __future__ import annotations

from typing import Any

import immutables

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.dyadic_grid import midpoint_on_grid
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Comparison, Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.batch_store import BatchTriangulation
from geomexact.mesh2d.longest_edge import comes_first, longest_first
from geomexact.mesh2d.ops import (
    join_in_edge,
    join_in_quadrilateral,
    legalization_stack,
    quadrilateral_area_centroid,
    quadrilateral_vertex_centroid,
)
from geomexact.mesh2d.refinement.centroids import rounded_area_centroid
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.refinement.driver import Progress, Refinement, RunOptions, StepLimit
from geomexact.mesh2d.snapshot import (
    MAX_VERTICES,
    Attributes,
    Edge,
    Mesh2,
    walk_star,
)
from geomexact.mesh2d.vertex_interpolation import (
    interpolated_in_quadrilateral,
    interpolated_on_edge,
)
from geomexact.trace.step import Step

_CCW = Orientation.COUNTERCLOCKWISE
_LESS = Comparison.LESS
_MASK = _digest.MODULUS - 1


def compare_squared_lengths_on_grid(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
    """:func:`~geomexact.kernel.comparisons.compare_squared_lengths` (as -1, 0, 1) for points on
    the dyadic grid (:mod:`geomexact.kernel.dyadic_grid`), where it is exact in floats."""
    ux, uy, vx, vy = b[2] - a[2], b[3] - a[3], d[2] - c[2], d[3] - c[3]
    first, second = ux * ux + uy * uy, vx * vx + vy * vy
    return (first > second) - (first < second)


def _exact_point(x: Rational, y: Rational) -> Point2:
    """:func:`point2` for rationals, without its conversions."""
    try:
        return Point2(x, y, float(x), float(y))
    except OverflowError:
        return point2(x, y)


class BatchRefinement(BatchTriangulation, Refinement):
    """The refinement loop on a batch triangulation with its outgoing hints and its log
    of the triangles each action adds and removes (for the queue), plus the vertex tables,
    the step limit and the progress reports.  Its trace is tested equal to the reference
    engine's, step by step."""

    def __init__(self, mesh: Mesh2, max_steps: int | None, run: RunOptions) -> None:
        Refinement.__init__(self, mesh, run)
        BatchTriangulation.__init__(self, mesh, hints=True, log=True)
        # the snapshot's vertex map, opened for edits (sealing it is O(1))
        self.vertex_table = mesh.vertices.mutate()
        self.new_markers: dict[int, int] = {}
        # vertex attributes, opened only for a mesh that has them (new vertices get them
        # interpolated, as in the reference ops)
        self.vertex_attrs = mesh.vertex_attributes.mutate() if len(mesh.vertex_attributes) else None
        self.limit = max_steps
        self.get = self.halfedges.get
        self.point = self.points.__getitem__
        criterion = self.criterion
        # MaxArea.rate on grid triangles, exact in floats (a float key orders, hashes and
        # compares like the equal rational)
        self.max_area2 = (
            2 * criterion.area
            if type(criterion) is MaxArea and self.scale is not None
            else None
        )

    # -- the store's hooks --------------------------------------------------------------
    def begin_step(self) -> None:
        if self.limit is not None and len(self.steps) >= self.limit:
            raise StepLimit

    def record(self, op: str, args: tuple[Any, ...]) -> None:
        super().record(op, args)
        if self.on_step is not None:
            self.on_step(
                Progress(
                    len(self.steps), self.steps[-1], len(self.halfedges) // 3, len(self.points),
                    self.queue.size,
                )
            )

    def vertex_attributes(self, vertex: int) -> Attributes:
        """The attributes of ``vertex`` (``()`` when it has none)."""
        table = self.vertex_attrs
        return table.get(vertex, ()) if table is not None else ()

    def add_vertex(
        self, point: Point2, marker: int, on_grid: bool, attributes: Attributes = ()
    ) -> int:
        """Append a vertex at ``point`` (in no triangle yet) and return its id."""
        vertex = len(self.points)
        if vertex >= MAX_VERTICES:
            raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
        self.points.append(point)
        self.vertex_table[vertex] = point
        self.hints.append(None)
        self.grid.append(on_grid)
        if vertex >= len(_digest.VERTEX_KEYS):
            _digest.vertex_key(vertex + 1023)  # extend the cached keys a block at a time
        total = self.digest + _digest.vertex_hash(vertex, (point[0], point[1]))
        if marker:
            self.new_markers[vertex] = marker
            total += _digest.attribute_hash("vm", (vertex,), (marker,))
        if attributes and self.vertex_attrs is not None:
            self.vertex_attrs[vertex] = attributes
            total += _digest.attribute_hash("va", (vertex,), attributes)
        self.digest = total & _MASK
        return vertex

    # -- steps --------------------------------------------------------------------------
    def bisect(self, u: int, v: int) -> int:
        """:func:`geomexact.mesh2d.ops.bisect_in`."""
        self.begin_step()
        pu, pv = self.points[u], self.points[v]
        scale, grid = self.scale, self.grid
        marker = self.segments.get((u, v) if u < v else (v, u))
        midpoint = _exact_point((pu[0] + pv[0]) / 2, (pu[1] + pv[1]) / 2)
        n = self.add_vertex(
            midpoint,
            marker or 0,
            scale is not None and grid[u] and grid[v] and midpoint_on_grid(pu, pv, scale),
            interpolated_on_edge(
                pu, self.vertex_attributes(u), pv, self.vertex_attributes(v), midpoint
            ) if self.vertex_attrs is not None else (),
        )
        join_in_edge(self, u, v, n)
        self.record("bisect", (u, v))
        return n

    def centroid(self, u: int, v: int) -> int:
        """:func:`geomexact.mesh2d.ops.insert_centroid_in` or
        :func:`geomexact.mesh2d.ops.insert_in_quadrilateral_in`."""
        self.begin_step()
        halfedges, points = self.halfedges, self.points
        w, x = halfedges[(u, v)], halfedges[(v, u)]
        pu, pv, pw, px = points[u], points[v], points[w], points[x]
        args: tuple[int | Rational, ...] = (u, v)
        if self.centroid_kind == "area":
            point = rounded_area_centroid(pu, pv, pw, px)
            op, args = "insert_in_quadrilateral", (u, v, point.x, point.y)
        elif self.centroid_kind == "area-exact":
            point, op = quadrilateral_area_centroid(pu, pv, pw, px), "insert_centroid"
        else:
            point, op = quadrilateral_vertex_centroid(pu, pv, pw, px), "insert_vertex_centroid"
        for p, q in ((pu, px), (px, pv), (pv, pw), (pw, pu)):
            if orient2d(p, q, point) != _CCW:  # pragma: no cover - terminal pairs are convex
                raise PreconditionError(op, f"centroid of ({u}, {v}) outside its quadrilateral")
        attributes: Attributes = ()
        if self.vertex_attrs is not None:  # as in the reference op
            attributes = interpolated_in_quadrilateral(
                ((pu, self.vertex_attributes(u)), (pv, self.vertex_attributes(v)),
                 (pw, self.vertex_attributes(w)), (px, self.vertex_attributes(x))), point)
        n = self.add_vertex(point, 0, False, attributes)
        join_in_quadrilateral(self, u, v, w, x, n)
        self.record(op, args)
        return n

    def legalize(self, vertex: int, star: list[Edge] | None = None) -> None:
        """:func:`geomexact.mesh2d.ops.legalize_in`, flip for flip; ``star`` is the star of
        ``vertex`` as (w, x) pairs of its triangles (vertex, w, x), counter-clockwise
        (any rotation for an interior vertex), when the caller knows it."""
        if star is None:
            triangles = walk_star(self.apex, vertex, self.hints[vertex])
            star = [(w, x) for _, w, x in triangles]
        self.legalize_edges(vertex, legalization_stack(star))

    def insert_midpoint(self, u: int, v: int) -> None:
        """:meth:`Refinement.insert_midpoint`, with the star of the midpoint known: the
        edge (u, v) has the triangle (u, v, w) on its left (every caller's edge does)."""
        w, x = self.halfedges[(u, v)], self.halfedges.get((v, u))
        vertex = self.bisect(u, v)
        if self.legalize_insertions:
            # counter-clockwise, starting after the boundary gap (as walk_star lists it)
            if x is None:
                self.legalize(vertex, [(v, w), (w, u)])
            else:
                self.legalize(vertex, [(u, x), (x, v), (v, w), (w, u)])

    # -- the loop's hot paths -------------------------------------------------------------
    def terminal(self, a: int, b: int, c: int) -> tuple[int, int, int, int | None, bool]:
        """:func:`geomexact.mesh2d.longest_edge.lepp`'s terminal edge, comparing lengths in
        floats where all the points compared are on the dyadic grid."""
        get, points, grid, segments = self.get, self.points, self.grid, self.segments
        attributed = self.attributed
        exact, on_grid = compare_squared_lengths, compare_squared_lengths_on_grid
        compare = on_grid if grid[a] and grid[b] and grid[c] else exact
        u, v, w = longest_first(points[a], points[b], points[c], a, b, c, compare)
        pu, pv = points[u], points[v]
        self.searches += 1
        hops = 1
        while True:
            x = get((v, u))
            if x is None or ((u, v) if u < v else (v, u)) in segments or (
                attributed and self.different_attributes(u, v, w, x)
            ):
                constrained = True
                break
            px = points[x]
            compare = on_grid if grid[u] and grid[v] and grid[x] else exact
            if compare(pu, pv, pv, px) != _LESS and compare(pu, pv, px, pu) != _LESS:
                constrained = False
                break
            hops += 1
            if comes_first(compare(pu, px, px, pv), u, x, x, v):
                w, v, pv = v, x, px
            else:
                w, u, pu = u, x, px
        self.hops += hops
        return u, v, w, x, constrained

    def rating(self, a: int, b: int, c: int) -> Any | None:
        """:meth:`Refinement.rating`, in floats for ``MaxArea`` on grid triangles."""
        if self.criterion_attributes:
            return super().rating(a, b, c)
        points, grid, max_area2 = self.points, self.grid, self.max_area2
        pa, pb, pc = points[a], points[b], points[c]
        if max_area2 is not None and grid[a] and grid[b] and grid[c]:
            ax, ay = pa[2], pa[3]
            twice = (pb[2] - ax) * (pc[3] - ay) - (pb[3] - ay) * (pc[2] - ax)
            return -twice if twice > max_area2 else None
        return self.criterion.rate(pa, pb, pc)

    def finish(self, start: Mesh2) -> tuple[Mesh2, list[Step], list[int]]:
        markers = start.vertex_markers.mutate()
        for vertex, marker in self.new_markers.items():
            markers[vertex] = marker
        outgoing = immutables.Map(
            (vertex, hint) for vertex, hint in enumerate(self.hints) if hint is not None
        )
        mesh = self.sealed(
            start,
            vertices=self.vertex_table.finish(),
            vertex_markers=markers.finish(),
            outgoing=outgoing,
            **(
                {"vertex_attributes": self.vertex_attrs.finish()}
                if self.vertex_attrs is not None else {}
            ),
        )
        return mesh, self.steps, self.digests
