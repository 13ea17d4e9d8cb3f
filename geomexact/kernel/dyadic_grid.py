"""The dyadic grid: points whose degree-2 predicates are exact in plain floats.

Fix a power of two ``unit = 2^-G``.  A point is *on the grid* when both of its exact
coordinates are integer multiples of ``unit`` of magnitude below ``2^GRID_BITS`` units.  Then
its floats ``fx, fy`` equal its rationals, and for points on the grid every expression of
the form ``(a - b)(c - d) ± (e - f)(g - h)`` — squared lengths, dot products of edge vectors,
doubled signed areas — and the difference of two such sums evaluates without any rounding in
IEEE doubles: differences stay below ``2^(GRID_BITS+1)`` units, products below
``2^(2·GRID_BITS+2)`` units², and sums of them below ``2^53`` units².  Comparisons of
those values are then exact, with no filter and no fallback.

:func:`grid_unit` picks ``G`` from the largest coordinate of the input so that every point in
its bounding box has coordinates below ``2^GRID_BITS`` units; midpoints of grid points stay
in that box, and a midpoint is on the grid exactly when its (exact) float coordinates are
still multiples of the unit (:func:`midpoint_on_grid`).  Refinement of dyadic inputs (unit
squares, power-of-two boxes) stays on the grid for ``G`` levels of bisection.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from geomexact.kernel.points import Point2

GRID_BITS = 24
"""Grid coordinates are below ``2^GRID_BITS`` units in magnitude (sums of two products of
differences then stay below 2^51 < 2^53)."""

_LIMIT = float(2**GRID_BITS)
_EXPONENT_RANGE = 400  # keeps unit², and the largest products, far from under/overflow


def grid_unit(points: Sequence[Point2]) -> float | None:
    """The scale ``2^G`` (1/unit) for ``points`` (the input of a run; later points lie in
    its bounding box), or None when the coordinates are all zero or so large or small that
    products could leave the normal double range.  O(n)."""
    largest = max((max(abs(p[2]), abs(p[3])) for p in points), default=0.0)
    if largest == 0.0 or math.isinf(largest):
        return None
    exponent = math.frexp(largest)[1]  # largest < 2^exponent
    if abs(exponent) > _EXPONENT_RANGE:
        return None
    return math.ldexp(1.0, GRID_BITS - exponent)


def on_grid(point: Point2, scale: float | None) -> bool:
    """True when ``point`` is on the grid of ``scale`` (exact test on its rationals)."""
    if scale is None:
        return False
    fx, fy = point[2], point[3]
    if fx != point[0] or fy != point[1]:  # mpq == float compares exactly
        return False
    x, y = fx * scale, fy * scale  # exact: scaling by a power of two
    return x.is_integer() and y.is_integer() and abs(x) < _LIMIT and abs(y) < _LIMIT


def midpoint_on_grid(pu: Point2, pv: Point2, scale: float) -> bool:
    """For two grid points: True when their midpoint is on the grid too.  The float sum of
    two grid coordinates is exact and halving it is exact, so this tests the exact midpoint;
    it lies in the bounding box of the input, below the magnitude limit."""
    return (((pu[2] + pv[2]) * 0.5) * scale).is_integer() and (
        ((pu[3] + pv[3]) * 0.5) * scale
    ).is_integer()


def grid_flags(points: Sequence[Point2]) -> tuple[float | None, list[bool]]:
    """``(scale, flags)``: the grid scale for ``points`` and which of them are on it."""
    scale = grid_unit(points)
    return scale, [on_grid(p, scale) for p in points]
