"""What every copy of the certified float filters shares: their error-bound constants and
how often each Python filter decided.

One source for the constants of all three backends: the Python predicates
(:mod:`~geomexact.kernel.predicates2d`, :mod:`~geomexact.kernel.predicates3d`,
:mod:`~geomexact.kernel.comparisons`, :mod:`~geomexact.kernel.angles`), the numpy filters
(:mod:`~geomexact.kernel.array_filters`) and the C filters of ``ckernel.h`` (filled in from
here when a compiled kernel is imported).  Imports nothing, so reading a constant costs
nothing.

For a predicate of degree k in the coordinate differences, with ``t`` the sum of the
absolute computed differences plus K and ``m`` the sum of the absolute pivot coordinates
(floats), a filter accepts the float determinant when

    |det| > t^(k-1) * (m + t) * C        (evaluated left to right in floats).

C covers the rounding of the inputs (each float is only the nearest double of its
rational), of the differences, products and sums; K >= 2^(-950/k) keeps every product in
the bound normal so that underflow is covered.  The derivation, and the minimal C each
value was rounded up from, are in ``specs/predicates.md``; ``tests/kernel/test_predicates.py``
recomputes the requirements with exact rationals.
"""

from __future__ import annotations

from typing import Final

__all__ = [
    "ANGLE_C",
    "ANGLE_K",
    "DOT_C",
    "DOT_K",
    "INCIRCLE_C",
    "INCIRCLE_K",
    "INSPHERE_C",
    "INSPHERE_K",
    "LENGTHS_C",
    "LENGTHS_K",
    "ORIENT2D_C",
    "ORIENT2D_K",
    "ORIENT3D_C",
    "ORIENT3D_K",
    "SUM_MARGIN",
    "filter_counters",
    "reset_filter_counters",
]

_U: Final = 2.0**-53  # the unit roundoff
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
SUM_MARGIN: Final = 1.0 + 2.0**-50

# [hits, misses] of each Python predicate, incremented in place by the predicate itself
# (a module-level list: the cheapest counter on the fast path).
ORIENT2D_COUNTS: Final = [0, 0]
ORIENT3D_COUNTS: Final = [0, 0]
INCIRCLE_COUNTS: Final = [0, 0]
INSPHERE_COUNTS: Final = [0, 0]
LENGTHS_COUNTS: Final = [0, 0]
AREAS_COUNTS: Final = [0, 0]
ANGLE_COUNTS: Final = [0, 0]
_COUNTERS: Final = {
    "orient2d": ORIENT2D_COUNTS,
    "orient3d": ORIENT3D_COUNTS,
    "incircle": INCIRCLE_COUNTS,
    "insphere": INSPHERE_COUNTS,
    "compare_squared_lengths": LENGTHS_COUNTS,
    "compare_areas": AREAS_COUNTS,
    "compare_angle": ANGLE_COUNTS,
}


def filter_counters() -> dict[str, tuple[int, int]]:
    """``{predicate name: (filter successes, exact fallbacks)}`` since the last reset."""
    return {name: (counts[0], counts[1]) for name, counts in _COUNTERS.items()}


def reset_filter_counters() -> None:
    """Set every filter counter back to zero."""
    for counts in _COUNTERS.values():
        counts[0] = 0
        counts[1] = 0
