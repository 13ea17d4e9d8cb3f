"""Polygon meshes (e.g. Polylla output): the :class:`PolygonMesh` value, its exact checker
:func:`validate_polygon_mesh` and its statistics :func:`mesh_stats`.

A polygon is a counter-clockwise cycle of vertex ids.  A polygon mesh built from a
triangulation (Polylla, convex decomposition) also lists, for each polygon, the triangles
it is made of (``sources``); the checker then proves exactly, and cheaply, that the
polygons partition the triangulation.  Spec: ``specs/polylla.md`` (polygon meshes).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from functools import cmp_to_key
from typing import Any

import attrs

from geomexact.errors import InvalidMeshError, PreconditionError, Violation
from geomexact.kernel.numbers import ZERO, Rational, format_rational
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.measures import angle_and_area_report, atan2_degrees
from geomexact.mesh2d.segments import meeting_pairs
from geomexact.mesh2d.snapshot import Edge, Mesh2, Triangle, canonical_triangle

__all__ = [
    "PolygonMesh",
    "check_polygon_mesh",
    "interior_angles_degrees",
    "is_convex_polygon",
    "mesh_stats",
    "nonconvex_polygons",
    "orientation_signs",
    "polygon_twice_area",
    "reflex_vertices",
    "validate_polygon_mesh",
]

_CW = Orientation.CLOCKWISE
_CCW = Orientation.COUNTERCLOCKWISE


# Typed converters: mypy cannot type attrs fields converted by the generic ``tuple``.
def _points(values: Iterable[Point2]) -> tuple[Point2, ...]:
    return tuple(values)


def _polygons(values: Iterable[Iterable[int]]) -> tuple[tuple[int, ...], ...]:
    return tuple(tuple(polygon) for polygon in values)


def _sources(values: Iterable[Iterable[Triangle]]) -> tuple[tuple[Triangle, ...], ...]:
    return tuple(tuple(source) for source in values)


@attrs.frozen(slots=True)
class PolygonMesh:
    """An immutable polygon mesh with exact vertices.

    - ``vertices``: the points, ids = positions (vertices in no polygon are allowed);
    - ``polygons``: tuples of at least 3 vertex ids, counter-clockwise for a valid mesh;
    - ``sources``: empty, or one tuple per polygon of the counter-clockwise triangles it is
      the union of (canonical triangles, see :func:`~geomexact.mesh2d.snapshot.canonical_triangle`).

    The constructor checks only the structure (sizes, ids); :meth:`validate` checks the
    geometry exactly (simple, counter-clockwise, no overlap, sources partitioning a
    triangulation).  Equality compares exact content.
    """

    vertices: tuple[Point2, ...] = attrs.field(converter=_points)
    polygons: tuple[tuple[int, ...], ...] = attrs.field(converter=_polygons)
    sources: tuple[tuple[Triangle, ...], ...] = attrs.field(converter=_sources, default=())

    def __attrs_post_init__(self) -> None:
        count = len(self.vertices)
        for index, polygon in enumerate(self.polygons):
            if len(polygon) < 3:
                raise PreconditionError(
                    "PolygonMesh", f"polygon #{index} has {len(polygon)} vertices (< 3)",
                    polygon=index,
                )
            if min(polygon) < 0 or max(polygon) >= count:
                vertex = next(v for v in polygon if not 0 <= v < count)
                raise PreconditionError(
                    "PolygonMesh", f"polygon #{index} refers to missing vertex {vertex}",
                    polygon=index, vertex=vertex,
                )
        if self.sources:
            if len(self.sources) != len(self.polygons):
                raise PreconditionError(
                    "PolygonMesh",
                    f"{len(self.sources)} source lists for {len(self.polygons)} polygons: one "
                    "per polygon is needed",
                )
            for index, source in enumerate(self.sources):
                if not source:
                    raise PreconditionError(
                        "PolygonMesh", f"polygon #{index} has an empty source list",
                        polygon=index,
                    )
                for triangle in source:
                    if len(triangle) != 3 or min(triangle) < 0 or max(triangle) >= count:
                        raise PreconditionError(
                            "PolygonMesh",
                            f"source {triangle} of polygon #{index} is not a triangle of "
                            "existing vertices",
                            polygon=index,
                        )

    # -- queries --------------------------------------------------------------------------
    def polygon_points(self, index: int) -> tuple[Point2, ...]:
        """The points of polygon ``index`` in its vertex order."""
        vertices = self.vertices
        return tuple(vertices[vertex] for vertex in self.polygons[index])

    def edges(self) -> list[Edge]:
        """Every polygon edge once, as sorted ``(min, max)`` pairs.  O(n log n)."""
        found: set[Edge] = set()
        for polygon in self.polygons:
            previous = polygon[-1]
            for vertex in polygon:
                found.add((previous, vertex) if previous < vertex else (vertex, previous))
                previous = vertex
        return sorted(found)

    def area(self, index: int) -> Rational:
        """The exact signed area of polygon ``index`` (positive when counter-clockwise)."""
        return polygon_twice_area(self.vertices, self.polygons[index]) / 2

    def total_area(self) -> Rational:
        """The exact sum of the polygons' signed areas."""
        vertices = self.vertices
        twice = ZERO
        for polygon in self.polygons:
            twice += polygon_twice_area(vertices, polygon)
        return twice / 2

    def validate(
        self, triangulation: Mesh2 | None = None, *, geometric: bool | None = None
    ) -> list[Violation]:
        """Every violated invariant (see :func:`validate_polygon_mesh`)."""
        return validate_polygon_mesh(self, triangulation, geometric=geometric)

    def __repr__(self) -> str:
        return (
            f"PolygonMesh(vertices={len(self.vertices)}, polygons={len(self.polygons)}, "
            f"sources={'yes' if self.sources else 'no'})"
        )


