"""Exact points in the plane and in space.

A point carries its exact rational coordinates and, for the predicates' float filter only,
the nearest doubles of them (``nan`` when a coordinate is beyond the double range, which
sends every predicate on it to the exact path).  Two points are equal when their exact
coordinates are equal.
"""

from __future__ import annotations

import math
from typing import NamedTuple, TypeVar

from geomexact.kernel.numbers import Rational, to_rational


def nearest_double(value: Rational) -> float:
    """The double nearest to ``value`` (NaN beyond the doubles' range): a point's ``fx``."""
    try:
        return float(value)  # gmpy2 rounds to nearest
    except OverflowError:
        return math.nan


class Point2(NamedTuple):
    """A point of the plane: exact ``x``, ``y`` and their doubles ``fx``, ``fy``."""

    x: Rational
    y: Rational
    fx: float
    fy: float

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Point2) and self.x == other.x and self.y == other.y

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash((self.x, self.y))

    def __repr__(self) -> str:
        return f"Point2({self.x}, {self.y})"


class Point3(NamedTuple):
    """A point of space: exact ``x``, ``y``, ``z`` and their doubles."""

    x: Rational
    y: Rational
    z: Rational
    fx: float
    fy: float
    fz: float

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, Point3)
            and self.x == other.x
            and self.y == other.y
            and self.z == other.z
        )

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:
        return hash((self.x, self.y, self.z))

    def __repr__(self) -> str:
        return f"Point3({self.x}, {self.y}, {self.z})"


PointT = TypeVar("PointT", Point2, Point3)
"""A point of either dimension, the same for every argument (functions on both)."""


def point2(x: object, y: object) -> Point2:
    """The exact point (x, y); coordinates are converted by :func:`to_rational`."""
    qx, qy = to_rational(x), to_rational(y)
    return Point2(qx, qy, nearest_double(qx), nearest_double(qy))


def point3(x: object, y: object, z: object) -> Point3:
    """The exact point (x, y, z); coordinates are converted by :func:`to_rational`."""
    qx, qy, qz = to_rational(x), to_rational(y), to_rational(z)
    return Point3(qx, qy, qz, nearest_double(qx), nearest_double(qy), nearest_double(qz))


def midpoint2(a: Point2, b: Point2) -> Point2:
    """The exact midpoint of segment ab."""
    return point2((a.x + b.x) / 2, (a.y + b.y) / 2)


def midpoint3(a: Point3, b: Point3) -> Point3:
    """The exact midpoint of segment ab."""
    return point3((a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2)
