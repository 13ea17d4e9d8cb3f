"""Exact geometry of one mixed cell: its faces' planes, planarity and convexity, the
cell's convexity and volume, and :func:`cell_problems`, the checks every cell of a valid
mixed mesh passes (``specs/mixed.md``, "Cells").  Exact ``orient3d`` and rational
arithmetic only."""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence

from geomexact.errors import Violation
from geomexact.kernel.numbers import ZERO, Rational, sign
from geomexact.kernel.points import Point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.mixed.cells import Cell, Face
from geomexact.mesh3d.snapshot import signed_volume6

__all__ = [
    "Vector",
    "cell_problems",
    "cell_volume",
    "face_corner",
    "face_normal",
    "is_convex_polygon",
    "is_planar_polygon",
]

Vector = tuple[Rational, Rational, Rational]


def _difference(a: Point3, b: Point3) -> Vector:
    return (a.x - b.x, a.y - b.y, a.z - b.z)


def _cross(u: Vector, v: Vector) -> Vector:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _dot(u: Vector, v: Vector) -> Rational:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]  # type: ignore[no-any-return]


def face_corner(points: Sequence[Point3]) -> int | None:
    """The first position i at which the polygon turns (points i - 1, i, i + 1 not
    collinear), or None when all its points are collinear."""
    count = len(points)
    for i in range(count):
        turn = _cross(_difference(points[i], points[i - 1]),
                      _difference(points[(i + 1) % count], points[i]))
        if any(turn):
            return i
    return None


def face_normal(points: Sequence[Point3]) -> Vector | None:
    """The polygon's normal at its first corner, (p_i - p_{i-1}) x (p_{i+1} - p_i): for a
    convex polygon it points to the side from which the cycle turns counter-clockwise
    (outward for a cell's face); None when the points are collinear."""
    corner = face_corner(points)
    if corner is None:
        return None
    count = len(points)
    return _cross(_difference(points[corner], points[corner - 1]),
                  _difference(points[(corner + 1) % count], points[corner]))


def is_planar_polygon(points: Sequence[Point3]) -> bool:
    """True when every point is on the plane of the first corner (exact orient3d = 0);
    collinear points count as planar."""
    corner = face_corner(points)
    if corner is None:
        return True
    a, b, c = points[corner - 1], points[corner], points[(corner + 1) % len(points)]
    return all(orient3d(a, b, c, p) == Orientation.COLLINEAR for p in points)


def is_convex_polygon(points: Sequence[Point3]) -> bool:
    """True when the planar polygon is convex, collinear points on its sides allowed:
    not all collinear, and every point on or left of every side (seen from the side its
    normal points to), so it winds once around a convex region."""
    normal = face_normal(points)
    if normal is None:
        return False
    count = len(points)
    for i in range(count):
        a, b = points[i], points[(i + 1) % count]
        side = _difference(b, a)
        for p in points:
            if sign(_dot(_cross(side, _difference(p, a)), normal)) < 0:
                return False
    return True


def cell_volume(cell: Cell, points: Mapping[int, Point3]) -> Rational:
    """The cell's exact signed volume: the sum, over its faces fanned from their first
    vertex, of the tetrahedra they make with the cell's first vertex (positive for
    outward faces; for a closed surface the result does not depend on the vertex)."""
    apex = points[cell.vertices[0]]
    total = ZERO
    for face in cell.faces:
        first = points[face[0]]
        for i in range(1, len(face) - 1):
            total += signed_volume6(first, points[face[i + 1]], points[face[i]], apex)
    return total / 6  # type: ignore[no-any-return]


def surface_problem(cell: Cell) -> str | None:
    """Why the faces do not bound a closed oriented surface that is a sphere (each
    directed edge once, its reverse once; V - E + F = 2), or None."""
    directed: Counter[tuple[int, int]] = Counter()
    for face in cell.faces:
        for i, vertex in enumerate(face):
            directed[(vertex, face[(i + 1) % len(face)])] += 1
    for (u, v), times in sorted(directed.items()):
        if times != 1 or directed.get((v, u), 0) != 1:
            return (f"its edge ({u}, {v}) is in {times} face(s) that way and "
                    f"{directed.get((v, u), 0)} the other way: its faces do not close")
    edges = len(directed) // 2
    euler = len(cell.vertices) - edges + len(cell.faces)
    if euler != 2:
        return f"its faces make a surface of Euler characteristic {euler}, not a sphere"
    return None


def cell_problems(cell: Cell, points: Mapping[int, Point3], *,
                  geometry: bool = True) -> list[Violation]:
    """The violations of one cell, exact, in this order (each check only when the ones
    before it pass, as it needs them): ``cell-surface`` (faces not a closed oriented
    sphere), ``coincident-vertices`` (two of its vertices at one point),
    ``non-planar-face``, ``non-convex-face`` (collinear, or not convex), then
    ``non-positive-volume`` and ``non-convex-cell`` (a vertex strictly outside a face's
    plane).  Passing all of them makes the cell a convex polyhedron (``specs/mixed.md``).
    Every violation's elements are the cell's vertices.  Without ``geometry``, the first
    two checks only."""
    elements = cell.vertices
    problem = surface_problem(cell)
    if problem is not None:
        return [Violation("cell-surface", f"cell {cell}: {problem}", elements)]
    if len({points[v] for v in cell.vertices}) != len(cell.vertices):
        return [Violation("coincident-vertices", f"cell {cell}: two of its vertices are at "
                          "one point", elements)]
    if not geometry:
        return []
    found = []
    for face in cell.faces:
        corners = [points[v] for v in face]
        if not is_planar_polygon(corners):
            found.append(Violation("non-planar-face", f"cell {cell}: face {face} is not "
                                   "planar (exact orient3d of its vertices)", elements))
        elif not is_convex_polygon(corners):
            found.append(Violation("non-convex-face", f"cell {cell}: face {face} is not a "
                                   "convex polygon", elements))
    if found:
        return found
    volume = cell_volume(cell, points)
    if volume <= 0:
        return [Violation("non-positive-volume", f"cell {cell} has volume {volume}",
                          elements)]
    outside = _vertex_outside(cell, points)
    if outside is not None:
        face, vertex = outside
        return [Violation("non-convex-cell", f"cell {cell}: vertex {vertex} is outside the "
                          f"plane of its face {face}", elements)]
    return []


def _vertex_outside(cell: Cell, points: Mapping[int, Point3]) -> tuple[Face, int] | None:
    """(a face, a vertex strictly on the outer side of its plane), or None (convex)."""
    for face in cell.faces:
        corners = [points[v] for v in face]
        corner = face_corner(corners)
        assert corner is not None, "faces were checked convex"
        a, b, c = corners[corner - 1], corners[corner], corners[(corner + 1) % len(face)]
        for vertex in cell.vertices:
            if orient3d(a, b, c, points[vertex]) == Orientation.COUNTERCLOCKWISE:
                return face, vertex
    return None