# -----------------------------------------------------------------------------------------
# single polygons
# -----------------------------------------------------------------------------------------
def polygon_twice_area(points: Sequence[Point2], polygon: Sequence[int]) -> Rational:
    """Twice the exact signed area of ``polygon`` (shoelace; positive when
    counter-clockwise)."""
    twice = ZERO
    previous = points[polygon[-1]]
    for vertex in polygon:
        point = points[vertex]
        twice += previous.x * point.y - point.x * previous.y
        previous = point
    return twice


def orientation_signs(
    points: Sequence[Point2], a: Sequence[int], b: Sequence[int], c: Sequence[int]
) -> list[int]:
    """``orient2d(points[a[i]], points[b[i]], points[c[i]])`` for every i, as -1, 0 or 1.

    Exact: the float filter of :func:`~geomexact.kernel.predicates2d.orient2d` on numpy
    arrays (:func:`~geomexact.kernel.array_filters.orient2d_signs`) decides most triples
    at once; ``orient2d`` itself decides the rest.  O(n)."""
    if len(a) == 0:
        return []
    # imported here: NumPy only where polygons are checked, not for every reader
    from geomexact.kernel.array_filters import orient2d_signs, point_doubles

    fx, fy = point_doubles(points)
    signs = orient2d_signs(fx, fy, a, b, c)
    result: list[int] = signs.tolist()
    for i in [i for i, sign in enumerate(result) if sign == 0]:
        result[i] = int(orient2d(points[a[i]], points[b[i]], points[c[i]]))
    return result


def nonconvex_polygons(mesh: PolygonMesh) -> list[int]:
    """The indices of the polygons with a reflex corner (exact, see
    :func:`reflex_vertices`), sorted.  O(n)."""
    previous: list[int] = []
    middle: list[int] = []
    following: list[int] = []
    owner: list[int] = []
    for index, polygon in enumerate(mesh.polygons):
        count = len(polygon)
        previous.extend(polygon[i - 1] for i in range(count))
        middle.extend(polygon)
        following.extend(polygon[i + 1 - count] for i in range(count))
        owner.extend([index] * count)
    signs = orientation_signs(mesh.vertices, previous, middle, following)
    return sorted({owner[i] for i, sign in enumerate(signs) if sign < 0})


def reflex_vertices(points: Sequence[Point2], polygon: Sequence[int]) -> list[int]:
    """The vertices of the counter-clockwise ``polygon`` where it turns right (exact
    orientation: a collinear corner is not reflex), in polygon order."""
    count = len(polygon)
    found = []
    for index in range(count):
        a = points[polygon[index - 1]]
        vertex = polygon[index]
        c = points[polygon[index + 1 - count]]
        if orient2d(a, points[vertex], c) == _CW:
            found.append(vertex)
    return found


