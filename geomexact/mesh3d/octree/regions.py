"""Where the octree is refined: a *region* is any callable ``region(box) -> bool``, true when
it meets the closed box (exact rational arithmetic, no tolerance).  The classes here are
the source's regions: box, solid ball, sphere surface, point, segment, the whole domain,
and a union of regions.

Many boxes at once: :func:`answers_on_boxes` gives a box test's answers (a region's, or a
refinement criterion's) for the boxes of a grid of *sides* (each box one side per axis,
given by its rows into per-axis lists of sides).  A test that is a sum or a conjunction
over the axes (ball, sphere, box, point, whole domain, a union of those) answers there by
``answers_on_sides``: its per-axis terms made once per side, brought exactly to integers
over one common denominator and added by numpy (int64 where the sums fit, else Python
integers), the same answers as its call on each box; any other test is called on each
box."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, ClassVar, Protocol, TypeAlias

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, to_rational
from geomexact.mesh3d.cuboid.boxes import Box

__all__ = [
    "AxisSides",
    "BallRegion",
    "BoxRegion",
    "ConstantTest",
    "PointRegion",
    "Region",
    "SegmentRegion",
    "SphereSurfaceRegion",
    "UnionRegion",
    "WholeDomain",
    "answers_on_boxes",
]

Triple: TypeAlias = tuple[Rational, Rational, Rational]
AxisSides: TypeAlias = Sequence[Sequence[tuple[Rational, Rational]]]
"""Per axis, a list of sides (low, high) of boxes."""


class Region(Protocol):
    """True when the region meets the closed box."""

    def __call__(self, box: Box, /) -> bool: ...


def _triple(values: Sequence[object]) -> Triple:
    x, y, z = (to_rational(v) for v in values)
    return (x, y, z)


def _positive(value: object) -> Rational:
    number = to_rational(value)
    if number <= 0:
        raise PreconditionError("octree", f"a radius is positive, not {value}")
    return number


def _gap_reach(c: Rational, lo: Rational, hi: Rational) -> tuple[Rational, Rational]:
    """Along one axis, the distances from ``c`` to the nearest and farthest points of
    [lo, hi]."""
    gap = lo - c if c < lo else (c - hi if c > hi else ZERO)
    return gap, max(c - lo, hi - c)


def _distance2_range(centre: Triple, box: Box) -> tuple[Rational, Rational]:
    """The squared distances from ``centre`` to the nearest and farthest points of
    ``box``."""
    near = far = ZERO
    for c, lo, hi in zip(centre, box.low, box.high, strict=True):
        gap, reach = _gap_reach(c, lo, hi)
        near += gap * gap
        far += reach * reach
    return near, far


def _sums(terms: Sequence[Sequence[Sequence[Rational]]], rows: Any,
          bounds: Sequence[Rational]) -> tuple[list[Any], list[int]]:
    """For each of ``terms`` (per axis, one non-negative rational per side): its sum over
    the axes for each row of ``rows`` (n x 3 side indices), and ``bounds`` -- all scaled
    by the lcm of every denominator, so exact integers (int64 when the sums fit, else
    Python integers); a sum compares with a bound as the rationals do."""
    values = [q for term in terms for axis in term for q in axis] + list(bounds)
    scale = math.lcm(*(int(q.denominator) for q in values))
    largest = max((int(q.numerator) * (scale // int(q.denominator)) for q in values),
                  default=0)
    kind: Any = np.int64 if 3 * largest < 1 << 62 else object
    sums = []
    for term in terms:
        columns = [np.array([int(q.numerator) * (scale // int(q.denominator)) for q in axis],
                            dtype=kind) for axis in term]
        sums.append(columns[0][rows[:, 0]] + columns[1][rows[:, 1]] + columns[2][rows[:, 2]])
    return sums, [int(q * scale) for q in bounds]


def _all_axes(meets: Sequence[Sequence[bool]], rows: Any) -> Any:
    """True for the rows (n x 3 side indices) whose side meets on every axis."""
    flags = [np.array(axis, dtype=bool) for axis in meets]
    return flags[0][rows[:, 0]] & flags[1][rows[:, 1]] & flags[2][rows[:, 2]]


def answers_on_boxes(test: Callable[[Box], bool], sides: AxisSides, rows: Any) -> Any:
    """``test`` (a region, or a criterion) on each box ``sides[0][rows[n, 0]] x
    sides[1][rows[n, 1]] x sides[2][rows[n, 2]]`` (a bool array): by the test's
    ``answers_on_sides`` when it has one, else by calling it on each box."""
    rows = np.asarray(rows, dtype=np.int64).reshape(-1, 3)
    vectorised = getattr(test, "answers_on_sides", None)
    if vectorised is not None:
        return np.asarray(vectorised(sides, rows), dtype=bool)
    return np.array([bool(test(Box(tuple(sides[a][row[a]][0] for a in range(3)),
                                         tuple(sides[a][row[a]][1] for a in range(3)))))
                     for row in rows.tolist()], dtype=bool)


class ConstantTest:
    """A box test with the same ``answer`` for every box (a region or a criterion)."""

    __slots__ = ()
    answer: ClassVar[bool]

    def __call__(self, box: Box, /) -> bool:
        return self.answer

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        return np.full(len(rows), self.answer, dtype=bool)


@attrs.frozen(slots=True)
class WholeDomain(ConstantTest):
    """Every box."""

    answer = True


@attrs.frozen(slots=True)
class BoxRegion:
    """The closed box ``low .. high`` (exact)."""

    low: Triple = attrs.field(converter=_triple)
    high: Triple = attrs.field(converter=_triple)

    def __attrs_post_init__(self) -> None:
        if not all(lo <= hi for lo, hi in zip(self.low, self.high, strict=True)):
            raise PreconditionError("octree", f"a box region needs low <= high, not "
                                    f"{self.low} .. {self.high}")

    def __call__(self, box: Box, /) -> bool:
        return all(lo <= b_hi and b_lo <= hi for lo, hi, b_lo, b_hi
                   in zip(self.low, self.high, box.low, box.high, strict=True))

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        return _all_axes([[lo <= b_hi and b_lo <= hi for b_lo, b_hi in axis]
                          for lo, hi, axis in zip(self.low, self.high, sides, strict=True)],
                         rows)


@attrs.frozen(slots=True)
class BallRegion:
    """The solid ball of ``centre`` and ``radius`` (closed)."""

    centre: Triple = attrs.field(converter=_triple)
    radius: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        near, _ = _distance2_range(self.centre, box)
        return bool(near <= self.radius * self.radius)

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        gaps = [[_gap_reach(c, lo, hi)[0] ** 2 for lo, hi in axis]
                for c, axis in zip(self.centre, sides, strict=True)]
        (near,), (r2,) = _sums([gaps], rows, [self.radius * self.radius])
        return near <= r2


@attrs.frozen(slots=True)
class SphereSurfaceRegion:
    """The sphere (surface only) of ``centre`` and ``radius``: it meets a box when the box
    has points both within and beyond the radius (closed)."""

    centre: Triple = attrs.field(converter=_triple)
    radius: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        near, far = _distance2_range(self.centre, box)
        r2 = self.radius * self.radius
        return bool(near <= r2 <= far)

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        ranges = [[_gap_reach(c, lo, hi) for lo, hi in axis]
                  for c, axis in zip(self.centre, sides, strict=True)]
        gaps = [[gap * gap for gap, _ in axis] for axis in ranges]
        reaches = [[reach * reach for _, reach in axis] for axis in ranges]
        (near, far), (r2,) = _sums([gaps, reaches], rows, [self.radius * self.radius])
        return (near <= r2) & (r2 <= far)


@attrs.frozen(slots=True)
class PointRegion:
    """One point: it meets the boxes that contain it (on the boundary included)."""

    point: Triple = attrs.field(converter=_triple)

    def __call__(self, box: Box, /) -> bool:
        return all(lo <= p <= hi for p, lo, hi in zip(self.point, box.low, box.high,
                                                      strict=True))

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        return _all_axes([[lo <= p <= hi for lo, hi in axis]
                          for p, axis in zip(self.point, sides, strict=True)], rows)


@attrs.frozen(slots=True)
class SegmentRegion:
    """The closed segment from ``start`` to ``end`` (exact slab clipping)."""

    start: Triple = attrs.field(converter=_triple)
    end: Triple = attrs.field(converter=_triple)

    def __call__(self, box: Box, /) -> bool:
        enter, leave = ZERO, to_rational(1)
        for p, q, lo, hi in zip(self.start, self.end, box.low, box.high, strict=True):
            step = q - p
            if step == 0:
                if not lo <= p <= hi:
                    return False
                continue
            t0, t1 = (lo - p) / step, (hi - p) / step
            if t0 > t1:
                t0, t1 = t1, t0
            enter, leave = max(enter, t0), min(leave, t1)
            if enter > leave:
                return False
        return True


@attrs.frozen(slots=True)
class UnionRegion:
    """The union of ``regions`` (any callables ``region(box) -> bool``)."""

    regions: tuple[Callable[[Box], bool], ...] = attrs.field(converter=tuple)

    def __call__(self, box: Box, /) -> bool:
        return any(region(box) for region in self.regions)

    def answers_on_sides(self, sides: AxisSides, rows: Any) -> Any:
        met = np.zeros(len(rows), dtype=bool)
        for region in self.regions:  # each asked only about the boxes not yet met
            open_rows = np.flatnonzero(~met)
            if not len(open_rows):
                break
            met[open_rows] = answers_on_boxes(region, sides, rows[open_rows])
        return met
