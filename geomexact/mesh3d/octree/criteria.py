"""When a leaf is fine enough: a *criterion* is any callable ``criterion(box) -> bool``, true
when the leaf's box satisfies it (the refinement splits a leaf while a criterion fails on
it, inside a region, up to the maximum level).  All comparisons are exact: lengths are
compared through their squares, so no square root is ever taken.

The shape criteria (radius-edge ratio, aspect ratio, volume / longest-edge ratio) are
unchanged by a split into octants, so on one leaf they either hold or fail down to the
maximum level; they tell apart the cells of a stretched grid.  The list is the source's
(Arancibia 2007), with the scalar-field (doping concentration) criterion.
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import product
from typing import Protocol

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, to_rational
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.regions import ConstantTest

__all__ = [
    "AllOf",
    "AspectRatio",
    "Criterion",
    "MaxEdgeLength",
    "MinEdgeLength",
    "RadiusEdgeRatio",
    "RefineToMaxLevel",
    "ScalarFieldVariation",
    "VolumeEdgeRatio",
]


class Criterion(Protocol):
    """True when the leaf's box satisfies the criterion (no split needed)."""

    def __call__(self, box: Box, /) -> bool: ...


def _positive(value: object) -> Rational:
    number = to_rational(value)
    if number <= 0:
        raise PreconditionError("octree", f"a criterion's bound is positive, not {value}")
    return number


@attrs.frozen(slots=True)
class RefineToMaxLevel(ConstantTest):
    """Never satisfied: the refinement goes to the maximum level wherever the region
    meets a leaf."""

    answer = False


@attrs.frozen(slots=True)
class MaxEdgeLength:
    """Every edge of the leaf is at most ``length``."""

    length: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        return bool(max(box.extents) <= self.length)


@attrs.frozen(slots=True)
class MinEdgeLength:
    """The shortest edge of the leaf is at most ``length`` (a leaf is split while even its
    shortest edge is longer)."""

    length: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        return bool(min(box.extents) <= self.length)


@attrs.frozen(slots=True)
class RadiusEdgeRatio:
    """circumradius / shortest edge <= ``bound`` (the circumradius of a box is half its
    diagonal; the cube's ratio is sqrt(3)/2)."""

    bound: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        x, y, z = box.extents
        shortest = min(x, y, z)
        return bool((x * x + y * y + z * z) <= 4 * self.bound * self.bound * shortest * shortest)


@attrs.frozen(slots=True)
class AspectRatio:
    """longest edge / shortest edge <= ``bound``."""

    bound: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        extents = box.extents
        return bool(max(extents) <= self.bound * min(extents))


@attrs.frozen(slots=True)
class VolumeEdgeRatio:
    """volume / longest edge**3 >= ``bound`` (1 for a cube)."""

    bound: Rational = attrs.field(converter=_positive)

    def __call__(self, box: Box, /) -> bool:
        longest = max(box.extents)
        return bool(box.volume >= self.bound * longest * longest * longest)


@attrs.frozen(slots=True)
class ScalarFieldVariation:
    """The user's field varies by at most ``threshold`` over the leaf: max - min of
    ``field(x, y, z)`` over the eight corners and the centre (exact values; a float result
    is taken at its exact binary value).  The source's doping-concentration criterion."""

    field: Callable[[Rational, Rational, Rational], object]
    threshold: Rational = attrs.field(converter=to_rational)

    def __call__(self, box: Box, /) -> bool:
        samples = [to_rational(self.field(*box.at2(position)[:3]))
                   for position in (*product((0, 2), repeat=3), (1, 1, 1))]
        return bool(max(samples) - min(samples) <= self.threshold)


@attrs.frozen(slots=True)
class AllOf:
    """Every one of ``criteria`` holds."""

    criteria: tuple[Callable[[Box], bool], ...] = attrs.field(converter=tuple)

    def __call__(self, box: Box, /) -> bool:
        return all(criterion(box) for criterion in self.criteria)

