"""Exact geometric predicates with a certified floating-point filter.

Every predicate first evaluates its determinant in double precision from the cached
floats of the points (``fx, fy(, fz)``, each the correctly rounded value of the exact
rational coordinate, or ``nan`` beyond the double range) together with an error bound
that is *certified* for such inputs (the derivation is in ``specs/predicates.md``).  When
the float determinant is farther from zero than the bound, its sign is the exact sign;
otherwise (including ``nan``/``inf`` anywhere, and magnitudes so small that underflow
could matter) the predicate recomputes the determinant exactly with gmpy2 rationals.  The
answer is therefore always the exact one; the filter only makes it fast.

Sign conventions (see ``specs/predicates.md``):

* ``orient2d(a, b, c)`` is the sign of ``det[b - a, c - a]``: counterclockwise is positive.
* ``incircle(a, b, c, d)`` is positive (INSIDE) when ``d`` is strictly inside the circle
  through ``a, b, c`` *and a, b, c are counterclockwise*; the sign flips when they are
  clockwise.  Same as Shewchuk's ``incircle``.
* ``orient3d(a, b, c, d)`` is the sign of ``det[b - a, c - a, d - a]``: positive when ``d``
  is on the side of plane abc from which a, b, c appear counterclockwise.  This is the
  *opposite* of Shewchuk's ``orient3d``.
* ``insphere(a, b, c, d, e)`` is positive (INSIDE) when ``e`` is strictly inside the sphere
  through ``a, b, c, d`` *and* ``orient3d(a, b, c, d)`` is positive; the sign flips
  otherwise.  This is the opposite of Shewchuk's ``insphere`` (whose orientation
  convention is the opposite one).

References: J. R. Shewchuk, *Adaptive Precision Floating-Point Arithmetic and Fast Robust
Geometric Predicates*, Discrete Comput. Geom. 18 (1997) 305-363.
"""

from __future__ import annotations

import math
from enum import IntEnum
from fractions import Fraction
from typing import Any, Final, TypeVar

import attrs
import gmpy2

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq, to_rational
from geomexact.kernel.points import Point2, Point3

PointT = TypeVar("PointT", Point2, Point3)

__all__ = [
    "AngleThreshold",
    "CircleLocation",
    "Comparison",
    "Orientation",
    "SphereLocation",
    "angle_degrees",
    "compare_angle",
    "compare_areas",
    "compare_squared_lengths",
    "filter_counters",
    "incircle",
    "incircle_exact",
    "insphere",
    "insphere_exact",
    "orient2d",
    "orient2d_exact",
    "orient3d",
    "orient3d_exact",
    "reset_filter_counters",
]


class Orientation(IntEnum):
    """Sign of an orientation determinant."""

    CLOCKWISE = -1
    COLLINEAR = 0
    COUNTERCLOCKWISE = 1


class CircleLocation(IntEnum):
    """Where a point lies with respect to a circle (for a counterclockwise triangle)."""

    OUTSIDE = -1
    COCIRCULAR = 0
    INSIDE = 1


class SphereLocation(IntEnum):
    """Where a point lies with respect to a sphere (for a positive tetrahedron)."""

    OUTSIDE = -1
    COSPHERICAL = 0
    INSIDE = 1


class Comparison(IntEnum):
    """Result of comparing a first quantity with a second one."""

    LESS = -1
    EQUAL = 0
    GREATER = 1


# Members indexed by a sign in {-1, 0, 1} (index -1 is the last item).
_ORIENTATIONS: Final = (
    Orientation.COLLINEAR,
    Orientation.COUNTERCLOCKWISE,
    Orientation.CLOCKWISE,
)
_CIRCLE: Final = (CircleLocation.COCIRCULAR, CircleLocation.INSIDE, CircleLocation.OUTSIDE)
_SPHERE: Final = (SphereLocation.COSPHERICAL, SphereLocation.INSIDE, SphereLocation.OUTSIDE)
_COMPARISONS: Final = (Comparison.EQUAL, Comparison.GREATER, Comparison.LESS)

