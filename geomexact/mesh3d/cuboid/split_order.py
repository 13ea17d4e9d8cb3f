"""The order in which a pattern's Steiner points are inserted (``specs/cuboid.md``).

* ``"conforming"`` (the default): the face centres first, then the edge midpoints, each
  group in lexicographic order of the points' exact coordinates.  Two cuboids sharing a
  face see the same points in the same order, so they triangulate it identically.
* ``"index"``: the bits in increasing number, as the source does.
"""

from __future__ import annotations

from typing import Final, Literal, TypeAlias

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.numbering import ALL_BITS, bits_of

__all__ = ["ORDERS", "SplitOrder", "check_order", "split_ranks", "split_sequence"]

SplitOrder: TypeAlias = Literal["conforming", "index"]
ORDERS: Final[tuple[SplitOrder, ...]] = ("conforming", "index")


def check_order(order: str) -> SplitOrder:
    """``order`` when it is a split order's name, else PreconditionError."""
    if order == "conforming":
        return "conforming"
    if order == "index":
        return "index"
    raise PreconditionError("cuboid", f"the split order is 'conforming' or 'index', "
                            f"not {order!r}")


def split_sequence(pattern: int, box: Box, order: str = "conforming") -> tuple[int, ...]:
    """The bits of ``pattern`` in the order their Steiner points are inserted."""
    bits = bits_of(pattern)
    if check_order(order) == "index":
        return bits
    return tuple(sorted(bits, key=lambda bit: (bit < 12, box.steiner_point(bit)[:3])))


def split_ranks(box: Box, order: str = "conforming") -> tuple[int, ...]:
    """All 18 bits in their insertion order (the order of any pattern is this one
    restricted to its bits: both orders sort by a fixed key)."""
    return split_sequence(ALL_BITS, box, order)
