"""The mixed-cell mesh value :class:`MixedMesh3`: exact points and canonical cells
(tetrahedra, pyramids, wedges, hexahedra, convex polyhedra), with an incremental content
digest and a face table from which adjacency is read.  Immutable; a step builds the next
snapshot in O(k log n) for k cells touched and shares the rest.  Specification:
``specs/mixed.md``."""

from __future__ import annotations

from typing import TYPE_CHECKING

import attrs
import immutables

from geomexact.kernel import digest as _digest
from geomexact.kernel.derived import Derived
from geomexact.kernel.numbers import ZERO, Rational
from geomexact.kernel.points import Point3
from geomexact.mesh3d.mixed.cell_geometry import cell_volume
from geomexact.mesh3d.mixed.cells import (
    Cell,
    Face,
    cell_arguments,
    cell_hash_of,
    reversed_face,
    rotated_face,
)
from geomexact.trace.protocols import kind_of

if TYPE_CHECKING:
    from geomexact.mesh3d.mixed.transient import MixedTransient3

__all__ = ["MixedMesh3", "empty_mixed_mesh", "full_mixed_digest", "mixed_volume"]


@attrs.frozen(slots=True, eq=False)
class MixedMesh3:
    """An immutable mesh of mixed cells with exact rational vertices.

    Tables (persistent maps):

    - ``vertices``: id -> :class:`Point3`, ids 0..n-1 in insertion order;
    - ``cell_hashes``: canonical :class:`Cell` -> its hash in the digest (the cells);
    - ``faces``: outward face rotated to its smallest id -> the cells having it (sorted;
      one in a valid mesh).  An interior face is a key in both orientations, a boundary
      face in one;

    plus the content ``digest``: the sum mod 2^128 of the vertex hashes and cell hashes.
    """

    vertices: immutables.Map[int, Point3]
    cell_hashes: immutables.Map[Cell, int]
    faces: immutables.Map[Face, tuple[Cell, ...]]
    digest: int
    _derived: Derived = attrs.field(init=False, factory=Derived, eq=False, repr=False)
    """Values derived from the tables, kept once computed
    (:class:`~geomexact.kernel.derived.Derived`): never content."""

    @property
    def vertex_count(self) -> int:
        return len(self.vertices)

    @property
    def cell_count(self) -> int:
        return len(self.cell_hashes)

    @property
    def digest_text(self) -> str:
        return _digest.digest_text(self.digest)

    def transient(self, *, batch: bool = False) -> MixedTransient3:
        """A batch builder on this snapshot (the snapshot itself never changes)."""
        transient: MixedTransient3 = kind_of(MixedMesh3).transient(self, batch=batch)
        return transient

    def point(self, vertex: int) -> Point3:
        return self.vertices[vertex]

    def cell_list(self) -> list[Cell]:
        """Every cell, sorted (kept once computed)."""
        cells: list[Cell] = self._derived.get("cells", lambda: sorted(self.cell_hashes))
        return list(cells)

    def has_cell(self, cell: Cell) -> bool:
        return cell in self.cell_hashes

    def cells_with_face(self, face: Face) -> tuple[Cell, ...]:
        """The cells having the outward face ``face`` (any rotation)."""
        return self.faces.get(rotated_face(face), ())

    def neighbours(self, cell: Cell, face: Face) -> tuple[Cell, ...]:
        """The cells across ``face`` of ``cell``: those having it with the other
        orientation (one for an interior face, none on the boundary)."""
        return self.faces.get(reversed_face(face), ())

    def boundary_faces(self) -> list[Face]:
        """The outward faces with no cell on their other side, sorted."""
        faces = self.faces
        return sorted(face for face in faces if reversed_face(face) not in faces)

    def interior_faces(self) -> list[Face]:
        """Each face with cells on both sides once, in the orientation that is the smaller
        key, sorted."""
        faces = self.faces
        return sorted(face for face in faces
                      if face < reversed_face(face) and reversed_face(face) in faces)

    def cells(self) -> list[tuple[int, ...]]:
        """The cells as sorted int tuples (their step arguments): what the trace tools
        compare between steps (:class:`~geomexact.trace.protocols.CellSnapshot`)."""
        return sorted(cell_arguments(cell) for cell in self.cell_hashes)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MixedMesh3):
            return NotImplemented
        return (self.digest == other.digest and self.vertices == other.vertices
                and self.cell_hashes == other.cell_hashes)

    def __hash__(self) -> int:
        return hash(self.digest)

    def __repr__(self) -> str:
        return (f"MixedMesh3(vertices={self.vertex_count}, cells={self.cell_count}, "
                f"digest={self.digest_text})")


def empty_mixed_mesh() -> MixedMesh3:
    """The mesh with no vertices and no cells (digest 0)."""
    return MixedMesh3(vertices=immutables.Map(), cell_hashes=immutables.Map(),
                      faces=immutables.Map(), digest=0)


def full_mixed_digest(mesh: MixedMesh3) -> int:
    """The digest recomputed from the content (``validate_mixed`` compares it with
    ``digest``)."""
    total = 0
    for vertex, point in mesh.vertices.items():
        total = _digest.combine(total, _digest.vertex_hash(vertex, point[:3]))
    for cell in mesh.cell_hashes:
        total = _digest.combine(total, cell_hash_of(cell))
    return total


def mixed_volume(mesh: MixedMesh3) -> Rational:
    """The exact sum of the cells' volumes."""
    total = ZERO
    for cell in mesh.cell_list():
        total += cell_volume(cell, mesh.vertices)
    return total
