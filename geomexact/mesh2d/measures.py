"""Exact measures of 2D meshes: triangle areas, total area, the area enclosed by the
boundary; and (for reports only) angles in degrees."""

from __future__ import annotations

import math

from geomexact.kernel.numbers import ZERO, Rational, floor_log2, format_rational, mpq, to_float
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


_SMALLEST_NORMAL = 2.0**-1022
_BAND = (2.0**-500, 2.0**500)
"""Arm components whose largest magnitude lies here multiply without overflow or
underflow; outside it an arm is first scaled exactly by a power of two."""


def _direction(dx: Rational, dy: Rational) -> tuple[float, float]:
    """The vector (dx, dy) as doubles, scaled by an exact power of two when its size is
    outside :data:`_BAND` (directions and angles do not change under scaling)."""
    try:
        fx, fy = float(dx), float(dy)
    except OverflowError:
        fx = fy = math.inf
    size = max(abs(fx), abs(fy))
    if _BAND[0] <= size <= _BAND[1] or (dx == 0 and dy == 0):
        return fx, fy
    scale = mpq(2) ** -floor_log2(max(abs(dx), abs(dy)))
    return float(dx * scale), float(dy * scale)


def _arm(p: Point2, q: Point2) -> tuple[float, float]:
    """The vector p -> q as doubles, scaled as :func:`_direction` does."""
    return _direction(q.x - p.x, q.y - p.y)


def atan2_degrees(y: Rational, x: Rational) -> float:
    """``atan2(y, x)`` in degrees, in (-180, 180], of exact y and x at any magnitude
    (floating point, for reports)."""
    fx, fy = _direction(x, y)
    return math.degrees(math.atan2(fy, fx))


def triangle_angles_degrees(a: Point2, b: Point2, c: Point2) -> tuple[float, float, float]:
    """The angles at a, b and c in degrees (floating point, for reports), at any
    magnitude: tiny or huge triangles are scaled exactly before the float arithmetic."""

    def angle(p: Point2, q: Point2, r: Point2) -> float:
        ux, uy = _arm(p, q)
        vx, vy = _arm(p, r)
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
    doubles (None for no cells; the exact text for an area beyond the range of a double
    or below its normal range, never a wrong number), and the exact total area as text."""
    return {
        "min_angle_deg": angles[0],
        "max_angle_deg": angles[1],
        "min_area": None if smallest is None else _reported(smallest),
        "max_area": None if largest is None else _reported(largest),
        "mean_area": _reported(total / count) if count else None,
        "total_area": format_rational(total),
    }


def _reported(value: Rational) -> float | str:
    """The nearest double when it is normal (or ``value`` is 0), else the exact text:
    beyond the doubles, or so small that the double is subnormal or 0 (a wrong number)."""
    try:
        nearest = to_float(value)
    except OverflowError:
        return format_rational(value)
    if value != 0 and abs(nearest) < _SMALLEST_NORMAL:
        return format_rational(value)
    return nearest
