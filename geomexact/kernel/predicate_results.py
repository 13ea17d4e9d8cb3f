"""What the predicates return: small ``IntEnum`` s of a sign, shared by 2D and 3D.

The members are ordinary ints (``Orientation.CLOCKWISE == -1``), so multiplying by a
permutation's parity or comparing with ``0`` works.  ``ORIENTATIONS[s]`` (and the others)
is the member of a sign ``s`` in {-1, 0, 1} (index -1 is the last item), the cheapest way
for a predicate to turn a sign into its answer.
"""

from __future__ import annotations

from enum import IntEnum
from typing import Final, TypeVar

__all__ = [
    "CIRCLE_LOCATIONS",
    "COMPARISONS",
    "ORIENTATIONS",
    "SPHERE_LOCATIONS",
    "CircleLocation",
    "Comparison",
    "Orientation",
    "SphereLocation",
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


_Result = TypeVar("_Result", bound=IntEnum)


def _by_sign(kind: type[_Result]) -> tuple[_Result, _Result, _Result]:
    """The members of ``kind`` for the signs 0, 1, -1: item ``s`` is the member of value s."""
    return kind(0), kind(1), kind(-1)


ORIENTATIONS: Final = _by_sign(Orientation)
CIRCLE_LOCATIONS: Final = _by_sign(CircleLocation)
SPHERE_LOCATIONS: Final = _by_sign(SphereLocation)
COMPARISONS: Final = _by_sign(Comparison)
