"""Independent exact checks used by the Delaunay tests (no tests here).

Everything is recomputed from the mesh tables and the exact predicates, never through
``geomexact.mesh2d.delaunay.triangulation`` itself: the convex hull (monotone chain), polygon areas (shoelace),
the empty-circle property, Euler characteristics, boundary loops, and the points of an
input segment.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence

from geomexact import (
    PSLG,
    CircleLocation,
    Mesh2,
    Orientation,
    incircle,
    orient2d,
    point2,
    replay,
    validate,
)
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.kernel.points import Point2
from geomexact.mesh2d.delaunay.triangulation import Construction
from geomexact.mesh2d.snapshot import canonical_triangle

CCW = Orientation.COUNTERCLOCKWISE
CW = Orientation.CLOCKWISE
COLLINEAR = Orientation.COLLINEAR
INSIDE = CircleLocation.INSIDE
COCIRCULAR = CircleLocation.COCIRCULAR

CoordinateTriangle = frozenset[tuple[Rational, Rational]]


# -- hulls and areas -----------------------------------------------------------------------
def convex_hull(points: Iterable[Point2]) -> list[Point2]:
    """Corners of the convex hull, counter-clockwise, without collinear boundary points
    (Andrew's monotone chain, exact)."""
    unique = sorted(set(points), key=lambda p: (p.x, p.y))
    if len(unique) < 3:
        return unique

    def chain(sequence: list[Point2]) -> list[Point2]:
        result: list[Point2] = []
        for p in sequence:
            while len(result) >= 2 and orient2d(result[-2], result[-1], p) != CCW:
                result.pop()
            result.append(p)
        return result

    lower, upper = chain(unique), chain(unique[::-1])
    return lower[:-1] + upper[:-1]


def on_closed_segment(p: Point2, a: Point2, b: Point2) -> bool:
    """True when p lies on the closed segment ab (exact)."""
    return orient2d(a, b, p) == COLLINEAR and (
        min(a.x, b.x) <= p.x <= max(a.x, b.x) and min(a.y, b.y) <= p.y <= max(a.y, b.y)
    )


def hull_boundary_points(points: Iterable[Point2]) -> set[Point2]:
    """The distinct points on the boundary of their convex hull: corners and the points in
    the relative interior of hull edges."""
    unique = set(points)
    hull = convex_hull(unique)
    edges = list(zip(hull, hull[1:] + hull[:1], strict=True))
    return {p for p in unique if any(on_closed_segment(p, a, b) for a, b in edges)}


def polygon_area(polygon: Sequence[Point2]) -> Rational:
    """Signed area (shoelace), exact."""
    twice = ZERO
    for p, q in zip(polygon, [*polygon[1:], polygon[0]], strict=True):
        twice += p.x * q.y - q.x * p.y
    return twice / 2


def mesh_area(mesh: Mesh2) -> Rational:
    """Exact sum of the triangle areas, from the half-edge table."""
    twice = ZERO
    for a, b, c in mesh.triangles():
        pa, pb, pc = mesh.point(a), mesh.point(b), mesh.point(c)
        twice += (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x)
    return twice / 2


def segment_loops(pslg: PSLG) -> list[list[int]]:
    """The closed loops of a PSLG whose vertices all have segment degree 2."""
    neighbours: dict[int, list[int]] = {}
    for u, v, _ in pslg.segments:
        neighbours.setdefault(u, []).append(v)
        neighbours.setdefault(v, []).append(u)
    assert all(len(n) == 2 for n in neighbours.values()), "not a union of loops"
    seen: set[int] = set()
    loops = []
    for start in sorted(neighbours):
        if start in seen:
            continue
        loop, previous, current = [start], None, start
        seen.add(start)
        while True:
            a, b = neighbours[current]
            following = b if a == previous else a
            if following == start:
                break
            loop.append(following)
            seen.add(following)
            previous, current = current, following
        loops.append(loop)
    return loops


# -- triangles as geometry -----------------------------------------------------------------
def coordinate_triangles(mesh: Mesh2) -> set[CoordinateTriangle]:
    """Triangles as sets of exact coordinate pairs (independent of vertex ids)."""
    return {
        frozenset((mesh.point(v).x, mesh.point(v).y) for v in triangle)
        for triangle in mesh.triangles()
    }


def inside(point: Point2, polygon: Sequence[Point2]) -> bool:
    """Crossing-number test for a point not on the polygon's border (exact)."""
    result = False
    for p, q in zip(polygon, [*polygon[1:], polygon[0]], strict=True):
        if (p.y > point.y) != (q.y > point.y):
            x = p.x + (point.y - p.y) * (q.x - p.x) / (q.y - p.y)
            if x > point.x:
                result = not result
    return result


def in_closed_triangle(p: Point2, a: Point2, b: Point2, c: Point2) -> bool:
    """True when p is in the closed counter-clockwise triangle abc."""
    return CW not in (orient2d(a, b, p), orient2d(b, c, p), orient2d(c, a, p))


def triangles_containing(mesh: Mesh2, p: Point2) -> list[tuple[int, int, int]]:
    return [t for t in mesh.triangles() if in_closed_triangle(p, *(mesh.point(v) for v in t))]


def used_vertices(mesh: Mesh2) -> set[int]:
    return {v for triangle in mesh.triangles() for v in triangle}


# -- Delaunay ------------------------------------------------------------------------------
def locally_non_delaunay(mesh: Mesh2) -> list[tuple[int, int]]:
    """Unconstrained interior edges {u, v} whose opposite apex is strictly inside the
    circumcircle of the other triangle (exact incircle)."""
    found = []
    for u, v in mesh.edges():
        w, x = mesh.apex(u, v), mesh.apex(v, u)
        if w is None or x is None or mesh.is_constrained(u, v):
            continue
        if incircle(mesh.point(u), mesh.point(v), mesh.point(w), mesh.point(x)) == INSIDE:
            found.append((u, v))
    return found


def globally_non_empty(mesh: Mesh2) -> list[tuple[tuple[int, int, int], int]]:
    """(triangle, vertex) pairs with a mesh vertex strictly inside the triangle's
    circumcircle: the empty-circle property of an unconstrained Delaunay triangulation,
    checked against every vertex.  O(n T): for small meshes."""
    used = sorted(used_vertices(mesh))
    found = []
    for a, b, c in mesh.triangles():
        pa, pb, pc = mesh.point(a), mesh.point(b), mesh.point(c)
        for v in used:
            if v not in (a, b, c) and incircle(pa, pb, pc, mesh.point(v)) == INSIDE:
                found.append(((a, b, c), v))
    return found


def cocircular_among(points: Sequence[Point2]) -> bool:
    """True when some four of ``points`` lie on one circle (or one line)."""
    n = len(points)
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                for m in range(k + 1, n):
                    if incircle(points[i], points[j], points[k], points[m]) == COCIRCULAR:
                        return True
    return False


def differ_only_where_cocircular(first: Mesh2, second: Mesh2) -> bool:
    """Equal triangle sets, or the triangles that differ have four cocircular corners
    among them (where the Delaunay triangulation is not unique)."""
    a, b = coordinate_triangles(first), coordinate_triangles(second)
    if a == b:
        return True
    corners = sorted({corner for triangle in a ^ b for corner in triangle})
    return cocircular_among([point2(x, y) for x, y in corners])


# -- topology ------------------------------------------------------------------------------
def euler_characteristic(mesh: Mesh2) -> int:
    """V - E + T over the vertices used by triangles."""
    return len(used_vertices(mesh)) - len(mesh.edges()) + mesh.triangle_count


def components(mesh: Mesh2) -> int:
    """Connected components of triangles joined by edges."""
    seen: set[tuple[int, int, int]] = set()
    count = 0
    for triangle in mesh.triangles():
        if triangle in seen:
            continue
        count += 1
        stack = [triangle]
        seen.add(triangle)
        while stack:
            a, b, c = stack.pop()
            for u, v in ((a, b), (b, c), (c, a)):
                w = mesh.apex(v, u)
                if w is not None:
                    neighbour = canonical_triangle(v, u, w)
                    if neighbour not in seen:
                        seen.add(neighbour)
                        stack.append(neighbour)
    return count


def boundary_loops(mesh: Mesh2) -> int:
    """Closed loops of boundary half-edges (each vertex on at most one loop)."""
    following = {u: v for u, v in mesh.boundary_edges()}
    seen: set[int] = set()
    loops = 0
    for start in sorted(following):
        if start in seen:
            continue
        loops += 1
        vertex = start
        while vertex not in seen:
            seen.add(vertex)
            vertex = following[vertex]
    return loops


# -- segments ------------------------------------------------------------------------------
def points_on_segment(mesh: Mesh2, a: Point2, b: Point2) -> list[int]:
    """Used mesh vertices on the closed segment ab, sorted from a to b."""
    on = [v for v in used_vertices(mesh) if on_closed_segment(mesh.point(v), a, b)]
    return sorted(on, key=lambda v: (mesh.point(v).x - a.x) * (b.x - a.x)
                  + (mesh.point(v).y - a.y) * (b.y - a.y))


def segment_is_union_of_constrained_edges(mesh: Mesh2, a: Point2, b: Point2) -> bool:
    """The mesh vertices on segment ab, in order, are joined by constrained edges."""
    chain = points_on_segment(mesh, a, b)
    if len(chain) < 2 or mesh.point(chain[0]) != a or mesh.point(chain[-1]) != b:
        return False
    return all(mesh.is_constrained(u, v) for u, v in itertools.pairwise(chain))


# -- whole constructions -------------------------------------------------------------------
def assert_sound(construction: Construction) -> None:
    """Valid (every snapshot invariant), exact (no float coordinate), and replayable."""
    mesh = construction.mesh
    assert validate(mesh) == []
    assert all(type(p.x) is mpq and type(p.y) is mpq for p in mesh.vertices.values())
    assert construction.trace.input_digest == construction.start.digest
    assert construction.trace.final_digest == mesh.digest
    assert replay(construction.start, construction.trace) == mesh
    assert construction.start.triangle_count == 0
    assert construction.start.vertex_count <= mesh.vertex_count


def point_set_triangle_count(points: Iterable[Point2]) -> int:
    """Triangles of any triangulation of a point set (every point used, the hull covered):
    T = 2n - 2 - h with n distinct points and h of them on the hull boundary (corners and
    points on hull edges: each is a boundary vertex of the triangulation).  Derivation:
    3T + h = 2E (each triangle has 3 edges, interior edges have 2 triangles, boundary edges
    1, and the boundary is a cycle through the h points) and n - E + T = 1 (Euler for a
    disk)."""
    unique = set(points)
    return 2 * len(unique) - 2 - len(hull_boundary_points(unique))