_CCW: Final = Orientation.COUNTERCLOCKWISE
_CW: Final = Orientation.CLOCKWISE
_INSIDE: Final = CircleLocation.INSIDE
_OUTSIDE: Final = CircleLocation.OUTSIDE
_SPH_INSIDE: Final = SphereLocation.INSIDE
_SPH_OUTSIDE: Final = SphereLocation.OUTSIDE
_LESS: Final = Comparison.LESS
_EQUAL: Final = Comparison.EQUAL
_GREATER: Final = Comparison.GREATER

# ---------------------------------------------------------------------------------------
# Filter constants.  u = 2^-53 is the unit roundoff.  For a predicate of degree k in the
# coordinate differences, with t = sum of |computed differences| + K and m = sum of
# |pivot coordinates| (floats), the filter accepts the float determinant when
#     |det| > t^(k-1) * (m + t) * C        (evaluated left to right in floats).
# C covers the rounding of the inputs (each float is only the nearest double of its
# rational), of the differences, products and sums; K >= 2^(-950/k) keeps every product
# in the bound normal so that underflow is covered.  The derivation, and the minimal C
# each value was rounded up from, are in specs/predicates.md; tests/kernel/test_predicates.py
# recomputes the requirements with exact rationals.
# ---------------------------------------------------------------------------------------
_U: Final = 2.0**-53
ORIENT2D_C: Final = 3.0 * _U  # derived minimum 2.733 u
ORIENT2D_K: Final = 2.0**-475
ORIENT3D_C: Final = 1.125 * _U  # derived minimum 1.021 u
ORIENT3D_K: Final = 2.0**-316
INCIRCLE_C: Final = 2.0 * _U  # derived minimum 1.824 u
INCIRCLE_K: Final = 2.0**-237
INSPHERE_C: Final = 0.4375 * _U  # derived minimum 0.391 u
INSPHERE_K: Final = 2.0**-190
LENGTHS_C: Final = 9.0 * _U  # derived minimum 8.001 u (2D and 3D)
LENGTHS_K: Final = 2.0**-475
DOT_C: Final = 3.25 * _U  # derived minimum 3.001 u (2D and 3D)
DOT_K: Final = 2.0**-475
ANGLE_C: Final = 5.5 * _U  # derived minimum 5.161 u (cos^2 * |u|^2 |v|^2 - (u.v)^2)
ANGLE_K: Final = 2.0**-237
# |a| - |b| is compared with the sum of two certified bounds; this factor covers the
# rounding of that sum (and of the subtraction it is compared with).
_SUM_MARGIN: Final = 1.0 + 2.0**-50

# Filter hit/miss counters: one two-item list per predicate, [hits, misses].
_O2D: Final = [0, 0]
_O3D: Final = [0, 0]
_ICC: Final = [0, 0]
_ISP: Final = [0, 0]
_LEN: Final = [0, 0]
_AREA: Final = [0, 0]
_ANG: Final = [0, 0]
_COUNTERS: Final = {
    "orient2d": _O2D,
    "orient3d": _O3D,
    "incircle": _ICC,
    "insphere": _ISP,
    "compare_squared_lengths": _LEN,
    "compare_areas": _AREA,
    "compare_angle": _ANG,
}


def filter_counters() -> dict[str, tuple[int, int]]:
    """``{predicate name: (filter successes, exact fallbacks)}`` since the last reset."""
    return {name: (counts[0], counts[1]) for name, counts in _COUNTERS.items()}


def reset_filter_counters() -> None:
    """Set every filter counter back to zero."""
    for counts in _COUNTERS.values():
        counts[0] = 0
        counts[1] = 0


# ---------------------------------------------------------------------------------------
# Exact versions (gmpy2 mpq arithmetic on the exact coordinates).
# ---------------------------------------------------------------------------------------


def _sign(value: Rational) -> int:
    return (value > 0) - (value < 0)  # type: ignore[no-any-return]


