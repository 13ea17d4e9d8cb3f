"""The two 5-tetrahedron templates of a cuboid and the rule that chooses one.

Template ``t`` has a central tetrahedron on the four corners whose number of 1 bits has
parity ``t`` (template 0: corners 0, 3, 5, 6; template 1: corners 1, 2, 4, 7, its mirror
image) and one tetrahedron at each other corner, on that corner and its three
neighbours.  Each face's diagonal joins its two corners of the central tetrahedron and
lies in three of the five tetrahedra.  Neighbours agree on the diagonal of their shared
face when every cuboid of a grid takes :func:`template_at` of its integer position: the
diagonals then join the grid points of even coordinate sum (``specs/cuboid.md``).
"""

from __future__ import annotations

from typing import Final

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.numbering import EDGE_CORNERS, FACE_CORNERS

__all__ = ["TEMPLATES", "TEMPLATE_TETRAHEDRA", "check_template", "diagonal", "segment_of",
           "template_at"]

TEMPLATES: Final = (0, 1)

TEMPLATE_TETRAHEDRA: Final[tuple[tuple[tuple[int, int, int, int], ...], ...]] = (
    ((3, 0, 5, 6), (0, 1, 3, 5), (2, 0, 3, 6), (0, 4, 5, 6), (5, 3, 6, 7)),
    ((1, 2, 4, 7), (0, 1, 2, 4), (2, 1, 3, 7), (1, 4, 5, 7), (4, 2, 6, 7)),
)
"""Template t -> its five tetrahedra (corner numbers), each positive on any box (the
central one first, then the corner ones by corner)."""


def check_template(template: int) -> int:
    """``template`` when it is 0 or 1, else PreconditionError."""
    if isinstance(template, bool) or template not in TEMPLATES:
        raise PreconditionError("cuboid", f"the template is 0 or 1, not {template!r}")
    return template


def template_at(i: int, j: int, k: int) -> int:
    """The template of the cuboid at integer position (i, j, k) of a grid of equal cuboids:
    the parity of i + j + k, so that a face's diagonal joins the grid points of even
    coordinate sum, whichever of its two cuboids draws it."""
    return (i + j + k) & 1


def diagonal(face_bit: int, template: int) -> tuple[int, int]:
    """The corners (increasing) of the diagonal of face ``face_bit`` (12..17) in
    ``template``."""
    check_template(template)
    p, q = (k for k in FACE_CORNERS[face_bit - 12] if bin(k).count("1") % 2 == template)
    return p, q


def segment_of(bit: int, template: int) -> tuple[int, int]:
    """The corners (increasing) of the segment whose midpoint is the Steiner point of
    ``bit``: the cube edge (bits 0..11) or the face diagonal (12..17).  It is an edge of the
    initial mesh and stays one until it is split (a split removes only its own edge)."""
    return EDGE_CORNERS[bit] if bit < 12 else diagonal(bit, template)