def is_convex_polygon(points: Sequence[Point2], polygon: Sequence[int]) -> bool:
    """True when the counter-clockwise ``polygon`` has no reflex vertex (exact; corners
    where it goes straight on count as convex)."""
    count = len(polygon)
    for index in range(count):
        if orient2d(points[polygon[index - 1]], points[polygon[index]],
                    points[polygon[index + 1 - count]]) == _CW:
            return False
    return True


def interior_angles_degrees(points: Sequence[Point2], polygon: Sequence[int]) -> list[float]:
    """The interior angle at each vertex of the counter-clockwise ``polygon`` in degrees,
    in (0, 360) (floating point, for reports; computed from the exact cross and dot
    products, at any magnitude)."""
    count = len(polygon)
    angles = []
    for index in range(count):
        p = points[polygon[index - 1]]
        v = points[polygon[index]]
        n = points[polygon[index + 1 - count]]
        # interior angle: from the direction to the next vertex, counter-clockwise, to the
        # direction to the previous one
        ux, uy = n.x - v.x, n.y - v.y
        wx, wy = p.x - v.x, p.y - v.y
        angle = atan2_degrees(ux * wy - uy * wx, ux * wx + uy * wy)
        angles.append(angle + 360.0 if angle < 0 else angle)
    return angles


# -----------------------------------------------------------------------------------------
# the checker
# -----------------------------------------------------------------------------------------
def validate_polygon_mesh(
    mesh: PolygonMesh, triangulation: Mesh2 | None = None, *, geometric: bool | None = None
) -> list[Violation]:
    """Every violation of the polygon-mesh invariants, in a deterministic order (empty when
    the mesh is valid).  All tests are exact.

    Always checked: no polygon repeats a vertex (``repeated-vertex``); every polygon is
    strictly counter-clockwise (``orientation``); no directed edge belongs to two polygons
    (``duplicate-edge``).

    With ``sources`` (O(n)): every source triangle is counter-clockwise and belongs to one
    polygon only (``source-triangle``, ``triangle-twice``); the boundary of each polygon's
    triangles (their half-edges whose reverse is not a half-edge of the same polygon's
    triangles) is exactly the polygon's edge cycle (``source-boundary``); the total area of
    the polygons equals that of the triangles (``area``).  Since triangles of a valid
    triangulation do not overlap, this proves that each polygon is the union of its
    triangles, is simple, and that polygons do not overlap.

    With ``triangulation``: it is itself valid (:func:`geomexact.mesh2d.validation`, violations
    reported as ``triangulation``); the vertices of the polygons are its vertices
    (``vertex``); the sources are exactly its triangles, each in one polygon
    (``coverage``); and the polygons' union has its area exactly (``area``).

    ``geometric`` (default: only when there are no sources) adds the direct geometric
    checks, O(n log n + crossings found by an x-sweep): no two polygon edges meet except at
    common endpoints (``self-intersection`` within a polygon, ``crossing`` between
    polygons), polygons meeting at a vertex do not overlap there (``overlap``), and no
    connected group of polygons lies inside a polygon of another group (``overlap``).
    """
    found: list[Violation] = []
    points = mesh.vertices
    for index, polygon in enumerate(mesh.polygons):
        if len(set(polygon)) != len(polygon):
            repeated = sorted({v for v in polygon if polygon.count(v) > 1})
            found.append(Violation("repeated-vertex", f"polygon #{index} visits vertex "
                                   f"{repeated[0]} more than once", (index, *repeated)))
        twice = polygon_twice_area(points, polygon)
        if twice <= 0:
            what = "has zero area" if twice == 0 else "is clockwise"
            found.append(Violation("orientation", f"polygon #{index} {what}", (index,)))
    owner: dict[Edge, int] = {}
    for index, polygon in enumerate(mesh.polygons):
        previous = polygon[-1]
        for vertex in polygon:
            key = (previous, vertex)
            other = owner.setdefault(key, index)
            if other != index:  # a repeat within one polygon repeats a vertex (above)
                found.append(Violation("duplicate-edge", f"directed edge {key} belongs to "
                                       f"polygons #{other} and #{index}", (other, index)))
            previous = vertex
    if mesh.sources:
        found.extend(_check_sources(mesh))
    if triangulation is not None:
        found.extend(_check_triangulation(mesh, triangulation))
    if geometric or (geometric is None and not mesh.sources):
        found.extend(_check_geometry(mesh))
    return found


