"""The plane predicates orient2d and incircle: a certified float filter, else exact.

Each predicate first evaluates its determinant in double precision from the cached floats
of the points (``fx, fy``, each the correctly rounded value of the exact rational
coordinate, or ``nan`` beyond the double range) together with an error bound that is
*certified* for such inputs (the constants are in :mod:`~geomexact.kernel.filter_bounds`,
the derivation in ``specs/predicates.md``).  When the float determinant is farther from
zero than the bound, its sign is the exact sign; otherwise (including ``nan``/``inf``
anywhere, and magnitudes so small that underflow could matter) the predicate recomputes
the determinant exactly with gmpy2 rationals.  The answer is therefore always the exact
one; the filter only makes it fast.

Sign conventions (see ``specs/predicates.md``):

* ``orient2d(a, b, c)`` is the sign of ``det[b - a, c - a]``: counterclockwise is positive.
* ``incircle(a, b, c, d)`` is positive (INSIDE) when ``d`` is strictly inside the circle
  through ``a, b, c`` *and a, b, c are counterclockwise*; the sign flips when they are
  clockwise.  Same as Shewchuk's ``incircle``.

References: J. R. Shewchuk, *Adaptive Precision Floating-Point Arithmetic and Fast Robust
Geometric Predicates*, Discrete Comput. Geom. 18 (1997) 305-363.
"""

from __future__ import annotations

from typing import Any, Final

from geomexact.kernel.filter_bounds import INCIRCLE_C, INCIRCLE_K, ORIENT2D_C, ORIENT2D_K
from geomexact.kernel.filter_bounds import INCIRCLE_COUNTS as _ICC
from geomexact.kernel.filter_bounds import ORIENT2D_COUNTS as _O2D
from geomexact.kernel.numbers import scaled_to_integers, sign
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import (
    CIRCLE_LOCATIONS,
    ORIENTATIONS,
    CircleLocation,
    Orientation,
)

__all__ = ["incircle", "incircle_exact", "orient2d", "orient2d_exact"]

_CCW: Final = Orientation.COUNTERCLOCKWISE
_CW: Final = Orientation.CLOCKWISE
_INSIDE: Final = CircleLocation.INSIDE
_OUTSIDE: Final = CircleLocation.OUTSIDE


def orient2d_exact(a: Point2, b: Point2, c: Point2) -> Orientation:
    """:func:`orient2d` computed with exact rational arithmetic only."""
    cx = c[0]
    cy = c[1]
    det = (a[0] - cx) * (b[1] - cy) - (a[1] - cy) * (b[0] - cx)
    return ORIENTATIONS[sign(det)]


def _incircle_determinant(adx: Any, ady: Any, bdx: Any, bdy: Any, cdx: Any, cdy: Any) -> Any:
    """The incircle determinant of the differences ``a - d``, ``b - d``, ``c - d`` in their
    own arithmetic: exact on integers, and on floats or numpy arrays (``array_filters``)
    the same operations in the same order as the fast path of :func:`incircle`."""
    return (
        (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
        + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady)
    )


def incircle_exact(a: Point2, b: Point2, c: Point2, d: Point2) -> CircleLocation:
    """:func:`incircle` computed with exact rational arithmetic only."""
    ax, ay, bx, by, cx, cy, dx, dy = scaled_to_integers((a[0], a[1], b[0], b[1],
                                                          c[0], c[1], d[0], d[1]))
    det = _incircle_determinant(ax - dx, ay - dy, bx - dx, by - dy, cx - dx, cy - dy)
    return CIRCLE_LOCATIONS[sign(det)]


# The fast path is written out in full in each function (no helper calls, tuple indexing,
# locals) because these run millions of times: calling _incircle_determinant from incircle
# costs about 4%, a shared "certified sign" ending about 7% (measured).  Each ends the same
# way, Shewchuk's: the float value is certified when it is farther from zero than the
# bound, then its sign is the answer (one hit counted); otherwise one miss is counted and
# the exact version runs.


def _orient2d_float(a: Point2, b: Point2, c: Point2) -> tuple[float, float]:
    """orient2d's float determinant of abc and its certified bound (decided when
    ``abs(det) > bound``), for the filters built on it (``comparisons.compare_areas``).
    :func:`orient2d` computes the same, written out."""
    cx = c[2]
    cy = c[3]
    acx = a[2] - cx
    acy = a[3] - cy
    bcx = b[2] - cx
    bcy = b[3] - cy
    det = acx * bcy - acy * bcx
    t = abs(acx) + abs(acy) + abs(bcx) + abs(bcy) + ORIENT2D_K
    return det, t * (abs(cx) + abs(cy) + t) * ORIENT2D_C


def orient2d(a: Point2, b: Point2, c: Point2) -> Orientation:
    """Orientation of the triangle abc: the sign of ``det[b - a, c - a]``.

    COUNTERCLOCKWISE when a, b, c turn left, CLOCKWISE when they turn right, COLLINEAR
    when they lie on a line (including repeated points).  Exact; float filter first.
    """
    cx = c[2]
    cy = c[3]
    acx = a[2] - cx
    acy = a[3] - cy
    bcx = b[2] - cx
    bcy = b[3] - cy
    left = acx * bcy
    right = acy * bcx
    # Sign shortcut: rounding to nearest is monotonic, so a nonzero float difference has the
    # sign of the exact difference, and a nonzero float product the sign of the exact one;
    # products of opposite strict signs therefore fix the sign of the exact determinant.
    if left > 0.0:
        if right < 0.0:
            _O2D[0] += 1
            return _CCW
    elif left < 0.0 and right > 0.0:
        _O2D[0] += 1
        return _CW
    det = left - right
    t = abs(acx) + abs(acy) + abs(bcx) + abs(bcy) + ORIENT2D_K
    bound = t * (abs(cx) + abs(cy) + t) * ORIENT2D_C
    if det > bound or -det > bound:
        _O2D[0] += 1
        return _CCW if det > 0.0 else _CW
    _O2D[1] += 1
    return orient2d_exact(a, b, c)


def incircle(a: Point2, b: Point2, c: Point2, d: Point2) -> CircleLocation:
    """Where ``d`` lies with respect to the circle through a, b, c.

    INSIDE (positive determinant) when d is strictly inside and a, b, c are
    counterclockwise; COCIRCULAR when the four points are on one circle or line (or a,b,c
    are collinear and d on their line); the answer flips (INSIDE <-> OUTSIDE) when a, b, c
    are clockwise.  If a, b, c are collinear the "circle" is their line and the result is
    the side of d.  Exact; float filter first.
    """
    dx = d[2]
    dy = d[3]
    adx = a[2] - dx
    ady = a[3] - dy
    bdx = b[2] - dx
    bdy = b[3] - dy
    cdx = c[2] - dx
    cdy = c[3] - dy
    det = (
        (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
        + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady)
    )
    t = abs(adx) + abs(ady) + abs(bdx) + abs(bdy) + abs(cdx) + abs(cdy) + INCIRCLE_K
    bound = t * t * t * (abs(dx) + abs(dy) + t) * INCIRCLE_C
    if det > bound or -det > bound:
        _ICC[0] += 1
        return _INSIDE if det > 0.0 else _OUTSIDE
    _ICC[1] += 1
    return incircle_exact(a, b, c, d)
