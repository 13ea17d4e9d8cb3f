"""Exact measures of 2D meshes: triangle areas, total area, the area enclosed by the
boundary; and (for reports only) angles in degrees."""

from __future__ import annotations

import math

from geomexact.kernel.numbers import ZERO, Rational, format_rational, to_float
from geomexact.kernel.points import Point2
from geomexact.mesh2d.snapshot import Mesh2, Triangle


def signed_area(a: Point2, b: Point2, c: Point2) -> Rational:
    """Signed area of triangle abc (positive when counter-clockwise), exact."""
    return ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2


def triangle_area(mesh: Mesh2, triangle: Triangle) -> Rational:
    """Exact area of a triangle of ``mesh``."""
    a, b, c = triangle
    return signed_area(mesh.point(a), mesh.point(b), mesh.point(c))


def total_area(mesh: Mesh2) -> Rational:
    """Exact sum of the areas of all triangles.  O(n)."""
    total = ZERO
    for triangle in mesh.iter_triangles():
        total += triangle_area(mesh, triangle)
    return total


def boundary_enclosed_area(mesh: Mesh2) -> Rational:
    """Exact signed area enclosed by the boundary edges (shoelace over every boundary
    half-edge; holes count negatively).  Equals :func:`total_area` for a mesh that does not
    fold over itself."""
    halfedges, vertices = mesh.halfedges, mesh.vertices
    twice = ZERO
    for key in halfedges:
        u, v = key
        if (v, u) not in halfedges:
            p, q = vertices[u], vertices[v]
            twice += p.x * q.y - q.x * p.y
    return twice / 2


def triangle_angles_degrees(a: Point2, b: Point2, c: Point2) -> tuple[float, float, float]:
    """The angles at a, b and c in degrees (floating point, for reports)."""

    def angle(p: Point2, q: Point2, r: Point2) -> float:
        ux, uy = float(q.x - p.x), float(q.y - p.y)
        vx, vy = float(r.x - p.x), float(r.y - p.y)
        return math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))

    return angle(a, b, c), angle(b, c, a), angle(c, a, b)


def angle_and_area_report(
    angles: tuple[float | None, float | None],
    smallest: Rational | None,
    largest: Rational | None,
    total: Rational,
    count: int,
) -> dict[str, object]:
    """The angle and area entries of a mesh report (``info``, the summaries): the smallest
    and largest angle in degrees, the smallest, largest and mean cell area as the nearest
    doubles (None for no cells), and the exact total area as text."""
    return {
        "min_angle_deg": angles[0],
        "max_angle_deg": angles[1],
        "min_area": None if smallest is None else to_float(smallest),
        "max_area": None if largest is None else to_float(largest),
        "mean_area": to_float(total / count) if count else None,
        "total_area": format_rational(total),
    }
