"""The batch builder of :class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`: a
:class:`MixedTransient3` opens on a snapshot, takes edits and steps (recording each step
with the digest after it) and is sealed into the next snapshot.  It never escapes the
function that made it."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.points import Point3, point3
from geomexact.mesh3d.mixed.cells import Cell, Face, cell_hash_of, reversed_face, rotated_face
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, empty_mixed_mesh
from geomexact.mesh3d.transient import SpaceTransient
from geomexact.trace.tables import open_table, sealed_table, table_snapshot

__all__ = ["MixedTransient3", "mixed_mesh_from_cells"]


class MixedTransient3(SpaceTransient):
    """Mutable edits on a :class:`MixedMesh3`, the digest kept current (O(1) per
    element), the steps recorded with the digest after each; its steps go through the
    mixed step table (:data:`geomexact.mesh3d.mixed.ops.OPERATIONS`)."""

    __slots__ = ("_cells", "_faces")

    snapshot_type = MixedMesh3

    def __init__(self, mesh: MixedMesh3, *, batch: bool = False) -> None:
        """Open on ``mesh``'s vertices, cells and faces (``batch``: plain dicts,
        :meth:`_open_record`)."""
        self._open_record(mesh.vertices, mesh.digest, batch)
        self._cells = open_table(mesh.cell_hashes, batch)
        self._faces = open_table(mesh.faces, batch)

    # -- reads --------------------------------------------------------------------------
    @property
    def cell_count(self) -> int:
        return len(self._cells)

    def points_of(self, cell: Cell) -> dict[int, Point3]:
        """The points of the cell's vertices (:class:`PreconditionError` for a missing
        one)."""
        return {vertex: self.point(vertex) for vertex in cell.vertices}

    def has_cell(self, cell: Cell) -> bool:
        return cell in self._cells

    def cell_list(self) -> list[Cell]:
        """Every cell now in the transient, sorted (O(n log n))."""
        snapshot, self._cells = table_snapshot(self._cells)
        return sorted(snapshot)

    def cells_with_face(self, face: Sequence[int]) -> tuple[Cell, ...]:
        """The cells having the outward face ``face`` (any rotation)."""
        return self._faces.get(rotated_face(face), ())

    def neighbours(self, face: Sequence[int]) -> tuple[Cell, ...]:
        """The cells on the other side of the outward face ``face``."""
        return self._faces.get(reversed_face(face), ())

    # -- edits --------------------------------------------------------------------------
    def insert_cell(self, cell: Cell) -> None:
        """Add ``cell`` as it is (no geometric check: the steps check before calling);
        :class:`PreconditionError` when it is already there or names a missing vertex."""
        self._check_open()
        if cell in self._cells:
            raise PreconditionError("insert_cell", f"cell {cell} is already in the mesh")
        for vertex in cell.vertices:
            self.point(vertex)
        value = cell_hash_of(cell)
        self._cells[cell] = value
        faces = self._faces
        for face in cell.faces:
            faces[face] = tuple(sorted((*faces.get(face, ()), cell)))
        self._digest = _digest.combine(self._digest, value)

    def delete_cell(self, cell: Cell) -> None:
        """Remove ``cell``; :class:`PreconditionError` when it is not in the mesh."""
        self._check_open()
        value = self._cells.get(cell)
        if value is None:
            raise PreconditionError("delete_cell", f"cell {cell} is not in the mesh")
        del self._cells[cell]
        faces = self._faces
        for face in cell.faces:
            rest = tuple(other for other in faces[face] if other != cell)
            if rest:
                faces[face] = rest
            else:
                del faces[face]
        self._digest = _digest.remove(self._digest, value)

    # -- sealing ------------------------------------------------------------------------
    def seal(self) -> MixedMesh3:
        """Finish the edits and return the new snapshot; the transient is then unusable."""
        self._check_open()
        self._sealed = True
        return MixedMesh3(vertices=sealed_table(self._vertices),
                          cell_hashes=sealed_table(self._cells),
                          faces=sealed_table(self._faces), digest=self._digest)


def mixed_mesh_from_cells(points: Sequence[Point3 | tuple[object, object, object]],
                          cells: Iterable[Cell]) -> MixedMesh3:
    """The snapshot of ``points`` (vertex ids 0..n-1; :class:`Point3` or coordinate
    triples, converted exactly) and ``cells``, taken as they are: a mesh with bad cells
    can be made, and :func:`~geomexact.mesh3d.mixed.validation.validate_mixed` reports
    them.  :class:`PreconditionError` for a vertex out of range or a cell given twice."""
    transient = MixedTransient3(empty_mixed_mesh(), batch=True)
    for raw in points:
        transient.add_vertex(raw if isinstance(raw, Point3) else point3(*raw))
    for cell in cells:
        transient.insert_cell(cell)
    return transient.seal()


def faces_of(cells: Iterable[Cell]) -> dict[Face, list[Cell]]:
    """Outward face -> the cells having it, for ``cells`` (a recomputation of the face
    table)."""
    table: dict[Face, list[Cell]] = {}
    for cell in cells:
        for face in cell.faces:
            table.setdefault(face, []).append(cell)
    return table
