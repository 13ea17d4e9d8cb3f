"""Convex decomposition of polygon meshes made of triangles (e.g. Polylla meshes), exact.

Every non-convex polygon is split by edges of the triangulation it is made of (its
``sources``) until every polygon is convex; no vertex is added.  A corner is *reflex* when
the polygon turns right there (exact orientation; going straight on is convex).  For each
reflex corner, edges of the triangulation that leave the vertex inside the corner are
candidates; the corner's angle Θ is measured from the edge to the next vertex,
counter-clockwise, to the edge from the previous vertex:

1. **criterion 1** (optional): a candidate whose other end is a reflex corner too and that
   leaves every piece of both corners at most 180°; the one closest to the bisector of Θ;
2. else the candidate closest to the bisector of Θ, if both pieces are at most 180°;
3. else the two candidates closest to the trisectors of Θ (one edge when it is the
   closest to both).

A piece that is still reflex is treated again, so the process ends with convex polygons;
each one is then checked exactly and :class:`ConvexDecompositionError` is raised if any is
not (it never should).  Angles are compared exactly: an angle is a lifted complex direction
(full turns plus a rational vector), and sums of angles are products of vectors.  Ties (two
candidates exactly as close) go to the edge with the smaller ``(min id, max id)`` pair.
Spec: ``specs/convex.md``.

>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> from geomexact.mesh2d.polygonal.polylla_meshing import polylla
>>> pentagon = mesh_from_triangles(
...     [(1, 1), (0, 1), (0, 0), (4, 1), (3, 2)], [(0, 1, 2), (0, 2, 3), (0, 3, 4)])
>>> polylla(pentagon).polygons  # reflex at vertex 0
((0, 1, 2, 3, 4),)
>>> result = convex_decomposition(polylla(pentagon))
>>> result.inserted_edges, result.mesh.polygons
(((0, 2),), ((0, 1, 2), (0, 2, 3, 4)))
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, TypeAlias

import attrs
import numpy as np

from geomexact.errors import ConvexDecompositionError, PolyllaError, PreconditionError
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.polygonal.halfedge_table import HalfEdgeTable
from geomexact.mesh2d.polygonal.polygon_mesh import (
    PolygonMesh,
    nonconvex_polygons,
    orientation_signs,
)
from geomexact.mesh2d.snapshot import Edge, canonical_triangle

__all__ = [
    "ConvexDecomposition",
    "convex_decomposition",
]

_CW = Orientation.CLOCKWISE
_COLLINEAR = Orientation.COLLINEAR

ReflexRule: TypeAlias = Literal["strict", "straight"]
"""``"strict"``: a corner is reflex when it is above 180°; ``"straight"``: also at exactly
180° (Pineda 2023, Alg. 10)."""

CriterionOneRule: TypeAlias = Literal["bisector", "first"]
"""``"bisector"``: a first pass over the corners inserts, at each, the criterion-1
candidate closest to its bisector; ``"first"``: each corner, as it is treated, takes the
first criterion-1 candidate in its fan (clockwise from the previous vertex) and otherwise
criteria 2 and 3 at once, one sweep (Pineda 2023, Alg. 11)."""


@attrs.frozen(slots=True)
class ConvexDecomposition:
    """The result of :func:`convex_decomposition`: the convex polygon mesh (``sources``:
    the triangles of each polygon), the edges of the triangulation that were inserted
    (sorted ``(min, max)`` pairs), whether criterion 1 was used, and how many polygons of
    the input were not convex."""

    mesh: PolygonMesh
    inserted_edges: tuple[Edge, ...]
    criterion_one: bool
    nonconvex_before: int
    reflex: ReflexRule = "strict"
    criterion_one_rule: CriterionOneRule = "bisector"


def convex_decomposition(
    polygons: PolygonMesh,
    /,
    *,
    criterion_one: bool = True,
    reflex: ReflexRule = "strict",
    criterion_one_rule: CriterionOneRule = "bisector",
    preset: Literal["pineda", "pineda-thesis"] | None = None,
) -> ConvexDecomposition:
    """Split every polygon of ``polygons`` into convex polygons by inserting edges of its
    source triangles (see the module docstring for the rules).

    ``polygons`` must have ``sources`` (as
    :func:`geomexact.mesh2d.polygonal.polylla_meshing.polylla` makes) and each
    polygon must be a simple polygon that is the union of its source triangles
    (:class:`PreconditionError` otherwise).  Deterministic; O(n) plus O(d) exact angle
    comparisons per reflex corner with d candidate edges.

    ``reflex`` and ``criterion_one_rule`` (:data:`ReflexRule`, :data:`CriterionOneRule`)
    choose the rules where they are left at their defaults: ``preset="pineda"`` follows
    Pineda's program (``"strict"``, ``"first"``: its runs' 76 and 275 concave polygons and
    93 inserted edges on ``500poisson.off``), ``preset="pineda-thesis"`` the thesis's
    reading of table 5.1 (``"straight"``, ``"first"``: its 77 and 283 concave polygons)
    (``specs/convex.md``).
    """
    if preset is not None:
        if preset not in ("pineda", "pineda-thesis"):
            raise PreconditionError("convex_decomposition", f"unknown preset {preset!r}; "
                                    "choose 'pineda' or 'pineda-thesis'")
        if preset == "pineda-thesis":
            reflex = "straight" if reflex == "strict" else reflex
        criterion_one_rule = "first" if criterion_one_rule == "bisector" else criterion_one_rule
    if reflex not in ("strict", "straight"):
        raise PreconditionError("convex_decomposition", f"unknown reflex rule {reflex!r}")
    if criterion_one_rule not in ("bisector", "first"):
        raise PreconditionError("convex_decomposition",
                                f"unknown criterion-1 rule {criterion_one_rule!r}")
    straight = reflex == "straight"
    if not polygons.sources:
        raise PreconditionError(
            "convex_decomposition",
            "the polygon mesh has no sources: the triangles of each polygon are needed "
            "(make it with polylla, or read the triangulation and run polylla on it)",
        )
    with collector_paused():
        table = _table_of(polygons)
        cycles = _cycles(table, polygons)
        corner_lists = _reflex_corners(table, polygons, cycles, straight)
        inserted: list[Edge] = []
        for corners in corner_lists:
            _decompose(table, corners, criterion_one, inserted, straight,
                       criterion_one_rule == "first")
        result = table.sealed(*table.all_polygons())
    bad = nonconvex_polygons(result)
    if bad:
        raise ConvexDecompositionError([result.polygons[index] for index in bad])
    return ConvexDecomposition(result, tuple(sorted(inserted)), criterion_one,
                               len(corner_lists), reflex, criterion_one_rule)


# -----------------------------------------------------------------------------------------
# the triangulation behind the polygons
# -----------------------------------------------------------------------------------------
def _table_of(polygons: PolygonMesh) -> HalfEdgeTable:
    """The half-edge table of all source triangles (sorted), with frontier half-edges
    between different polygons and on the boundary."""
    owner: dict[tuple[int, int, int], int] = {}
    for index, source in enumerate(polygons.sources):
        for a, b, c in source:
            key = canonical_triangle(a, b, c)
            if owner.setdefault(key, index) != index:
                raise PreconditionError(
                    "convex_decomposition",
                    f"triangle {key} is a source of polygons #{owner[key]} and #{index}",
                )
    triangles = sorted(owner)
    try:
        table = HalfEdgeTable(polygons.vertices, triangles)
    except PolyllaError as error:
        raise PreconditionError("convex_decomposition", f"the source triangles: {error}") \
            from None
    polygon_of = np.array([owner[triangle] for triangle in triangles], dtype=np.int64)
    twin = table.twin_array
    if len(twin):
        mine = polygon_of[np.arange(len(twin)) // 3]
        across = polygon_of[np.where(twin < 0, 0, twin) // 3]
        frontier = (twin < 0) | (mine != across)
        table.frontier[:] = frontier.astype(np.uint8).tobytes()
    return table


def _cycles(table: HalfEdgeTable, polygons: PolygonMesh) -> list[list[int]]:
    """For each polygon, the half-edges of its edges in polygon order, after checking that
    the polygon is simple and that its edges are exactly the frontier half-edges of its
    source triangles (then its triangles are connected and form exactly this polygon)."""
    def fail(index: int, problem: str) -> PreconditionError:
        return PreconditionError("convex_decomposition", f"polygon #{index}: {problem}",
                                 polygon=index)

    owners: list[int] = []
    origins: list[int] = []
    targets: list[int] = []
    for index, polygon in enumerate(polygons.polygons):
        if len(set(polygon)) != len(polygon):
            raise fail(index, "it is not simple (it repeats a vertex)")
        owners.extend([index] * len(polygon))
        origins.extend(polygon)
        targets.extend(polygon[1:])
        targets.append(polygon[0])
    found = table.find(origins, targets)
    polygon_of = np.repeat(np.arange(len(polygons.sources)),
                           [len(source) for source in polygons.sources])
    triangle_owner = np.empty(len(table.triangles), dtype=np.int64)
    order = {triangle: t for t, triangle in enumerate(table.triangles)}
    flat = [order[canonical_triangle(*triangle)]
            for source in polygons.sources for triangle in source]
    triangle_owner[np.array(flat, dtype=np.int64)] = polygon_of
    owner_array = np.array(owners, dtype=np.int64)
    missing = np.flatnonzero((found < 0) | (triangle_owner[np.where(found < 0, 0, found) // 3]
                                            != owner_array))
    if len(missing):
        raise fail(int(owner_array[missing[0]]),
                   "an edge of it is not an edge of its source triangles' boundary")
    frontier_count = np.bincount(
        triangle_owner[np.flatnonzero(np.frombuffer(bytes(table.frontier), dtype=np.uint8))
                       // 3], minlength=len(polygons.polygons))
    sizes = np.array([len(polygon) for polygon in polygons.polygons], dtype=np.int64)
    extra = np.flatnonzero(frontier_count != sizes)
    if len(extra):
        raise fail(int(extra[0]), "its source triangles have boundary edges that are not "
                   "edges of it")
    halfedges: list[int] = found.tolist()
    cycles = []
    position = 0
    for polygon in polygons.polygons:
        cycles.append(halfedges[position:position + len(polygon)])
        position += len(polygon)
    return cycles


# -----------------------------------------------------------------------------------------
# corners
# -----------------------------------------------------------------------------------------
def _reflex_corners(
    table: HalfEdgeTable, polygons: PolygonMesh, cycles: list[list[int]], straight: bool
) -> list[list[int]]:
    """For each non-convex polygon, the half-edges arriving at its reflex corners, in
    polygon order from its smallest vertex."""
    previous: list[int] = []
    middle: list[int] = []
    following: list[int] = []
    for polygon in polygons.polygons:
        count = len(polygon)
        previous.extend(polygon[i - 1] for i in range(count))
        middle.extend(polygon)
        following.extend(polygon[i + 1 - count] for i in range(count))
    signs = orientation_signs(table.points, previous, middle, following)
    result = []
    position = 0
    for polygon, cycle in zip(polygons.polygons, cycles, strict=True):
        count = len(polygon)
        reflex = [i for i in range(count)
                  if signs[position + i] < 0 or (straight and signs[position + i] == 0)]
        position += count
        if reflex:
            start = polygon.index(min(polygon))
            reflex.sort(key=lambda i: (i - start) % count)
            # the corner at polygon[i] is reached along the edge polygon[i - 1] -> polygon[i]
            result.append([cycle[i - 1] for i in reflex])
    return result


# -----------------------------------------------------------------------------------------
# corners
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class _Corner:
    """The current corner at the target ``v`` of frontier half-edge ``arriving``: from the
    direction to ``n`` counter-clockwise to the direction to ``p``; ``fan``: the internal
    half-edges (v, w) inside it, clockwise from p."""

    arriving: int
    p: int
    v: int
    n: int
    fan: tuple[int, ...]

    def reflex(self, points: Sequence[Point2], straight: bool = False) -> bool:
        turn = orient2d(points[self.p], points[self.v], points[self.n])
        return turn == _CW or (straight and turn == _COLLINEAR and bool(self.fan))


def _corner(table: HalfEdgeTable, arriving: int) -> _Corner:
    fan = table.fan(arriving)
    leaving = table.next_frontier(arriving)
    return _Corner(arriving, table.origin[arriving], table.target(arriving),
                   table.target(leaving), tuple(fan))


def _decompose(
    table: HalfEdgeTable, corners: list[int], criterion_one: bool, inserted: list[Edge],
    straight: bool = False, first_found: bool = False,
) -> None:
    """Insert edges at the reflex corners of one polygon (given by their arriving
    half-edges, in polygon order) until none is left."""
    points = table.points
    if criterion_one and not first_found:
        for arriving in corners:
            corner = _corner(table, arriving)
            if corner.reflex(points, straight):
                chosen = _criterion_one(table, corner, straight)
                if chosen is not None:
                    _insert(table, chosen, inserted)
    pending = list(reversed(corners))
    while pending:
        arriving = pending.pop()
        corner = _corner(table, arriving)
        if not corner.reflex(points, straight):
            continue
        repair = None
        if criterion_one and first_found:
            repair = _criterion_one(table, corner, straight, first=True)
        chosen_edges = [repair] if repair is not None else _angle_choice(table, corner)
        for g in chosen_edges:
            _insert(table, g, inserted)
        # the pieces at v (arriving along h and along each new edge) and the piece of the
        # far end that now arrives along the new edge are examined again
        pending.append(arriving)
        for g in chosen_edges:
            pending.append(g)
            pending.append(table.twin[g])


def _insert(table: HalfEdgeTable, g: int, inserted: list[Edge]) -> None:
    table.frontier[g] = table.frontier[table.twin[g]] = 1
    u, v = table.edge(g)
    inserted.append((u, v) if u < v else (v, u))


def _both_halves_convex(points: Sequence[Point2], p: int, v: int, n: int, w: int) -> bool:
    """Whether the edge (v, w) leaves both pieces of the corner (n .. p at v) at most
    180°."""
    pv, pw = points[v], points[w]
    return orient2d(pv, points[n], pw) != _CW and orient2d(pv, pw, points[p]) != _CW


def _criterion_one(
    table: HalfEdgeTable, corner: _Corner, straight: bool = False, first: bool = False
) -> int | None:
    """The criterion-1 candidate of a reflex corner closest to its bisector (``first``:
    the first in its fan), or None."""
    points, origin, twin, frontier = table.points, table.origin, table.twin, table.frontier
    found = []
    for g in corner.fan:
        w = table.target(g)
        if not _both_halves_convex(points, corner.p, corner.v, corner.n, w):
            continue
        # the corner at w around the edge (w, v): clockwise to the leaving frontier
        # half-edge, counter-clockwise to the arriving one
        q = g + 1 if g % 3 != 2 else g - 2
        while not frontier[q]:
            q = twin[q]
            q = q + 1 if q % 3 != 2 else q - 2
        n_w = table.target(q)
        o = twin[g]
        r = o - 1 if o % 3 else o + 2
        while not frontier[r]:
            o = twin[r]
            r = o - 1 if o % 3 else o + 2
        p_w = origin[r]
        turn = orient2d(points[p_w], points[w], points[n_w])
        if turn != _CW and not (straight and turn == _COLLINEAR):
            continue
        if _both_halves_convex(points, p_w, w, n_w, corner.v):
            if first:
                return g
            found.append(g)
    if not found:
        return None
    return _closest(table, corner, found, 1, 2)


def _angle_choice(table: HalfEdgeTable, corner: _Corner) -> list[int]:
    """Criteria 2 and 3 for a reflex corner: the candidate closest to the bisector when it
    leaves both pieces at most 180°, else those closest to the two trisectors."""
    points = table.points
    candidates = list(corner.fan)
    best = _closest(table, corner, candidates, 1, 2)
    if _both_halves_convex(points, corner.p, corner.v, corner.n, table.target(best)):
        return [best]
    first = _closest(table, corner, candidates, 1, 3)
    second = _closest(table, corner, candidates, 2, 3)
    return [first] if first == second else [first, second]


# -----------------------------------------------------------------------------------------
# exact angles
# -----------------------------------------------------------------------------------------
# An angle is (turns, x, y): 2π·turns + arg(x + iy) with arg in [0, 2π).  Adding angles
# multiplies the complex numbers; comparing them compares turns, then the arguments
# (half-plane, then the sign of a cross product).
_Angle = tuple[int, Rational, Rational]


def _upper(x: Rational, y: Rational) -> bool:
    """True when arg(x + iy) is in [0, π)."""
    return bool(y > 0 or (y == 0 and x > 0))


def _arg_compare(ax: Rational, ay: Rational, bx: Rational, by: Rational) -> int:
    """The sign of arg(a) - arg(b), both in [0, 2π)."""
    ua, ub = _upper(ax, ay), _upper(bx, by)
    if ua != ub:
        return -1 if ua else 1
    cross = ax * by - ay * bx
    return (cross < 0) - (cross > 0)  # type: ignore[no-any-return]


def _compare(a: _Angle, b: _Angle) -> int:
    if a[0] != b[0]:
        return -1 if a[0] < b[0] else 1
    return _arg_compare(a[1], a[2], b[1], b[2])


def _add(a: _Angle, b: _Angle) -> _Angle:
    ta, ax, ay = a
    tb, bx, by = b
    x, y = ax * bx - ay * by, ax * by + ay * bx
    wraps = not (by == 0 and bx > 0) and _arg_compare(x, y, ax, ay) < 0
    return ta + tb + wraps, x, y


def _times(a: _Angle, k: int) -> _Angle:
    result = a
    for _ in range(k - 1):
        result = _add(result, a)
    return result


def _turn(points: Sequence[Point2], v: int, start: int, end: int) -> _Angle:
    """The angle at v from the direction to ``start`` counter-clockwise to the direction
    to ``end`` (in [0, 2π))."""
    pv, ps, pe = points[v], points[start], points[end]
    sx, sy = ps.x - pv.x, ps.y - pv.y
    ex, ey = pe.x - pv.x, pe.y - pv.y
    return 0, ex * sx + ey * sy, ey * sx - ex * sy


def _closest(
    table: HalfEdgeTable, corner: _Corner, candidates: list[int], k: int, m: int
) -> int:
    """The candidate half-edge (v, w) whose direction is closest in angle to the ray at
    k/m of the corner's angle (from the direction to n); ties: smaller vertex pair."""
    points = table.points
    whole = _turn(points, corner.v, corner.n, corner.p)
    target = _times(whole, k)
    best = candidates[0]
    best_angle = _turn(points, corner.v, corner.n, table.target(best))
    best_side = _compare(_times(best_angle, m), target)
    for g in candidates[1:]:
        angle = _turn(points, corner.v, corner.n, table.target(g))
        side = _compare(_times(angle, m), target)
        closer = _closer(angle, side, best_angle, best_side, target, m)
        if closer > 0 or (closer == 0 and _pair(table, g) < _pair(table, best)):
            best, best_angle, best_side = g, angle, side
    return best


def _closer(a: _Angle, side_a: int, b: _Angle, side_b: int, target: _Angle, m: int) -> int:
    """1 when |m·a - target| < |m·b - target|, 0 when equal, -1 otherwise (``side_*``: the
    sign of m·angle - target)."""
    if side_a == 0 or side_b == 0:
        return (side_a == 0) - (side_b == 0)
    if side_a == side_b:  # same side: the nearer angle is closer
        order = _compare(a, b)
        return order if side_a < 0 else -order
    # opposite sides: |m·a - T| < |m·b - T|  <=>  (for a below) 2T < m·(a + b)
    order = _compare(_times(target, 2), _times(_add(a, b), m))
    return -order if side_a < 0 else order


def _pair(table: HalfEdgeTable, g: int) -> Edge:
    u, v = table.edge(g)
    return (u, v) if u < v else (v, u)