def _integer_coordinates(
    points: tuple[Point2, ...] | tuple[Point3, ...], dimension: int
) -> list[Any]:
    """The exact coordinates (flattened) times the lcm of their denominators: integers on
    which a homogeneous predicate has the same sign.  Much faster than mpq arithmetic (no
    gcd per operation) when denominators are unrelated (random or centroid coordinates)."""
    values: list[Rational] = [point[i] for point in points for i in range(dimension)]
    scale = 1
    for value in values:
        denominator = value.denominator
        if denominator != 1:
            scale = gmpy2.lcm(scale, denominator)
    return [value.numerator * (scale // value.denominator) for value in values]


def orient2d_exact(a: Point2, b: Point2, c: Point2) -> Orientation:
    """:func:`orient2d` computed with exact rational arithmetic only."""
    cx = c[0]
    cy = c[1]
    det = (a[0] - cx) * (b[1] - cy) - (a[1] - cy) * (b[0] - cx)
    return _ORIENTATIONS[_sign(det)]


def incircle_exact(a: Point2, b: Point2, c: Point2, d: Point2) -> CircleLocation:
    """:func:`incircle` computed with exact rational arithmetic only."""
    ax, ay, bx, by, cx, cy, dx, dy = _integer_coordinates((a, b, c, d), 2)
    adx = ax - dx
    ady = ay - dy
    bdx = bx - dx
    bdy = by - dy
    cdx = cx - dx
    cdy = cy - dy
    det = (
        (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
        + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady)
    )
    return _CIRCLE[_sign(det)]


def orient3d_exact(a: Point3, b: Point3, c: Point3, d: Point3) -> Orientation:
    """:func:`orient3d` computed with exact rational arithmetic only."""
    dx = d[0]
    dy = d[1]
    dz = d[2]
    adx = a[0] - dx
    ady = a[1] - dy
    adz = a[2] - dz
    bdx = b[0] - dx
    bdy = b[1] - dy
    bdz = b[2] - dz
    cdx = c[0] - dx
    cdy = c[1] - dy
    cdz = c[2] - dz
    det = (
        adz * (cdx * bdy - bdx * cdy)
        + bdz * (adx * cdy - cdx * ady)
        + cdz * (bdx * ady - adx * bdy)
    )
    return _ORIENTATIONS[_sign(det)]


def insphere_exact(a: Point3, b: Point3, c: Point3, d: Point3, e: Point3) -> SphereLocation:
    """:func:`insphere` computed with exact rational arithmetic only."""
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez = _integer_coordinates(
        (a, b, c, d, e), 3
    )
    aex = ax - ex
    aey = ay - ey
    aez = az - ez
    bex = bx - ex
    bey = by - ey
    bez = bz - ez
    cex = cx - ex
    cey = cy - ey
    cez = cz - ez
    dex = dx - ex
    dey = dy - ey
    dez = dz - ez
    ab = aex * bey - bex * aey
    bc = bex * cey - cex * bey
    cd = cex * dey - dex * cey
    da = dex * aey - aex * dey
    ac = aex * cey - cex * aey
    bd = bex * dey - dex * bey
    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da
    alift = aex * aex + aey * aey + aez * aez
    blift = bex * bex + bey * bey + bez * bez
    clift = cex * cex + cey * cey + cez * cez
    dlift = dex * dex + dey * dey + dez * dez
    det = (clift * dab - dlift * abc) + (alift * bcd - blift * cda)
    return _SPHERE[_sign(det)]


# ---------------------------------------------------------------------------------------
# Adaptive versions.  The fast path is written out in full in each function (no helper
# calls, tuple indexing, locals) because these run millions of times.
# ---------------------------------------------------------------------------------------


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
    if det > bound:
        _O2D[0] += 1
        return _CCW
    if -det > bound:
        _O2D[0] += 1
        return _CW
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
    if det > bound:
        _ICC[0] += 1
        return _INSIDE
    if -det > bound:
        _ICC[0] += 1
        return _OUTSIDE
    _ICC[1] += 1
    return incircle_exact(a, b, c, d)


def orient3d(a: Point3, b: Point3, c: Point3, d: Point3) -> Orientation:
    """Orientation of the tetrahedron abcd: the sign of ``det[b - a, c - a, d - a]``.

    COUNTERCLOCKWISE (positive) when d lies on the side of plane abc from which a, b, c
    are seen counterclockwise (the right-hand rule: (b - a) x (c - a) points towards d);
    COLLINEAR when the four points are coplanar.  Opposite sign to Shewchuk's orient3d.
    Exact; float filter first.
    """
    dx = d[3]
    dy = d[4]
    dz = d[5]
    adx = a[3] - dx
    ady = a[4] - dy
    adz = a[5] - dz
    bdx = b[3] - dx
    bdy = b[4] - dy
    bdz = b[5] - dz
    cdx = c[3] - dx
    cdy = c[4] - dy
    cdz = c[5] - dz
    det = (
        adz * (cdx * bdy - bdx * cdy)
        + bdz * (adx * cdy - cdx * ady)
        + cdz * (bdx * ady - adx * bdy)
    )
    t = (
        abs(adx) + abs(ady) + abs(adz) + abs(bdx) + abs(bdy) + abs(bdz)
        + abs(cdx) + abs(cdy) + abs(cdz) + ORIENT3D_K
    )  # fmt: skip
    bound = t * t * (abs(dx) + abs(dy) + abs(dz) + t) * ORIENT3D_C
    if det > bound:
        _O3D[0] += 1
        return _CCW
    if -det > bound:
        _O3D[0] += 1
        return _CW
    _O3D[1] += 1
    return orient3d_exact(a, b, c, d)


def insphere(a: Point3, b: Point3, c: Point3, d: Point3, e: Point3) -> SphereLocation:
    """Where ``e`` lies with respect to the sphere through a, b, c, d.

    INSIDE (positive) when e is strictly inside and ``orient3d(a, b, c, d)`` is
    COUNTERCLOCKWISE; COSPHERICAL when the five points are on one sphere (or plane); the
    answer flips when the tetrahedron abcd is negatively oriented.  Opposite sign to
    Shewchuk's insphere.  Exact; float filter first.
    """
    ex = e[3]
    ey = e[4]
    ez = e[5]
    aex = a[3] - ex
    aey = a[4] - ey
    aez = a[5] - ez
    bex = b[3] - ex
    bey = b[4] - ey
    bez = b[5] - ez
    cex = c[3] - ex
    cey = c[4] - ey
    cez = c[5] - ez
    dex = d[3] - ex
    dey = d[4] - ey
    dez = d[5] - ez
    ab = aex * bey - bex * aey
    bc = bex * cey - cex * bey
    cd = cex * dey - dex * cey
    da = dex * aey - aex * dey
    ac = aex * cey - cex * aey
    bd = bex * dey - dex * bey
    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da
    det = (
        (cex * cex + cey * cey + cez * cez) * dab - (dex * dex + dey * dey + dez * dez) * abc
    ) + ((aex * aex + aey * aey + aez * aez) * bcd - (bex * bex + bey * bey + bez * bez) * cda)
    t = (
        abs(aex) + abs(aey) + abs(aez) + abs(bex) + abs(bey) + abs(bez)
        + abs(cex) + abs(cey) + abs(cez) + abs(dex) + abs(dey) + abs(dez) + INSPHERE_K
    )  # fmt: skip
    t2 = t * t
    bound = t2 * t2 * (abs(ex) + abs(ey) + abs(ez) + t) * INSPHERE_C
    if det > bound:
        _ISP[0] += 1
        return _SPH_INSIDE
    if -det > bound:
        _ISP[0] += 1
        return _SPH_OUTSIDE
    _ISP[1] += 1
    return insphere_exact(a, b, c, d, e)


# ---------------------------------------------------------------------------------------
# Comparisons.
# ---------------------------------------------------------------------------------------


def _squared_length_exact(p: PointT, q: PointT) -> Rational:
    if len(p) == 4:
        dx = q[0] - p[0]
        dy = q[1] - p[1]
        return dx * dx + dy * dy
    dx = q[0] - p[0]
    dy = q[1] - p[1]
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
    if diff > bound:
        _LEN[0] += 1
        return _GREATER
    if -diff > bound:
        _LEN[0] += 1
        return _LESS
    _LEN[1] += 1
    return _COMPARISONS[_sign(_squared_length_exact(a, b) - _squared_length_exact(c, d))]


def _doubled_area_exact(a: Point2, b: Point2, c: Point2) -> Rational:
    cx = c[0]
    cy = c[1]
    det = (a[0] - cx) * (b[1] - cy) - (a[1] - cy) * (b[0] - cx)
    return abs(det)


def compare_areas(a: Point2, b: Point2, c: Point2, d: Point2, e: Point2, f: Point2) -> Comparison:
    """Compare the (unsigned) area of triangle abc with that of triangle def.

    Degenerate triangles have area zero.  Exact; float filter first.
    """
    cx = c[2]
    cy = c[3]
    acx = a[2] - cx
    acy = a[3] - cy
    bcx = b[2] - cx
    bcy = b[3] - cy
    det1 = acx * bcy - acy * bcx
    t = abs(acx) + abs(acy) + abs(bcx) + abs(bcy) + ORIENT2D_K
    bound1 = t * (abs(cx) + abs(cy) + t) * ORIENT2D_C
    fx = f[2]
    fy = f[3]
    dfx = d[2] - fx
    dfy = d[3] - fy
    efx = e[2] - fx
    efy = e[3] - fy
    det2 = dfx * efy - dfy * efx
    t = abs(dfx) + abs(dfy) + abs(efx) + abs(efy) + ORIENT2D_K
    bound2 = t * (abs(fx) + abs(fy) + t) * ORIENT2D_C
    area1 = abs(det1)
    area2 = abs(det2)
    # Each |det| is certified only when it exceeds its own bound (see the spec).
    if area1 > bound1 and area2 > bound2:
        diff = area1 - area2
        bound = (bound1 + bound2) * _SUM_MARGIN
        if diff > bound:
            _AREA[0] += 1
            return _GREATER
        if -diff > bound:
            _AREA[0] += 1
            return _LESS
    _AREA[1] += 1
    return _COMPARISONS[_sign(_doubled_area_exact(a, b, c) - _doubled_area_exact(d, e, f))]


# ---------------------------------------------------------------------------------------
# Angles.
# ---------------------------------------------------------------------------------------

_EXACT_COS2_BITS: Final = 64
_SMALLEST_NORMAL: Final = 2.0**-1022  # relative accuracy 2^-64 of an inexact threshold's cos^2


def _cos2_exact(degrees: Rational) -> Rational | None:
    """cos^2 of ``degrees`` when it is rational (sympy), else None.

    cos^2(theta) = (1 + cos 2theta)/2, and by Niven's theorem the cosine of a rational
    number of degrees is rational only when it is 0, +-1/2 or +-1: in (0, 180) that is
    theta in {30, 45, 60, 90, 120, 135, 150}.  sympy evaluates exactly these cases to
    rationals and leaves the others symbolic.
    """
    import sympy  # type: ignore[import-untyped]

    turn = sympy.Rational(int(degrees.numerator), int(degrees.denominator)) / 180
    value = sympy.cos(sympy.pi * turn) ** 2
    if value.is_Rational:
        return mpq(int(value.p), int(value.q))
    return None


def _cos2_safe(degrees: Rational, cos_sign: int) -> Rational:
    """A rational within 2^-64 (relative) of cos^2(degrees), rounded to the safe side.

    Safe side: the effective threshold angle is >= the requested one, i.e. cos^2 rounded
    down for acute thresholds and up for obtuse ones.  Computed with mpmath interval
    arithmetic, so the direction is certified.
    """
    from mpmath import iv  # type: ignore[import-untyped]
    from mpmath.libmp import to_rational as mpf_to_rational  # type: ignore[import-untyped]

    numerator, denominator = int(degrees.numerator), int(degrees.denominator)
    precision = 160
    while True:
        saved = iv.prec  # mpmath's interval context is global: restore it afterwards
        try:
            iv.prec = precision
            cos_double = iv.cos(iv.pi * iv.mpf(numerator) / iv.mpf(denominator * 90))
            interval = (1 + cos_double) / 2
        finally:
            iv.prec = saved
        low = Fraction(*mpf_to_rational(interval._mpi_[0]))
        high = Fraction(*mpf_to_rational(interval._mpi_[1]))
        if low > 0:
            # bits: relative error 2^-64 needs 64 bits below the leading bit of low
            leading = low.numerator.bit_length() - low.denominator.bit_length()
            bits = _EXACT_COS2_BITS + 2 - leading
            scale = Fraction(2) ** bits
            if (high - low) * scale < Fraction(1, 4):
                if cos_sign > 0:
                    rounded = Fraction(math.floor(low * scale)) / scale
                else:
                    rounded = min(Fraction(math.ceil(high * scale)) / scale, Fraction(1))
                return mpq(rounded.numerator, rounded.denominator)
        precision *= 2


@attrs.frozen(slots=True)
class AngleThreshold:
    """An angle θ in (0°, 180°) prepared for exact comparisons; build with :meth:`from_degrees`.

    ``cos2`` is cos²θ as a rational and ``cos_sign`` the sign of cos θ.  When cos²θ is
    rational (θ in {30, 45, 60, 90, 120, 135, 150} degrees) ``exact`` is True and
    comparisons are against θ itself.  Otherwise ``cos2`` is cos²θ' for an angle θ' >= θ
    within 2^-64 relative in cos², so :func:`compare_angle` never reports an angle below
    θ as GREATER or EQUAL (it may report an angle in [θ, θ') as LESS).  ``cos2_float`` is
    the nearest double of ``cos2``, used by the float filter.
    """

    degrees: Rational
    cos2: Rational
    cos_sign: int
    exact: bool
    cos2_float: float = attrs.field(eq=False)  # derived from cos2 (may be nan)

    @classmethod
    def from_degrees(cls, degrees: object) -> AngleThreshold:
        """The threshold of ``degrees`` (int, str, rational or float, read exactly)."""
        value = to_rational(degrees)
        if not 0 < value < 180:
            raise PreconditionError(
                "AngleThreshold.from_degrees",
                f"an angle threshold must be strictly between 0 and 180 degrees, not {value}",
                degrees=value,
            )
        cos_sign = _sign(90 - value)
        cos2 = _cos2_exact(value)
        exact = cos2 is not None
        if cos2 is None:
            cos2 = _cos2_safe(value, cos_sign)
        cos2_float = float(cos2)
        if cos2 != 0 and cos2_float < _SMALLEST_NORMAL:
            cos2_float = math.nan  # no relative error bound: the filter defers to exact
        return cls(value, cos2, cos_sign, exact, cos2_float)


def _compare_angle_exact(a: PointT, b: PointT, c: PointT, threshold: AngleThreshold) -> Comparison:
    if len(a) == 4:
        ux = a[0] - b[0]
        uy = a[1] - b[1]
        vx = c[0] - b[0]
        vy = c[1] - b[1]
        dot = ux * vx + uy * vy
        lengths = (ux * ux + uy * uy) * (vx * vx + vy * vy)
    else:
        ux = a[0] - b[0]
        uy = a[1] - b[1]
        uz = a[2] - b[2]
        vx = c[0] - b[0]
        vy = c[1] - b[1]
        vz = c[2] - b[2]
        dot = ux * vx + uy * vy + uz * vz
        lengths = (ux * ux + uy * uy + uz * uz) * (vx * vx + vy * vy + vz * vz)
    if lengths == 0:
        raise PreconditionError(
            "compare_angle", "the angle at b is undefined: a or c coincides with b", a=a, b=b, c=c
        )
    cos_sign = threshold.cos_sign
    dot_sign = _sign(dot)
    if cos_sign == 0:
        return _COMPARISONS[-dot_sign]
    if dot_sign != cos_sign:
        # cos(angle) <= 0 < cos(theta) (angle > theta) or cos(angle) >= 0 > cos(theta)
        return _GREATER if cos_sign > 0 else _LESS
    # same sign: compare cos^2(angle) = dot^2 / lengths with cos2
    difference = _sign(threshold.cos2 * lengths - dot * dot)  # > 0: |cos angle| < |cos theta|
    return _COMPARISONS[difference * cos_sign]


def compare_angle(a: PointT, b: PointT, c: PointT, threshold: AngleThreshold) -> Comparison:
    """Compare the angle ∠abc at vertex b (in [0°, 180°]) with ``threshold``.

    GREATER when the angle is larger than θ, EQUAL when equal, LESS when smaller (θ is
    the threshold's effective angle, see :class:`AngleThreshold`).  Exact: the dot
    product's sign and a squared comparison, no square roots.  Raises
    :class:`~geomexact.errors.PreconditionError` when a or c coincides with b.
    """
    if len(a) == 4:
        bx = b[2]
        by = b[3]
        ux = a[2] - bx
        uy = a[3] - by
        vx = c[2] - bx
        vy = c[3] - by
        dot = ux * vx + uy * vy
        lu = ux * ux + uy * uy
        lv = vx * vx + vy * vy
        t = abs(ux) + abs(uy) + abs(vx) + abs(vy) + DOT_K
        mt = abs(bx) + abs(by) + t
    else:
        bx = b[3]
        by = b[4]
        bz = b[5]
        ux = a[3] - bx
        uy = a[4] - by
        uz = a[5] - bz
        vx = c[3] - bx
        vy = c[4] - by
        vz = c[5] - bz
        dot = ux * vx + uy * vy + uz * vz
        lu = ux * ux + uy * uy + uz * uz
        lv = vx * vx + vy * vy + vz * vz
        t = abs(ux) + abs(uy) + abs(uz) + abs(vx) + abs(vy) + abs(vz) + DOT_K
        mt = abs(bx) + abs(by) + abs(bz) + t
    cos_sign = threshold.cos_sign
    bound = t * mt * DOT_C
    if dot > bound:
        dot_sign = 1
    elif -dot > bound:
        dot_sign = -1
    else:
        _ANG[1] += 1
        return _compare_angle_exact(a, b, c, threshold)
    if cos_sign == 0:
        _ANG[0] += 1
        return _LESS if dot_sign > 0 else _GREATER
    if dot_sign != cos_sign:
        _ANG[0] += 1
        return _GREATER if cos_sign > 0 else _LESS
    difference = threshold.cos2_float * lu * lv - dot * dot
    t += ANGLE_K
    bound = t * t * t * (mt + ANGLE_K) * ANGLE_C  # t and m + t, each grown by ANGLE_K
    if difference > bound:
        _ANG[0] += 1
        return _GREATER if cos_sign > 0 else _LESS
    if -difference > bound:
        _ANG[0] += 1
        return _LESS if cos_sign > 0 else _GREATER
    _ANG[1] += 1
    return _compare_angle_exact(a, b, c, threshold)


def angle_degrees(a: PointT, b: PointT, c: PointT) -> float:
    """The angle ∠abc at b in degrees, as a float (for reports only, never for decisions).

    Computed from the exact dot and cross products with ``atan2`` in 64-bit MPFR, so it is
    accurate for any magnitude.  Raises ``PreconditionError`` when a or c coincides with b.
    """
    if len(a) == 4:
        ux = a[0] - b[0]
        uy = a[1] - b[1]
        vx = c[0] - b[0]
        vy = c[1] - b[1]
        dot = ux * vx + uy * vy
        cross2 = (ux * vy - uy * vx) ** 2
        degenerate = (ux == 0 and uy == 0) or (vx == 0 and vy == 0)
    else:
        ux = a[0] - b[0]
        uy = a[1] - b[1]
        uz = a[2] - b[2]
        vx = c[0] - b[0]
        vy = c[1] - b[1]
        vz = c[2] - b[2]
        dot = ux * vx + uy * vy + uz * vz
        cross2 = (uy * vz - uz * vy) ** 2 + (uz * vx - ux * vz) ** 2 + (ux * vy - uy * vx) ** 2
        degenerate = (ux == 0 and uy == 0 and uz == 0) or (vx == 0 and vy == 0 and vz == 0)
    if degenerate:
        raise PreconditionError(
            "angle_degrees", "the angle at b is undefined: a or c coincides with b", a=a, b=b, c=c
        )
    with gmpy2.context(precision=64):
        radians = gmpy2.atan2(gmpy2.sqrt(gmpy2.mpfr(cross2)), gmpy2.mpfr(dot))
    return math.degrees(float(radians))
