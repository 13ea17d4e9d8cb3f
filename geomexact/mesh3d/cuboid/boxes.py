"""Axis-aligned boxes with exact rational corners: where a cuboid's corners and Steiner
points are."""

from __future__ import annotations

from collections.abc import Sequence

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, format_rational, mpq, to_rational
from geomexact.kernel.points import Point3, point3
from geomexact.mesh3d.cuboid.numbering import CORNER_POSITIONS, steiner_position2

__all__ = ["Box", "box_of_extents", "unit_cube"]


def _triple(values: Sequence[object]) -> tuple[Rational, Rational, Rational]:
    x, y, z = (to_rational(v) for v in values)
    return (x, y, z)


@attrs.frozen(slots=True)
class Box:
    """The box [low.x, high.x] x [low.y, high.y] x [low.z, high.z], exact, each extent > 0."""

    low: tuple[Rational, Rational, Rational] = attrs.field(converter=_triple)
    high: tuple[Rational, Rational, Rational] = attrs.field(converter=_triple)

    def __attrs_post_init__(self) -> None:
        if not all(h > lo for lo, h in zip(self.low, self.high, strict=True)):
            raise PreconditionError(
                "cuboid", f"a box needs high > low on every axis, not {self.low} .. {self.high}"
            )

    @property
    def extents(self) -> tuple[Rational, Rational, Rational]:
        x, y, z = (h - lo for lo, h in zip(self.low, self.high, strict=True))
        return (x, y, z)

    @property
    def volume(self) -> Rational:
        x, y, z = self.extents
        return x * y * z  # type: ignore[no-any-return]

    def at2(self, position2: Sequence[int]) -> Point3:
        """The point at twice-unit position ``position2`` (coordinates 0, 1, 2 along each
        axis: low, middle, high)."""
        x, y, z = (lo + (h - lo) * mpq(t, 2)
                   for lo, h, t in zip(self.low, self.high, position2, strict=True))
        return point3(x, y, z)

    def corner(self, k: int) -> Point3:
        """Corner ``k`` (0..7, bits z y x)."""
        return self.at2(tuple(2 * c for c in CORNER_POSITIONS[k]))

    def steiner_point(self, bit: int) -> Point3:
        """The Steiner point of ``bit``: the midpoint of edge ``bit`` or the centre of face
        ``bit``."""
        return self.at2(steiner_position2(bit))

    def describe(self) -> str:
        """``"1x2x4"`` for a box at the origin, else ``"[lo..hi]x[..]x[..]"`` (exact)."""
        if all(lo == 0 for lo in self.low):
            return "x".join(format_rational(h) for h in self.high)
        return "x".join(f"[{format_rational(lo)}..{format_rational(h)}]"
                        for lo, h in zip(self.low, self.high, strict=True))


def box_of_extents(x: object, y: object, z: object) -> Box:
    """The box [0, x] x [0, y] x [0, z] (exact extents > 0)."""
    return Box((0, 0, 0), (x, y, z))


def unit_cube() -> Box:
    """The box [0, 1]^3."""
    return box_of_extents(1, 1, 1)
