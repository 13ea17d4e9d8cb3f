"""The attributes of a new vertex: the exact linear interpolation of the vertex
attributes over the edge or triangle that contains it, as Triangle interpolates them.

A mesh without vertex attributes gives a new vertex none; so does a simplex whose corners
do not all carry attributes of one length (a mesh read from a file has all or none).
"""

from __future__ import annotations

from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.snapshot import Attributes

__all__ = ["interpolated_in_quadrilateral", "interpolated_in_triangle", "interpolated_on_edge"]


def _uniform(*rows: Attributes) -> bool:
    return bool(rows[0]) and all(len(row) == len(rows[0]) for row in rows)


def interpolated_on_edge(
    pu: Point2, au: Attributes, pv: Point2, av: Attributes, point: Point2
) -> Attributes:
    """The attributes at ``point`` on the segment from ``pu`` (attributes ``au``) to
    ``pv`` (``av``): ``au + s (av - au)`` with ``point = pu + s (pv - pu)``; the exact
    average at the midpoint."""
    if not _uniform(au, av):
        return ()
    dx = pv.x - pu.x
    s: Rational = (point.x - pu.x) / dx if dx != 0 else (point.y - pu.y) / (pv.y - pu.y)
    return tuple(a + s * (b - a) for a, b in zip(au, av, strict=True))


def _doubled_area(p: Point2, q: Point2, r: Point2) -> Rational:
    return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)  # type: ignore[no-any-return]


def interpolated_in_triangle(
    corners: tuple[tuple[Point2, Attributes], tuple[Point2, Attributes],
                   tuple[Point2, Attributes]],
    point: Point2,
) -> Attributes:
    """The attributes at ``point`` (inside or on the triangle of the three ``corners``,
    each a (point, attributes) pair): the barycentric combination of the corners'
    attributes, exactly."""
    (pa, aa), (pb, ab), (pc, ac) = corners
    if not _uniform(aa, ab, ac):
        return ()
    twice = _doubled_area(pa, pb, pc)
    la = _doubled_area(point, pb, pc) / twice
    lb = _doubled_area(pa, point, pc) / twice
    lc = 1 - la - lb
    return tuple(
        la * a + lb * b + lc * c for a, b, c in zip(aa, ab, ac, strict=True)
    )


def interpolated_in_quadrilateral(
    corners: tuple[tuple[Point2, Attributes], tuple[Point2, Attributes],
                   tuple[Point2, Attributes], tuple[Point2, Attributes]],
    point: Point2,
) -> Attributes:
    """The attributes at ``point`` inside the quadrilateral of the edge uv with its two
    triangles uvw and vux, ``corners`` being (u, v, w, x) with their attributes:
    interpolated in the triangle of the two that holds the point (either one on uv)."""
    (pu, au), (pv, av), (pw, aw), (px, ax) = corners
    if not _uniform(au, av, aw, ax):
        return ()
    if orient2d(pu, pv, point) != Orientation.CLOCKWISE:
        return interpolated_in_triangle(((pu, au), (pv, av), (pw, aw)), point)
    return interpolated_in_triangle(((pv, av), (pu, au), (px, ax)), point)
