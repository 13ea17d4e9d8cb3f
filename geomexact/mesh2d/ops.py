"""Pure steps on 2D meshes: flip, bisect, insert_in_triangle, insert_in_edge,
insert_centroid, legalize — and :func:`apply`, the only way a :class:`Step` changes a mesh.

Each op is written once, against a :class:`~geomexact.mesh2d.transient.Transient2`
(``*_in(transient, …)``), checks its preconditions exactly and raises
:class:`~geomexact.errors.PreconditionError` naming the violated one, records its
:class:`~geomexact.trace.step.Step` in ``transient.steps``, and leaves the transient unchanged
when it raises.  The pure functions (``flip(mesh, edge)``…) open a transient, run the op
and seal it: the input snapshot never changes.  Pre/postconditions: ``specs/ops.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Protocol

from geomexact.errors import PreconditionError
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import CircleLocation, Orientation
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.mesh2d.snapshot import (
    Attributes,
    Edge,
    Mesh2,
    Triangle,
    canonical_triangle,
    next_boundary_edge,
    previous_boundary_edge,
    walk_star,
)
from geomexact.mesh2d.transient import Transient2
from geomexact.mesh2d.vertex_interpolation import (
    interpolated_in_quadrilateral,
    interpolated_in_triangle,
    interpolated_on_edge,
)
from geomexact.trace.protocols import apply_from
from geomexact.trace.step import Step

CCW = Orientation.COUNTERCLOCKWISE
COLLINEAR = Orientation.COLLINEAR


# ---------------------------------------------------------------------------------------
# geometry shared by the ops
# ---------------------------------------------------------------------------------------
def strictly_between(p: Point2, u: Point2, v: Point2) -> bool:
    """True when p, known to be on line uv, lies strictly inside segment uv."""
    beyond_u = (p.x - u.x) * (v.x - u.x) + (p.y - u.y) * (v.y - u.y)
    before_v = (p.x - v.x) * (u.x - v.x) + (p.y - v.y) * (u.y - v.y)
    return bool(beyond_u > 0 and before_v > 0)


def quadrilateral_area_centroid(a: Point2, b: Point2, c: Point2, d: Point2) -> Point2:
    """Area centroid of the quadrilateral made of triangles (a, b, c) and (b, a, d), both
    counter-clockwise: (A1·G1 + A2·G2) / (A1 + A2) with Ai the areas and Gi the centroids."""
    area1 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
    area2 = (a.x - b.x) * (d.y - b.y) - (a.y - b.y) * (d.x - b.x)
    total = 3 * (area1 + area2)
    x = (area1 * (a.x + b.x + c.x) + area2 * (a.x + b.x + d.x)) / total
    y = (area1 * (a.y + b.y + c.y) + area2 * (a.y + b.y + d.y)) / total
    return point2(x, y)


def quadrilateral_vertex_centroid(a: Point2, b: Point2, c: Point2, d: Point2) -> Point2:
    """Average of the four vertices."""
    return point2((a.x + b.x + c.x + d.x) / 4, (a.y + b.y + c.y + d.y) / 4)


def _interior_edge(t: Transient2, op: str, u: int, v: int) -> tuple[int, int]:
    """Apexes (w, x) of the two triangles of the unconstrained interior edge {u, v}."""
    w, x = t.apex(u, v), t.apex(v, u)
    if w is None and x is None:
        raise PreconditionError(op, f"({u}, {v}) is not an edge of the mesh", edge=(u, v))
    if w is None or x is None:
        raise PreconditionError(
            op, f"edge ({u}, {v}) is on the boundary (it has one triangle)", edge=(u, v)
        )
    if t.segment_marker(u, v) is not None:
        raise PreconditionError(op, f"edge ({u}, {v}) is a constrained segment", edge=(u, v))
    first, second = t.triangle_attributes((u, v, w)), t.triangle_attributes((v, u, x))
    if first != second:
        raise PreconditionError(
            op,
            f"the triangles of edge ({u}, {v}) carry different attributes "
            f"({first} and {second})",
            edge=(u, v),
        )
    return w, x


# ---------------------------------------------------------------------------------------
# the triangle edits of the ops
# ---------------------------------------------------------------------------------------
class TriangleEditor(Protocol):
    """What the ops' triangle edits need of a mesh editor (a
    :class:`~geomexact.mesh2d.transient.Transient2`)."""

    def apex(self, u: int, v: int, /) -> int | None: ...

    def add_triangle(
        self, a: int, b: int, c: int, attributes: Attributes | None = None, /
    ) -> None: ...

    def remove_triangle(self, a: int, b: int, c: int, /) -> Attributes | None: ...

    def segment_marker(self, u: int, v: int, /) -> int | None: ...

    def set_segment(self, u: int, v: int, marker: int = 0, /) -> None: ...

    def remove_segment(self, u: int, v: int, /) -> int: ...


def join_in_edge(t: TriangleEditor, u: int, v: int, n: int) -> None:
    """Join the vertex n, strictly inside edge {u, v}, to the apex of each triangle of the
    edge (each half keeps the triangle's attributes); a constrained edge becomes its two
    halves, with its marker."""
    w, x = t.apex(u, v), t.apex(v, u)
    if w is not None:
        attributes = t.remove_triangle(u, v, w)
        t.add_triangle(u, n, w, attributes)
        t.add_triangle(n, v, w, attributes)
    if x is not None:
        attributes = t.remove_triangle(v, u, x)
        t.add_triangle(v, n, x, attributes)
        t.add_triangle(n, u, x, attributes)
    marker = t.segment_marker(u, v)
    if marker is not None:
        t.remove_segment(u, v)
        t.set_segment(u, n, marker)
        t.set_segment(n, v, marker)


def join_in_triangle(t: TriangleEditor, a: int, b: int, c: int, n: int) -> None:
    """Join the vertex n, strictly inside the triangle (a, b, c), to its corners."""
    attributes = t.remove_triangle(a, b, c)
    t.add_triangle(a, b, n, attributes)
    t.add_triangle(b, c, n, attributes)
    t.add_triangle(c, a, n, attributes)


def join_in_quadrilateral(t: TriangleEditor, u: int, v: int, w: int, x: int, n: int) -> None:
    """Replace the triangles (u, v, w) and (v, u, x) by (u, x, n), (x, v, n), (v, w, n),
    (w, u, n), for the vertex n strictly inside each."""
    attributes = t.remove_triangle(u, v, w)
    t.remove_triangle(v, u, x)
    t.add_triangle(u, x, n, attributes)
    t.add_triangle(x, v, n, attributes)
    t.add_triangle(v, w, n, attributes)
    t.add_triangle(w, u, n, attributes)


# ---------------------------------------------------------------------------------------
# ops on a transient
# ---------------------------------------------------------------------------------------
def flip_in(t: Transient2, u: int, v: int) -> Edge:
    """Replace the interior edge {u, v} of triangles (u, v, w), (v, u, x) by {w, x}.

    ::

            w                w
           / \\              /|\\
          u---v     ->     u | v
           \\ /              \\|/
            x                x

    Preconditions: {u, v} is an edge with two triangles, not constrained, whose
    quadrilateral u, x, v, w is strictly convex.  Returns the new edge (w, x).
    """
    w, x = _interior_edge(t, "flip", u, v)
    pu, pv, pw, px = t.point(u), t.point(v), t.point(w), t.point(x)
    if orient2d(px, pw, pu) != CCW or orient2d(pw, px, pv) != CCW:
        raise PreconditionError(
            "flip",
            f"the quadrilateral of edge ({u}, {v}) is not strictly convex",
            edge=(u, v),
        )
    attributes = t.remove_triangle(u, v, w)
    t.remove_triangle(v, u, x)
    t.add_triangle(x, w, u, attributes)
    t.add_triangle(w, x, v, attributes)
    t.record(Step("flip", (u, v)))
    return w, x


def _split_edge(
    t: Transient2, op: str, u: int, v: int, point: Point2, vertex: int | None = None,
    *, midpoint: bool = False,
) -> int:
    """Insert ``point`` (strictly inside segment uv) into edge {u, v}: a new vertex, or the
    isolated ``vertex`` at ``point``; return its id.  ``midpoint``: ``point`` is the exact
    midpoint of uv, strictly inside it since u and v are distinct points of the mesh (the
    check is then skipped)."""
    w, x = t.apex(u, v), t.apex(v, u)
    if w is None and x is None:
        raise PreconditionError(op, f"({u}, {v}) is not an edge of the mesh", edge=(u, v))
    pu, pv = t.point(u), t.point(v)
    if not midpoint and (orient2d(pu, pv, point) != COLLINEAR
                         or not strictly_between(point, pu, pv)):
        raise PreconditionError(
            op,
            f"point ({point.x}, {point.y}) is not strictly inside edge ({u}, {v})",
            edge=(u, v),
        )
    marker = t.segment_marker(u, v)
    if vertex is None:
        attributes = interpolated_on_edge(
            pu, t.vertex_attributes(u), pv, t.vertex_attributes(v), point
        )
        vertex = t.add_vertex(point, marker or 0, attributes)
    join_in_edge(t, u, v, vertex)
    return vertex


def bisect_in(t: Transient2, u: int, v: int) -> int:
    """Insert the exact midpoint of edge {u, v} (interior or boundary), joined to the
    opposite vertex of each triangle of the edge (2 triangles become 4, or 1 becomes 2).
    A constrained edge stays constrained as its two halves, with the same marker, and the
    new vertex takes that marker.  Returns the new vertex id."""
    pu, pv = t.point(u), t.point(v)
    midpoint = point2((pu.x + pv.x) / 2, (pu.y + pv.y) / 2)
    n = _split_edge(t, "bisect", u, v, midpoint, midpoint=True)
    t.record(Step("bisect", (u, v)))
    return n


def insert_in_edge_in(t: Transient2, u: int, v: int, point: Point2) -> int:
    """Insert ``point``, which must lie strictly inside edge {u, v}; as :func:`bisect_in`
    otherwise.  Returns the new vertex id."""
    n = _split_edge(t, "insert_in_edge", u, v, point)
    t.record(Step("insert_in_edge", (u, v, point.x, point.y)))
    return n


def _split_triangle(
    t: Transient2, op: str, triangle: Triangle, point: Point2, vertex: int | None = None
) -> int:
    """Join ``point`` (strictly inside ``triangle``) to its corners: a new vertex, or the
    isolated ``vertex`` at ``point``; return its id."""
    a, b, c = triangle
    if t.apex(a, b) != c:
        raise PreconditionError(
            op, f"{triangle} is not a counter-clockwise triangle of the mesh", triangle=triangle
        )
    pa, pb, pc = t.point(a), t.point(b), t.point(c)
    if orient2d(pa, pb, point) != CCW or orient2d(pb, pc, point) != CCW or (
        orient2d(pc, pa, point) != CCW
    ):
        raise PreconditionError(
            op,
            f"point ({point.x}, {point.y}) is not strictly inside triangle {triangle}",
            triangle=triangle,
        )
    if vertex is None:
        corners = ((pa, t.vertex_attributes(a)), (pb, t.vertex_attributes(b)),
                   (pc, t.vertex_attributes(c)))
        vertex = t.add_vertex(point, 0, interpolated_in_triangle(corners, point))
    join_in_triangle(t, a, b, c, vertex)
    return vertex


def insert_in_triangle_in(t: Transient2, triangle: Triangle, point: Point2) -> int:
    """Insert ``point``, strictly inside triangle (a, b, c), joined to a, b and c
    (one triangle becomes three).  Returns the new vertex id."""
    n = _split_triangle(t, "insert_in_triangle", triangle, point)
    t.record(Step("insert_in_triangle", (*triangle, point.x, point.y)))
    return n


# -- attaching existing isolated vertices (used to build triangulations) -----------------
def _require_isolated(t: Transient2, op: str, vertex: int) -> Point2:
    if not 0 <= vertex < t.vertex_count:
        raise PreconditionError(op, f"vertex {vertex} does not exist", vertex=vertex)
    if t.outgoing(vertex) is not None:
        raise PreconditionError(op, f"vertex {vertex} is already in a triangle", vertex=vertex)
    return t.point(vertex)


def make_triangle_in(t: Transient2, a: int, b: int, c: int) -> Triangle:
    """Create the triangle on three distinct isolated, non-collinear vertices (ordered
    counter-clockwise); returns it as stored."""
    points = [_require_isolated(t, "make_triangle", v) for v in (a, b, c)]
    if len({a, b, c}) != 3:
        raise PreconditionError("make_triangle", f"vertices {(a, b, c)} are not distinct")
    orientation = orient2d(*points)
    if orientation == COLLINEAR:
        raise PreconditionError("make_triangle", f"vertices {(a, b, c)} are collinear")
    triangle = (a, b, c) if orientation == CCW else (a, c, b)
    t.add_triangle(*triangle)
    t.record(Step("make_triangle", (a, b, c)))
    return triangle


def attach_in_triangle_in(t: Transient2, vertex: int, triangle: Triangle) -> None:
    """Join the isolated ``vertex``, strictly inside ``triangle``, to its corners."""
    point = _require_isolated(t, "attach_in_triangle", vertex)
    _split_triangle(t, "attach_in_triangle", triangle, point, vertex)
    t.record(Step("attach_in_triangle", (vertex, *triangle)))


def attach_in_edge_in(t: Transient2, vertex: int, u: int, v: int) -> None:
    """Split edge {u, v} at the isolated ``vertex``, strictly inside it (constrained
    halves keep the marker; the vertex keeps its own marker)."""
    point = _require_isolated(t, "attach_in_edge", vertex)
    _split_edge(t, "attach_in_edge", u, v, point, vertex)
    t.record(Step("attach_in_edge", (vertex, u, v)))


def attach_outside_in(t: Transient2, vertex: int, u: int, v: int) -> list[Edge]:
    """Join the isolated ``vertex``, strictly right of the boundary half-edge (u, v), to
    every boundary edge it sees strictly (the contiguous run of boundary half-edges around
    (u, v) with ``vertex`` strictly on their right): each such (a, b) gets the triangle
    (b, a, vertex).  Meant for convex boundaries (incremental construction); returns the
    edges joined, in boundary order."""
    point = _require_isolated(t, "attach_outside", vertex)
    if t.apex(u, v) is None or t.apex(v, u) is not None:
        raise PreconditionError("attach_outside", f"({u}, {v}) is not a boundary half-edge")

    def sees(edge: tuple[int, int]) -> bool:
        return orient2d(t.point(edge[0]), t.point(edge[1]), point) == Orientation.CLOCKWISE

    if not sees((u, v)):
        raise PreconditionError(
            "attach_outside", f"vertex {vertex} is not strictly right of edge ({u}, {v})"
        )
    visible = [(u, v)]
    edge = next_boundary_edge(t.apex, u, v)
    while edge != (u, v) and sees(edge):
        visible.append(edge)
        edge = next_boundary_edge(t.apex, *edge)
    if edge != (u, v):
        edge = previous_boundary_edge(t.apex, u, v)
        while sees(edge):
            visible.insert(0, edge)
            edge = previous_boundary_edge(t.apex, *edge)
    for a, b in visible:
        t.add_triangle(b, a, vertex)
    t.record(Step("attach_outside", (vertex, u, v)))
    return visible


def _insert_in_quadrilateral(
    t: Transient2, op: str, u: int, v: int, place: Callable[..., Point2], what: str
) -> int:
    """Replace the two triangles (u, v, w), (v, u, x) of the unconstrained interior edge
    {u, v} by (u, x, n), (x, v, n), (v, w, n), (w, u, n), with n a new vertex at
    ``place(pu, pv, pw, px)``, which must be strictly inside each of them; returns n (the
    caller records the step)."""
    w, x = _interior_edge(t, op, u, v)
    pu, pv, pw, px = t.point(u), t.point(v), t.point(w), t.point(x)
    point = place(pu, pv, pw, px)
    for p, q in ((pu, px), (px, pv), (pv, pw), (pw, pu)):
        if orient2d(p, q, point) != CCW:
            raise PreconditionError(
                op,
                f"{what} ({point.x}, {point.y}) is not strictly inside the four triangles "
                f"of the quadrilateral of edge ({u}, {v})",
                edge=(u, v),
            )
    attributes: Attributes = ()
    if t.vertex_attributes(u):
        attributes = interpolated_in_quadrilateral(
            ((pu, t.vertex_attributes(u)), (pv, t.vertex_attributes(v)),
             (pw, t.vertex_attributes(w)), (px, t.vertex_attributes(x))), point)
    n = t.add_vertex(point, 0, attributes)
    join_in_quadrilateral(t, u, v, w, x, n)
    return n


def _insert_centroid_step(
    t: Transient2, op: str, u: int, v: int, centre: Callable[..., Point2]
) -> int:
    n = _insert_in_quadrilateral(t, op, u, v, centre, "the centroid")
    t.record(Step(op, (u, v)))
    return n


def insert_in_quadrilateral_in(t: Transient2, u: int, v: int, point: Point2) -> int:
    """Replace the two triangles (u, v, w), (v, u, x) of the unconstrained interior edge
    {u, v} by (u, x, n), (x, v, n), (v, w, n), (w, u, n) with n a new vertex at ``point``,
    which must be strictly inside each of them.  Records
    ``insert_in_quadrilateral(u, v, x, y)``; returns n.  Lepp-centroid refinement inserts
    its rounded centroids with this step (``geomexact.mesh2d.refinement.centroids``).

    Preconditions as ``insert_centroid`` (``specs/ops.md``): both triangles exist, the edge
    is not constrained, the triangles carry equal attributes.
    """
    op = "insert_in_quadrilateral"
    n = _insert_in_quadrilateral(t, op, u, v, lambda *_: point, "point")
    t.record(Step(op, (u, v, point.x, point.y)))
    return n


def insert_centroid_in(t: Transient2, u: int, v: int, *, kind: str = "area") -> int:
    """Replace the two triangles of the unconstrained interior edge {u, v} by four joined
    at the centroid of their quadrilateral: the area centroid (``kind="area"``, step
    ``insert_centroid``) or the average of its four vertices (``kind="vertices"``, step
    ``insert_vertex_centroid``).  The centroid must be strictly inside each of the four new
    triangles (true for a strictly convex quadrilateral).  Returns the new vertex id."""
    if kind == "area":
        return _insert_centroid_step(t, "insert_centroid", u, v, quadrilateral_area_centroid)
    if kind == "vertices":
        return _insert_centroid_step(
            t, "insert_vertex_centroid", u, v, quadrilateral_vertex_centroid
        )
    raise PreconditionError("insert_centroid", f"unknown centroid kind {kind!r}")


def lawson_flip_wanted(t: Transient2, w: int, u: int, v: int, x: int) -> bool:
    """Whether Lawson's algorithm flips the interior edge uv of the counter-clockwise
    triangles (w, u, v) and (v, u, x): x strictly inside the circle through w, u, v
    (cocircular points never flip), the quadrilateral strictly convex (so the flip is
    valid), and both triangles of the same attributes (a flip never crosses a region's
    bound).  Whether uv is constrained is the caller's test."""
    pw, pu, pv, px = t.point(w), t.point(u), t.point(v), t.point(x)
    return (
        incircle(pw, pu, pv, px) == CircleLocation.INSIDE
        and orient2d(px, pw, pu) == CCW
        and orient2d(pw, px, pv) == CCW
        and t.triangle_attributes((w, u, v)) == t.triangle_attributes((v, u, x))
    )


def legalization_stack(star: list[Edge]) -> list[Edge]:
    """The edges (a, b) opposite a vertex in its triangles (vertex, a, b), given
    counter-clockwise as ``star``, as the stack legalization pops them: first the one
    with the smallest a, then counter-clockwise."""
    start = min(range(len(star)), key=lambda i: star[i][0])
    pending = star[start:] + star[:start]
    pending.reverse()
    return pending


def legalize_in(t: Transient2, vertex: int) -> list[Step]:
    """Lawson flips around ``vertex``: while an edge (a, b) opposite ``vertex`` in a
    triangle (vertex, a, b) is unconstrained, interior, and its other apex q lies strictly
    inside the circle through vertex, a, b, flip it (when its quadrilateral is strictly
    convex) and examine the two new opposite edges (a, q) then (q, b).  Cocircular points
    never cause a flip.  Edges are examined depth-first, starting from the star of
    ``vertex`` in counter-clockwise order from its smallest neighbour.  Returns the flips."""
    star = walk_star(t.apex, vertex, t.outgoing(vertex))
    if not star:
        raise PreconditionError("legalize", f"vertex {vertex} is in no triangle")
    return legalize_stack_in(t, vertex, legalization_stack([(a, b) for _, a, b in star]))


def legalize_stack_in(t: Transient2, vertex: int, pending: list[Edge]) -> list[Step]:
    """:func:`legalize_in`'s flips from the stack ``pending`` of edges (a, b) opposite
    ``vertex`` (popped last first; an edge whose triangle (vertex, a, b) is gone is
    skipped): the order an insertion that knows the edges it made examines them in.
    Returns the flips."""
    flips: list[Step] = []
    t.point(vertex)  # a PreconditionError at once when there is no such vertex
    while pending:
        a, b = pending.pop()
        if t.apex(vertex, a) != b:
            continue
        q = t.apex(b, a)
        if q is None or t.segment_marker(a, b) is not None:
            continue
        if not lawson_flip_wanted(t, vertex, a, b, q):
            continue
        flip_in(t, a, b)
        flips.append(t.steps[-1])
        pending.append((q, b))
        pending.append((a, q))
    return flips


# -- constraints and regions (used to build constrained triangulations) ------------------
def constrain_in(t: Transient2, u: int, v: int, marker: int = 0) -> None:
    """Make the existing, unconstrained edge {u, v} a constrained segment with ``marker``."""
    if t.apex(u, v) is None and t.apex(v, u) is None:
        raise PreconditionError("constrain", f"({u}, {v}) is not an edge of the mesh")
    if t.segment_marker(u, v) is not None:
        raise PreconditionError("constrain", f"edge ({u}, {v}) is already constrained")
    t.set_segment(u, v, marker)
    t.record(Step("constrain", (u, v, marker)))


def containing_triangle(t: Transient2, point: Point2) -> Triangle | None:
    """The triangle (canonical form) whose closure contains ``point``: the smallest such
    triangle when the point is on an edge or a vertex; None outside the mesh.  O(n)."""
    best: Triangle | None = None
    for (a, b), c in t.halfedges_snapshot().items():
        if not (a < b and a < c) or (best is not None and (a, b, c) >= best):
            continue
        pa, pb, pc = t.point(a), t.point(b), t.point(c)
        if (orient2d(pa, pb, point) != Orientation.CLOCKWISE
                and orient2d(pb, pc, point) != Orientation.CLOCKWISE
                and orient2d(pc, pa, point) != Orientation.CLOCKWISE):
            best = (a, b, c)
    return best


def _flood(t: Transient2, seeds: list[Triangle]) -> list[Triangle]:
    """Triangles reachable from ``seeds`` across unconstrained edges, sorted."""
    seen = set(seeds)
    stack = list(seeds)
    while stack:
        a, b, c = stack.pop()
        for u, v in ((a, b), (b, c), (c, a)):
            if t.segment_marker(u, v) is not None:
                continue
            w = t.apex(v, u)
            if w is None:
                continue
            neighbour = canonical_triangle(v, u, w)
            if neighbour not in seen:
                seen.add(neighbour)
                stack.append(neighbour)
    return sorted(seen)


def _region_of_point(t: Transient2, op: str, x: object, y: object) -> list[Triangle]:
    point = point2(x, y)
    seed = containing_triangle(t, point)
    if seed is None:
        raise PreconditionError(op, f"point ({point.x}, {point.y}) is in no triangle")
    return _flood(t, [seed])


def carve_in(t: Transient2, x: object, y: object) -> int:
    """Remove the region containing point (x, y): the triangle containing it (see
    :func:`containing_triangle`) and every triangle reachable from it without crossing a
    constrained segment — Triangle's hole seeds.  Returns the number removed."""
    point = point2(x, y)
    region = _region_of_point(t, "carve", point.x, point.y)
    for triangle in region:
        t.remove_triangle(*triangle)
    t.record(Step("carve", (point.x, point.y)))
    return len(region)


def exterior_triangles(t: Transient2) -> list[Triangle]:
    """Triangles reachable from an unconstrained boundary edge without crossing a
    constrained segment (the part of a convex-hull triangulation outside the PSLG)."""
    halfedges = t.halfedges_snapshot()
    seeds = sorted(
        canonical_triangle(u, v, w)
        for (u, v), w in halfedges.items()
        if (v, u) not in halfedges and t.segment_marker(u, v) is None
    )
    return _flood(t, seeds) if seeds else []


def carve_exterior_in(t: Transient2) -> int:
    """Remove :func:`exterior_triangles`; returns the number removed."""
    region = exterior_triangles(t)
    for triangle in region:
        t.remove_triangle(*triangle)
    t.record(Step("carve_exterior", ()))
    return len(region)


def set_region_in(t: Transient2, x: object, y: object, attributes: tuple[object, ...]) -> int:
    """Give ``attributes`` (exact rationals) to the region containing (x, y), bounded by
    constrained segments (Triangle's regional attributes).  Returns the triangles set."""
    values = tuple(point2(value, 0).x for value in attributes)
    region = _region_of_point(t, "set_region", x, y)
    for triangle in region:
        t.set_triangle_attributes(triangle, values)
    point = point2(x, y)
    t.record(Step("set_region", (point.x, point.y, *values)))
    return len(region)


# ---------------------------------------------------------------------------------------
# steps
# ---------------------------------------------------------------------------------------
def _ints(step: Step, count: int, total: int) -> tuple[int, ...]:
    if len(step.args) != total:
        raise PreconditionError(
            step.op, f"expects {total} arguments, got {len(step.args)}: {step}"
        )
    head = step.args[:count]
    if not all(isinstance(a, int) for a in head):
        raise PreconditionError(step.op, f"vertex arguments must be integers: {step}")
    return tuple(int(a) for a in head)


def _coordinates(step: Step, start: int) -> Point2:
    return point2(step.args[start], step.args[start + 1])


def _apply_flip(t: Transient2, step: Step) -> None:
    u, v = _ints(step, 2, 2)
    flip_in(t, u, v)


def _apply_bisect(t: Transient2, step: Step) -> None:
    u, v = _ints(step, 2, 2)
    bisect_in(t, u, v)


def _apply_insert_in_edge(t: Transient2, step: Step) -> None:
    u, v = _ints(step, 2, 4)
    insert_in_edge_in(t, u, v, _coordinates(step, 2))


def _apply_insert_in_triangle(t: Transient2, step: Step) -> None:
    a, b, c = _ints(step, 3, 5)
    insert_in_triangle_in(t, (a, b, c), _coordinates(step, 3))


def _apply_insert_centroid(t: Transient2, step: Step) -> None:
    u, v = _ints(step, 2, 2)
    insert_centroid_in(t, u, v, kind="area")


def _apply_insert_vertex_centroid(t: Transient2, step: Step) -> None:
    u, v = _ints(step, 2, 2)
    insert_centroid_in(t, u, v, kind="vertices")


def _apply_insert_in_quadrilateral(t: Transient2, step: Step) -> None:
    if len(step.args) != 4 or not all(isinstance(a, int) for a in step.args[:2]):
        raise PreconditionError(
            "insert_in_quadrilateral", f"expects u, v, x, y (u, v vertex ids): {step}"
        )
    u, v = int(step.args[0]), int(step.args[1])
    insert_in_quadrilateral_in(t, u, v, point2(step.args[2], step.args[3]))


def _apply_make_triangle(t: Transient2, step: Step) -> None:
    make_triangle_in(t, *_ints(step, 3, 3))


def _apply_attach_in_triangle(t: Transient2, step: Step) -> None:
    vertex, a, b, c = _ints(step, 4, 4)
    attach_in_triangle_in(t, vertex, (a, b, c))


def _apply_attach_in_edge(t: Transient2, step: Step) -> None:
    attach_in_edge_in(t, *_ints(step, 3, 3))


def _apply_attach_outside(t: Transient2, step: Step) -> None:
    attach_outside_in(t, *_ints(step, 3, 3))


def _apply_constrain(t: Transient2, step: Step) -> None:
    constrain_in(t, *_ints(step, 3, 3))


def _apply_carve(t: Transient2, step: Step) -> None:
    if len(step.args) != 2:
        raise PreconditionError("carve", f"expects 2 arguments, got {len(step.args)}: {step}")
    carve_in(t, *step.args)


def _apply_carve_exterior(t: Transient2, step: Step) -> None:
    if step.args:
        raise PreconditionError("carve_exterior", f"takes no arguments: {step}")
    carve_exterior_in(t)


def _apply_set_region(t: Transient2, step: Step) -> None:
    if len(step.args) < 3:
        raise PreconditionError("set_region", f"expects x, y and attributes: {step}")
    set_region_in(t, step.args[0], step.args[1], tuple(step.args[2:]))


OPERATIONS: Mapping[str, Callable[[Transient2, Step], None]] = MappingProxyType({
    "constrain": _apply_constrain,
    "carve": _apply_carve,
    "carve_exterior": _apply_carve_exterior,
    "set_region": _apply_set_region,
    "make_triangle": _apply_make_triangle,
    "attach_in_triangle": _apply_attach_in_triangle,
    "attach_in_edge": _apply_attach_in_edge,
    "attach_outside": _apply_attach_outside,
    "flip": _apply_flip,
    "bisect": _apply_bisect,
    "insert_in_edge": _apply_insert_in_edge,
    "insert_in_triangle": _apply_insert_in_triangle,
    "insert_centroid": _apply_insert_centroid,
    "insert_vertex_centroid": _apply_insert_vertex_centroid,
    "insert_in_quadrilateral": _apply_insert_in_quadrilateral,
})
"""Step name -> how to apply it to a 2D transient: every 2D step there is, complete at
import (the :data:`geomexact.trace.protocols.OperationTable` of ``mesh2d``)."""


def apply_in(t: Transient2, step: Step) -> None:
    """Apply ``step`` to the transient (it records the step in ``t.steps``)."""
    apply_from(OPERATIONS, t, step)


# ---------------------------------------------------------------------------------------
# pure functions
# ---------------------------------------------------------------------------------------
def apply(mesh: Mesh2, step: Step, /) -> Mesh2:
    """The mesh after ``step``; ``mesh`` is unchanged.  O(k log n) for a step touching k
    triangles."""
    t = Transient2(mesh)
    apply_in(t, step)
    return t.seal()


def flip(mesh: Mesh2, edge: Edge, /) -> Mesh2:
    """The mesh with interior edge ``edge`` flipped (see :func:`flip_in`)."""
    return apply(mesh, Step("flip", edge))


def bisect(mesh: Mesh2, edge: Edge, /) -> Mesh2:
    """The mesh with the midpoint of ``edge`` inserted (see :func:`bisect_in`); the new
    vertex is ``mesh.vertex_count``."""
    return apply(mesh, Step("bisect", edge))


def insert_in_edge(mesh: Mesh2, edge: Edge, point: Point2, /) -> Mesh2:
    """The mesh with ``point`` inserted strictly inside ``edge``."""
    return apply(mesh, Step("insert_in_edge", (*edge, point.x, point.y)))


def insert_in_triangle(mesh: Mesh2, triangle: Triangle, point: Point2, /) -> Mesh2:
    """The mesh with ``point`` inserted strictly inside ``triangle`` (1 -> 3 triangles)."""
    return apply(mesh, Step("insert_in_triangle", (*triangle, point.x, point.y)))


def insert_centroid(mesh: Mesh2, edge: Edge, /, *, kind: str = "area") -> Mesh2:
    """The mesh with the centroid of the quadrilateral of interior ``edge`` inserted
    (2 -> 4 triangles); ``kind`` is ``"area"`` or ``"vertices"``."""
    name = {"area": "insert_centroid", "vertices": "insert_vertex_centroid"}.get(kind)
    if name is None:
        raise PreconditionError("insert_centroid", f"unknown centroid kind {kind!r}")
    return apply(mesh, Step(name, edge))


def legalize(mesh: Mesh2, vertex: int, /) -> tuple[Mesh2, tuple[Step, ...]]:
    """Delaunay flips around ``vertex`` (see :func:`legalize_in`); returns the new mesh and
    the flips made, in order."""
    t = Transient2(mesh)
    flips = legalize_in(t, vertex)
    return t.seal(), tuple(flips)