def isolated_polygon_vertices(mesh: PolygonMesh) -> list[Violation]:
    """An ``isolated-vertex`` violation for each vertex in no polygon (legal in a polygon
    mesh, reported by ``geomexact check --strict``), in id order.  O(n)."""
    used = {vertex for polygon in mesh.polygons for vertex in polygon}
    return [
        Violation("isolated-vertex", f"vertex {vertex} is in no polygon", (vertex,))
        for vertex in range(len(mesh.vertices)) if vertex not in used
    ]


def check_polygon_mesh(
    mesh: PolygonMesh, triangulation: Mesh2 | None = None, *, geometric: bool | None = None
) -> PolygonMesh:
    """Return ``mesh`` when it is valid, else raise :class:`InvalidMeshError` listing every
    violation (see :func:`validate_polygon_mesh`)."""
    violations = validate_polygon_mesh(mesh, triangulation, geometric=geometric)
    if violations:
        raise InvalidMeshError(violations)
    return mesh


def _check_sources(mesh: PolygonMesh) -> list[Violation]:
    found: list[Violation] = []
    points = mesh.vertices
    seen: dict[Triangle, int] = {}
    twice_triangles = ZERO
    for index, (polygon, source) in enumerate(zip(mesh.polygons, mesh.sources, strict=True)):
        halfedges: set[Edge] = set()
        good = True
        for triangle in source:
            a, b, c = triangle
            key = canonical_triangle(a, b, c)
            pa, pb, pc = points[a], points[b], points[c]
            if len({a, b, c}) != 3 or orient2d(pa, pb, pc) != _CCW:
                found.append(Violation("source-triangle", f"source {triangle} of polygon "
                                       f"#{index} is not counter-clockwise", (index, a, b, c)))
                good = False
                continue
            other = seen.setdefault(key, index)
            if other != index:  # a repeat within one source repeats its half-edges
                found.append(Violation("triangle-twice", f"triangle {key} belongs to polygons "
                                       f"#{other} and #{index}", (other, index, *key)))
                good = False
            twice_triangles += (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x)
            for edge in ((a, b), (b, c), (c, a)):
                if edge in halfedges:
                    found.append(Violation("source-boundary", f"triangles of polygon #{index} "
                                           f"share the directed edge {edge}", (index, *edge)))
                    good = False
                halfedges.add(edge)
        if not good:
            continue
        boundary = {(u, v) for u, v in halfedges if (v, u) not in halfedges}
        previous = polygon[-1]
        cycle = set()
        for vertex in polygon:
            cycle.add((previous, vertex))
            previous = vertex
        if boundary != cycle:
            extra = sorted(boundary - cycle)
            missing = sorted(cycle - boundary)
            detail = (f"its triangles' boundary has {extra[:3]} not in the cycle"
                      if extra else f"the cycle has {missing[:3]} not on its triangles' "
                      "boundary")
            found.append(Violation("source-boundary", f"polygon #{index} is not the union of "
                                   f"its triangles: {detail}", (index,)))
    twice_polygons = 2 * mesh.total_area()
    if not found and twice_polygons != twice_triangles:
        found.append(Violation("area", f"polygons cover area {format_rational(twice_polygons / 2)}"
                               f" but their triangles {format_rational(twice_triangles / 2)}"))
    return found


