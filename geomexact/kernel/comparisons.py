"""Exact comparisons of squared lengths (2D and 3D) and of triangle areas (2D): a
certified float filter, else exact.

The same scheme as :mod:`~geomexact.kernel.predicates2d` (constants in
:mod:`~geomexact.kernel.filter_bounds`, derivation in ``specs/predicates.md``); the
answer is always the exact one.
"""

from __future__ import annotations

from typing import Final

from geomexact.kernel.filter_bounds import AREAS_COUNTS as _AREA
from geomexact.kernel.filter_bounds import LENGTHS_C, LENGTHS_K, SUM_MARGIN
from geomexact.kernel.filter_bounds import LENGTHS_COUNTS as _LEN
from geomexact.kernel.numbers import Rational, sign
from geomexact.kernel.points import Point2, PointT
from geomexact.kernel.predicate_results import COMPARISONS, Comparison
from geomexact.kernel.predicates2d import _orient2d_float

__all__ = ["compare_areas", "compare_squared_lengths"]

_LESS: Final = Comparison.LESS
_GREATER: Final = Comparison.GREATER


def _squared_length_exact(p: PointT, q: PointT) -> Rational:
    dx = q[0] - p[0]
    dy = q[1] - p[1]
    if len(p) == 4:
        return dx * dx + dy * dy
    dz = q[2] - p[2]
    return dx * dx + dy * dy + dz * dz


def compare_squared_lengths(a: PointT, b: PointT, c: PointT, d: PointT) -> Comparison:
    """Compare ``|ab|^2`` with ``|cd|^2`` (points all 2D or all 3D).

    GREATER when segment ab is longer than cd, EQUAL when they have the same length.
    Exact; float filter first.
    """
    if len(a) == 4:
        ux = b[2] - a[2]
        uy = b[3] - a[3]
        vx = d[2] - c[2]
        vy = d[3] - c[3]
        diff = (ux * ux + uy * uy) - (vx * vx + vy * vy)
        t = abs(ux) + abs(uy) + abs(vx) + abs(vy) + LENGTHS_K
        m = abs(a[2]) + abs(a[3]) + abs(c[2]) + abs(c[3])
    else:
        ux = b[3] - a[3]
        uy = b[4] - a[4]
        uz = b[5] - a[5]
        vx = d[3] - c[3]
        vy = d[4] - c[4]
        vz = d[5] - c[5]
        diff = (ux * ux + uy * uy + uz * uz) - (vx * vx + vy * vy + vz * vz)
        t = abs(ux) + abs(uy) + abs(uz) + abs(vx) + abs(vy) + abs(vz) + LENGTHS_K
        m = abs(a[3]) + abs(a[4]) + abs(a[5]) + abs(c[3]) + abs(c[4]) + abs(c[5])
    # 2t (exact doubling): the squared lengths reach T^2, so B must overflow with them
    bound = t * (m + (t + t)) * LENGTHS_C
    if diff > bound or -diff > bound:
        _LEN[0] += 1
        return _GREATER if diff > 0.0 else _LESS
    _LEN[1] += 1
    return COMPARISONS[sign(_squared_length_exact(a, b) - _squared_length_exact(c, d))]


def _doubled_area_exact(a: Point2, b: Point2, c: Point2) -> Rational:
    cx = c[0]
    cy = c[1]
    det = (a[0] - cx) * (b[1] - cy) - (a[1] - cy) * (b[0] - cx)
    return abs(det)


def compare_areas(a: Point2, b: Point2, c: Point2, d: Point2, e: Point2, f: Point2) -> Comparison:
    """Compare the (unsigned) area of triangle abc with that of triangle def.

    Degenerate triangles have area zero.  Exact; float filter first.
    """
    det1, bound1 = _orient2d_float(a, b, c)
    det2, bound2 = _orient2d_float(d, e, f)
    area1 = abs(det1)
    area2 = abs(det2)
    # Each |det| is certified only when it exceeds its own bound (see the spec).
    if area1 > bound1 and area2 > bound2:
        diff = area1 - area2
        bound = (bound1 + bound2) * SUM_MARGIN
        if diff > bound or -diff > bound:
            _AREA[0] += 1
            return _GREATER if diff > 0.0 else _LESS
    _AREA[1] += 1
    return COMPARISONS[sign(_doubled_area_exact(a, b, c) - _doubled_area_exact(d, e, f))]
