"""Centroids of terminal quadrilaterals, and the step that inserts a given point into the
quadrilateral of an edge.

Why a rounded centroid: the exact area centroid of a quadrilateral has coordinates of about
three times the bit size of its corners' (a cubic over a quadratic), and in Lepp-centroid
refinement new centroids are taken of quadrilaterals made of earlier centroids, so the
sizes grow geometrically — measured on Lake Superior at 25°: 522 centroids gave
denominators of 1.2 million bits and four minutes of arithmetic.
:func:`rounded_area_centroid` keeps the area centroid to ``bits`` bits relative to the
quadrilateral's shortest side, on a dyadic grid, so coordinates stay a few dozen bits and
the predicates' float filters decide almost everything.  The rounded point is recorded
exactly in the step ``insert_in_quadrilateral(u, v, x, y)``; replay never recomputes it.
Specification: ``specs/refine.md``.
"""

from __future__ import annotations

import gmpy2

from geomexact.kernel.numbers import Rational, floor_log2, mpq
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.ops import quadrilateral_area_centroid

__all__ = ["CENTROID_BITS", "rounded_area_centroid"]

CENTROID_BITS = 24
"""Default precision of :func:`rounded_area_centroid`, in bits below the quadrilateral's
shortest side."""

_CCW = Orientation.COUNTERCLOCKWISE
_ATTEMPTS = 8




def _round_to(value: Rational, exponent: int) -> Rational:
    """The multiple of 2^exponent nearest to ``value`` (halves round up)."""
    step = mpq(2) ** exponent
    scaled = value / step + mpq(1, 2)
    whole = gmpy2.mpz(scaled.numerator) // gmpy2.mpz(scaled.denominator)
    result: Rational = mpq(whole) * step
    return result


def _strictly_inside(corners: tuple[Point2, Point2, Point2, Point2], point: Point2) -> bool:
    u, x, v, w = corners
    return all(
        orient2d(p, q, point) == _CCW for p, q in ((u, x), (x, v), (v, w), (w, u))
    )


def rounded_area_centroid(
    pu: Point2, pv: Point2, pw: Point2, px: Point2, bits: int = CENTROID_BITS
) -> Point2:
    """The area centroid of the strictly convex quadrilateral u, x, v, w (triangles
    (u, v, w) and (v, u, x), counter-clockwise), rounded to the nearest point of the grid
    of spacing 2^e with e = floor(log2(shortest side)) − ``bits``.

    If the rounded point is not strictly inside all four triangles (u, x, ·), (x, v, ·),
    (v, w, ·), (w, u, ·) — possible only for a quadrilateral much thinner than its sides —
    the grid is refined by another ``bits`` bits, up to 8 times, and then the exact
    centroid is returned.  Deterministic: exact integer arithmetic only.
    """
    exact = quadrilateral_area_centroid(pu, pv, pw, px)
    corners = (pu, px, pv, pw)
    shortest = min(
        (q.x - p.x) ** 2 + (q.y - p.y) ** 2
        for p, q in ((pu, px), (px, pv), (pv, pw), (pw, pu))
    )
    exponent = floor_log2(shortest) // 2 - bits
    for _ in range(_ATTEMPTS):
        candidate = point2(_round_to(exact.x, exponent), _round_to(exact.y, exponent))
        if _strictly_inside(corners, candidate):
            return candidate
        exponent -= bits
    return exact