def _check_triangulation(mesh: PolygonMesh, triangulation: Mesh2) -> list[Violation]:
    # imported here: the validation's arrays (NumPy) only where a polygon mesh is checked
    from geomexact.mesh2d.validation import validate as validate_triangulation

    found = [Violation("triangulation", str(violation), violation.elements)
             for violation in validate_triangulation(triangulation, check_digest=False)]
    points = mesh.vertices
    used = sorted({vertex for polygon in mesh.polygons for vertex in polygon})
    for vertex in used:
        if vertex not in triangulation.vertices or triangulation.vertices[vertex] != points[vertex]:
            found.append(Violation("vertex", f"vertex {vertex} of the polygons is not vertex "
                                   f"{vertex} of the triangulation", (vertex,)))
            break
    if not mesh.sources:
        found.append(Violation("coverage", "the polygon mesh has no sources to compare with "
                               "the triangulation's triangles"))
        return found
    listed = {canonical_triangle(*t) for source in mesh.sources for t in source}
    actual = set(triangulation.iter_triangles())
    missing = sorted(actual - listed)
    extra = sorted(listed - actual)
    if missing:
        found.append(Violation("coverage", f"{len(missing)} triangle(s) of the triangulation "
                               f"are in no polygon, e.g. {missing[0]}", missing[0]))
    if extra:
        found.append(Violation("coverage", f"{len(extra)} source triangle(s) are not triangles "
                               f"of the triangulation, e.g. {extra[0]}", extra[0]))
    if not found:
        polygons_area = mesh.total_area()
        domain = ZERO
        vertices = triangulation.vertices
        for a, b, c in actual:
            pa, pb, pc = vertices[a], vertices[b], vertices[c]
            domain += (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x)
        domain /= 2
        if polygons_area != domain:
            found.append(Violation("area", f"polygons cover area {format_rational(polygons_area)}"
                                   f" but the triangulation {format_rational(domain)}"))
    return found


# -- geometric checks (no sources needed) -------------------------------------------------
def _check_geometry(mesh: PolygonMesh) -> list[Violation]:
    points = mesh.vertices
    edge_polygons: dict[Edge, list[int]] = {}
    for index, polygon in enumerate(mesh.polygons):
        previous = polygon[-1]
        for vertex in polygon:
            key = (previous, vertex) if previous < vertex else (vertex, previous)
            edge_polygons.setdefault(key, []).append(index)
            previous = vertex
    found: list[Violation] = []
    for first, second in meeting_pairs(points, sorted(edge_polygons)):
        owners_a, owners_b = set(edge_polygons[first]), set(edge_polygons[second])
        common = sorted(owners_a & owners_b)
        if common:
            found.append(Violation("self-intersection", f"edges {first} and {second} of polygon "
                                   f"#{common[0]} meet", (common[0], *first, *second)))
        else:
            found.append(Violation("crossing", f"edge {first} of polygon #{min(owners_a)} meets "
                                   f"edge {second} of polygon #{min(owners_b)}",
                                   (*first, *second)))
    if found:
        return found  # the angular checks below assume edges meet only at endpoints
    found.extend(_corner_overlaps(mesh))
    if not found:
        found.extend(_nested_groups(mesh))
    return found


def _direction_order(points: Sequence[Point2], center: Point2) -> Any:
    """A sort key ordering vertices by the direction from ``center`` to them,
    counter-clockwise from the positive x axis (exact)."""

    def half(vertex: int) -> int:
        p = points[vertex]
        dy = p.y - center.y
        return 0 if dy > 0 or (dy == 0 and p.x > center.x) else 1

    def compare(a: int, b: int) -> int:
        ha, hb = half(a), half(b)
        if ha != hb:
            return ha - hb
        return -int(orient2d(center, points[a], points[b]))

    return cmp_to_key(compare)


def _corner_overlaps(mesh: PolygonMesh) -> list[Violation]:
    """Polygons that overlap near a vertex they share: the angular sectors between
    consecutive edges around the vertex may each lie inside one polygon only."""
    points = mesh.vertices
    corners: dict[int, list[tuple[int, int, int]]] = {}
    for index, polygon in enumerate(mesh.polygons):
        count = len(polygon)
        for position, vertex in enumerate(polygon):
            previous = polygon[position - 1]
            following = polygon[position + 1 - count]
            corners.setdefault(vertex, []).append((index, previous, following))
    found: list[Violation] = []
    for vertex in sorted(corners):
        around = corners[vertex]
        if len(around) < 2:
            continue
        neighbours = sorted({n for _, p, f in around for n in (p, f)},
                            key=_direction_order(points, points[vertex]))
        pair = _first_overlap(around, {n: i for i, n in enumerate(neighbours)})
        if pair is not None:
            found.append(Violation("overlap", f"polygons #{pair[0]} and #{pair[1]} overlap at "
                                   f"vertex {vertex}", (vertex, *pair)))
    return found


