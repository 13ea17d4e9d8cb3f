"""The numbering of a 1-irregular cuboid (``specs/cuboid.md``, with a drawing).

Corner ``k`` (0..7) is at the unit position ``(k & 1, k >> 1 & 1, k >> 2 & 1)`` (bits
z y x).  Bits 0..11 are the twelve cube edges: a ring round the bottom face (0..3), the
same ring round the top face (4..7), then the four vertical edges (8..11).  Bits 12..17 are
the six faces x=0, x=1, y=0, y=1, z=0, z=1; a face's Steiner point is its centre, the
midpoint of its diagonal in the chosen template (``templates.py``).  A *pattern* is an int
0 .. 2**18 - 1 whose bit i marks a Steiner point on edge or face i.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from geomexact.errors import PreconditionError

__all__ = [
    "ALL_BITS",
    "BIT_COUNT",
    "CORNER_POSITIONS",
    "EDGE_BITS",
    "EDGE_CORNERS",
    "FACE_BITS",
    "FACE_CORNERS",
    "FACE_EDGES",
    "FACE_NAMES",
    "PATTERN_COUNT",
    "bits_of",
    "check_pattern",
    "pattern_of",
    "steiner_position2",
]

BIT_COUNT: Final = 18
PATTERN_COUNT: Final = 1 << BIT_COUNT
"""Patterns are 0 .. PATTERN_COUNT - 1."""
ALL_BITS: Final = PATTERN_COUNT - 1
EDGE_BITS: Final = tuple(range(12))
FACE_BITS: Final = tuple(range(12, 18))

CORNER_POSITIONS: Final[tuple[tuple[int, int, int], ...]] = tuple(
    (k & 1, k >> 1 & 1, k >> 2 & 1) for k in range(8)
)
"""Corner k -> its unit position (x, y, z) in {0, 1}^3."""

EDGE_CORNERS: Final[tuple[tuple[int, int], ...]] = (
    (0, 1), (1, 3), (2, 3), (0, 2),  # bottom ring z=0: y=0, x=1, y=1, x=0
    (4, 5), (5, 7), (6, 7), (4, 6),  # top ring z=1, in the same order
    (0, 4), (1, 5), (3, 7), (2, 6),  # verticals at (x, y) = (0,0), (1,0), (1,1), (0,1)
)
"""Cube edge i (bit i, 0..11) -> its two corners (lower first)."""

FACE_NAMES: Final = ("x=0", "x=1", "y=0", "y=1", "z=0", "z=1")
"""Face bit 12 + j -> its name: face j is where coordinate j // 2 is 0 (j even) or 1."""

FACE_CORNERS: Final[tuple[tuple[int, ...], ...]] = tuple(
    tuple(k for k in range(8) if CORNER_POSITIONS[k][j // 2] == j % 2) for j in range(6)
)
"""Face j (bit 12 + j) -> its four corners, increasing."""

FACE_EDGES: Final[tuple[tuple[int, ...], ...]] = tuple(
    tuple(i for i, (p, q) in enumerate(EDGE_CORNERS)
          if p in FACE_CORNERS[j] and q in FACE_CORNERS[j])
    for j in range(6)
)
"""Face j (bit 12 + j) -> its four edge bits, increasing."""


def check_pattern(pattern: int) -> int:
    """``pattern`` itself when it is an int in 0 .. 2**18 - 1, else PreconditionError."""
    if isinstance(pattern, bool) or not isinstance(pattern, int) or not (
        0 <= pattern < PATTERN_COUNT
    ):
        raise PreconditionError(
            "cuboid", f"a pattern is an integer 0 .. {PATTERN_COUNT - 1}, not {pattern!r}"
        )
    return pattern


def bits_of(pattern: int) -> tuple[int, ...]:
    """The set bits of ``pattern``, increasing (``bits_of(70688) == (5, 10, 12, 16)``)."""
    check_pattern(pattern)
    return tuple(i for i in range(BIT_COUNT) if pattern >> i & 1)


def pattern_of(bits: Iterator[int] | tuple[int, ...] | list[int]) -> int:
    """The pattern with exactly ``bits`` set (``pattern_of([4, 12, 13]) == 12304``)."""
    pattern = 0
    for bit in bits:
        if not 0 <= bit < BIT_COUNT:
            raise PreconditionError("cuboid", f"bit {bit} is outside 0..{BIT_COUNT - 1}")
        pattern |= 1 << bit
    return pattern


def steiner_position2(bit: int) -> tuple[int, int, int]:
    """Twice the unit position of the Steiner point of ``bit`` (each coordinate 0, 1 or
    2): the midpoint of edge ``bit`` (0..11) or the centre of face ``bit`` (12..17)."""
    if bit < 12:
        p, q = EDGE_CORNERS[bit]
        a, b = CORNER_POSITIONS[p], CORNER_POSITIONS[q]
        return (a[0] + b[0], a[1] + b[1], a[2] + b[2])
    j = bit - 12
    position = [1, 1, 1]
    position[j // 2] = 2 * (j % 2)
    return (position[0], position[1], position[2])
