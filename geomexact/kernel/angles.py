"""Exact comparisons of an angle with a threshold (2D and 3D), and angles in degrees for
reports.

:class:`AngleThreshold` prepares an angle θ once (cos²θ as a rational, rounded to the safe
side when it is irrational); :func:`compare_angle` compares ∠abc with it without square
roots, by a certified float filter in two stages (constants in
:mod:`~geomexact.kernel.filter_bounds`), else exactly.  See ``specs/predicates.md``.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Final

import attrs
import gmpy2

from geomexact.errors import PreconditionError
from geomexact.kernel.filter_bounds import ANGLE_C, ANGLE_K, DOT_C, DOT_K
from geomexact.kernel.filter_bounds import ANGLE_COUNTS as _ANG
from geomexact.kernel.numbers import Rational, mpq, sign, to_rational
from geomexact.kernel.points import PointT
from geomexact.kernel.predicate_results import COMPARISONS, Comparison

__all__ = ["AngleThreshold", "angle_degrees", "compare_angle"]

_LESS: Final = Comparison.LESS
_GREATER: Final = Comparison.GREATER

_EXACT_COS2_BITS: Final = 64
_SMALLEST_NORMAL: Final = 2.0**-1022  # relative accuracy 2^-64 of an inexact threshold's cos^2


_RATIONAL_COS2: Final[dict[Rational, Rational]] = {
    mpq(0): mpq(1), mpq(30): mpq(3, 4), mpq(45): mpq(1, 2), mpq(60): mpq(1, 4), mpq(90): mpq(0),
    mpq(120): mpq(1, 4), mpq(135): mpq(1, 2), mpq(150): mpq(3, 4)}
"""cos^2 of the angles (degrees, modulo 180) where it is rational."""


def _cos2_exact(degrees: Rational) -> Rational | None:
    """cos^2 of ``degrees`` when it is rational, else None.

    cos^2(theta) = (1 + cos 2theta)/2, and by Niven's theorem the cosine of a rational
    number of degrees is rational only when it is 0, +-1/2 or +-1: modulo 180 that is
    theta in {0, 30, 45, 60, 90, 120, 135, 150}, a table (no computer algebra to load).
    """
    return _RATIONAL_COS2.get(mpq(degrees) % 180)


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
        cos_sign = sign(90 - value)
        cos2 = _cos2_exact(value)
        exact = cos2 is not None
        if cos2 is None:
            cos2 = _cos2_safe(value, cos_sign)
        cos2_float = float(cos2)
        if cos2 != 0 and cos2_float < _SMALLEST_NORMAL:
            cos2_float = math.nan  # no relative error bound: the filter defers to exact
        return cls(value, cos2, cos_sign, exact, cos2_float)


def _arm_products(a: PointT, b: PointT, c: PointT) -> tuple[Rational, Rational, Rational]:
    """``(u.v, |u|^2, |v|^2)`` for the arms u = a - b and v = c - b of the angle at b, exact."""
    ux = a[0] - b[0]
    uy = a[1] - b[1]
    vx = c[0] - b[0]
    vy = c[1] - b[1]
    if len(a) == 4:
        return ux * vx + uy * vy, ux * ux + uy * uy, vx * vx + vy * vy
    uz = a[2] - b[2]
    vz = c[2] - b[2]
    return ux * vx + uy * vy + uz * vz, ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz


def _compare_angle_exact(a: PointT, b: PointT, c: PointT, threshold: AngleThreshold) -> Comparison:
    dot, uu, vv = _arm_products(a, b, c)
    lengths = uu * vv
    if lengths == 0:
        raise PreconditionError(
            "compare_angle", "the angle at b is undefined: a or c coincides with b", a=a, b=b, c=c
        )
    cos_sign = threshold.cos_sign
    dot_sign = sign(dot)
    if cos_sign == 0:
        return COMPARISONS[-dot_sign]
    if dot_sign != cos_sign:
        # cos(angle) <= 0 < cos(theta) (angle > theta) or cos(angle) >= 0 > cos(theta)
        return _GREATER if cos_sign > 0 else _LESS
    # same sign: compare cos^2(angle) = dot^2 / lengths with cos2
    difference = sign(threshold.cos2 * lengths - dot * dot)  # > 0: |cos angle| < |cos theta|
    return COMPARISONS[difference * cos_sign]


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
    if dot_sign != cos_sign:
        # θ = 90°, or the angle is on the other side of 90° from θ: greater when obtuse
        _ANG[0] += 1
        return COMPARISONS[-dot_sign]
    difference = threshold.cos2_float * lu * lv - dot * dot
    t += ANGLE_K
    bound = t * t * t * (mt + ANGLE_K) * ANGLE_C  # t and m + t, each grown by ANGLE_K
    if difference > bound or -difference > bound:
        # difference > 0: |cos angle| < |cos θ|, the angle is nearer to 90° than θ
        _ANG[0] += 1
        return COMPARISONS[cos_sign if difference > 0.0 else -cos_sign]
    _ANG[1] += 1
    return _compare_angle_exact(a, b, c, threshold)


def angle_degrees(a: PointT, b: PointT, c: PointT) -> float:
    """The angle ∠abc at b in degrees, as a float (for reports only, never for decisions).

    Computed from the exact dot product and squared cross product with ``atan2`` in 64-bit
    MPFR, so it is accurate for any magnitude.  Raises ``PreconditionError`` when a or c
    coincides with b.
    """
    dot, uu, vv = _arm_products(a, b, c)
    if uu == 0 or vv == 0:
        raise PreconditionError(
            "angle_degrees", "the angle at b is undefined: a or c coincides with b", a=a, b=b, c=c
        )
    cross2 = uu * vv - dot * dot  # |u x v|^2, by Lagrange's identity (2D: (ux vy - uy vx)^2)
    with gmpy2.context(precision=64):
        radians = gmpy2.atan2(gmpy2.sqrt(gmpy2.mpfr(cross2)), gmpy2.mpfr(dot))
    return math.degrees(float(radians))