def _first_overlap(
    around: list[tuple[int, int, int]], position: dict[int, int]
) -> tuple[int, int] | None:
    """Two polygons whose interiors at a vertex share a sector, or None.  ``around``:
    (polygon, previous vertex, next vertex) per corner; ``position``: neighbour -> its
    index in counter-clockwise order."""
    size = len(position)
    cover: list[int | None] = [None] * size
    for index, previous, following in around:
        # the interior at the vertex: from the edge to the next vertex, counter-clockwise,
        # to the edge from the previous vertex
        sector = position[following]
        while sector != position[previous]:
            owner = cover[sector]
            if owner is not None:
                return owner, index
            cover[sector] = index
            sector = (sector + 1) % size
    return None


def _nested_groups(mesh: PolygonMesh) -> list[Violation]:
    """Groups of polygons connected through shared vertices, lying inside a polygon of
    another group (their edges do not cross, so one vertex of each group decides)."""
    parent = list(range(len(mesh.vertices)))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for polygon in mesh.polygons:
        root = find(polygon[0])
        for vertex in polygon[1:]:
            other = find(vertex)
            if other != root:
                parent[other] = root
    group_of = [find(polygon[0]) for polygon in mesh.polygons]
    firsts: dict[int, int] = {}
    for polygon, group in zip(mesh.polygons, group_of, strict=True):
        firsts[group] = min(firsts.get(group, polygon[0]), *polygon)
    if len(firsts) < 2:
        return []
    points = mesh.vertices
    found: list[Violation] = []
    for group, vertex in sorted(firsts.items(), key=lambda item: item[1]):
        for index, polygon in enumerate(mesh.polygons):
            if group_of[index] != group and _strictly_inside(points, polygon, points[vertex]):
                found.append(Violation("overlap", f"vertex {vertex} lies inside polygon "
                                       f"#{index} of another group", (vertex, index)))
                break
    return found


def _strictly_inside(points: Sequence[Point2], polygon: Sequence[int], q: Point2) -> bool:
    """Crossing number of a ray from q to the right (exact; q is not on the boundary)."""
    inside = False
    previous = points[polygon[-1]]
    for vertex in polygon:
        point = points[vertex]
        if (point.y > q.y) != (previous.y > q.y):
            # orientation of (lower, upper, q): q left of the upward edge = ray crosses it
            lower, upper = (previous, point) if previous.y < point.y else (point, previous)
            if orient2d(lower, upper, q) == _CCW:
                inside = not inside
        previous = point
    return inside


# -----------------------------------------------------------------------------------------
# statistics
# -----------------------------------------------------------------------------------------
def mesh_stats(mesh: PolygonMesh, *, inserted_edges: int | None = None) -> dict[str, Any]:
    """Statistics of a polygon mesh, JSON-ready: ``polygons``, ``convex``, ``nonconvex``
    (exact orientation tests), ``vertices`` (used by some polygon), ``edges``,
    ``min_polygon_size``, ``max_polygon_size``, ``mean_polygon_size``,
    ``min_angle_deg``/``max_angle_deg`` (interior angles, floats), ``min_area``,
    ``max_area``, ``mean_area`` (nearest doubles of the exact values), ``total_area``
    (exact text) and ``inserted_edges`` (the edges a convex decomposition added, as given
    by the caller, else None).  Entries are None for a mesh without polygons.  O(n)."""
    points = mesh.vertices
    nonconvex = len(nonconvex_polygons(mesh))
    min_angle = max_angle = None
    min_area = max_area = None
    total = ZERO
    sizes = [len(polygon) for polygon in mesh.polygons]
    for polygon in mesh.polygons:
        angles = interior_angles_degrees(points, polygon)
        low, high = min(angles), max(angles)
        min_angle = low if min_angle is None else min(min_angle, low)
        max_angle = high if max_angle is None else max(max_angle, high)
        area = polygon_twice_area(points, polygon) / 2
        total += area
        min_area = area if min_area is None else min(min_area, area)
        max_area = area if max_area is None else max(max_area, area)
    count = len(mesh.polygons)
    return {
        "polygons": count,
        "convex": count - nonconvex,
        "nonconvex": nonconvex,
        "vertices": len({vertex for polygon in mesh.polygons for vertex in polygon}),
        "edges": len(mesh.edges()),
        "min_polygon_size": min(sizes, default=None),
        "max_polygon_size": max(sizes, default=None),
        "mean_polygon_size": sum(sizes) / count if count else None,
        **angle_and_area_report((min_angle, max_angle), min_area, max_area, total, count),
        "inserted_edges": inserted_edges,
    }
