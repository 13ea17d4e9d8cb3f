"""Where the octree is refined: a *region* is any callable ``region(box) -> bool``, true when
it meets the closed box (exact rational arithmetic, no tolerance).  The classes here are
the source's regions: box, solid ball, sphere surface, point, segment, the whole domain,
and a union of regions."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, TypeAlias

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, to_rational
from geomexact.mesh3d.cuboid.boxes import Box

__all__ = [
    "BallRegion",
    "BoxRegion",
    "PointRegion",
    "Region",
    "SegmentRegion",
    "SphereSurfaceRegion",
    "UnionRegion",
    "WholeDomain",
]

Triple: TypeAlias = tuple[Rational, Rational, Rational]


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


def _distance2_range(centre: Triple, box: Box) -> tuple[Rational, Rational]:
    """The squared distances from ``centre`` to the nearest and farthest points of
    ``box``."""
    near = far = ZERO
    for c, lo, hi in zip(centre, box.low, box.high, strict=True):
        gap = lo - c if c < lo else (c - hi if c > hi else ZERO)
        near += gap * gap
        reach = max(c - lo, hi - c)
        far += reach * reach
    return near, far


@attrs.frozen(slots=True)
class WholeDomain:
    """Every box."""

    def __call__(self, box: Box, /) -> bool:
        return True


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


@attrs.frozen(slots=True)
class BallRegion:
    """The solid ball of ``centre`` and ``radius`` (closed)."""

    centre: Triple = attrs.field(converter=_triple)
    radius: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        near, _ = _distance2_range(self.centre, box)
        return bool(near <= self.radius * self.radius)


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


@attrs.frozen(slots=True)
class PointRegion:
    """One point: it meets the boxes that contain it (on the boundary included)."""

    point: Triple = attrs.field(converter=_triple)

    def __call__(self, box: Box, /) -> bool:
        return all(lo <= p <= hi for p, lo, hi in zip(self.point, box.low, box.high,
                                                      strict=True))


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
