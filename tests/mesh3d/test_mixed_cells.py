"""Mixed cells: the VTK orderings give positive cells, canonical forms do not depend on
how a cell was given (symmetry, rotation, face order), and a cell given by its faces is
recognised as its standard kind."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from geomexact.errors import PreconditionError
from geomexact.kernel.points import point3
from geomexact.mesh3d.mixed.cell_geometry import cell_problems, cell_volume
from geomexact.mesh3d.mixed.cells import (
    KIND_FACES,
    CellKind,
    cell_arguments,
    cell_hash_of,
    cell_of_arguments,
    cell_of_faces,
    reversed_face,
    standard_cell,
    symmetries,
)
from geomexact.mesh3d.snapshot import canonical_tetrahedron

REFERENCE = {
    CellKind.TETRA: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
    CellKind.PYRAMID: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), ("1/2", "1/2", 1)],
    CellKind.WEDGE: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, -1), (1, 0, -1), (0, 1, -1)],
    CellKind.HEXAHEDRON: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
                          (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],
}
"""VTK's reference cells (the wedge's base (0, 1, 2) has its normal pointing away from
(3, 4, 5))."""
VOLUMES = {CellKind.TETRA: "1/6", CellKind.PYRAMID: "1/3", CellKind.WEDGE: "1/2",
           CellKind.HEXAHEDRON: 1}
STANDARD = list(REFERENCE)


@pytest.mark.parametrize("kind", STANDARD)
def test_vtk_reference_cells_are_valid_with_their_volume(kind: CellKind) -> None:
    points = {i: point3(*p) for i, p in enumerate(REFERENCE[kind])}
    cell = standard_cell(kind, range(len(points)))
    assert cell_problems(cell, points) == []
    assert cell_volume(cell, points) == point3(VOLUMES[kind], 0, 0).x


def test_symmetry_counts() -> None:
    counts = {kind: len(symmetries(kind)) for kind in STANDARD}
    assert counts == {CellKind.TETRA: 12, CellKind.PYRAMID: 4, CellKind.WEDGE: 6,
                      CellKind.HEXAHEDRON: 24}


@given(st.sampled_from(STANDARD), st.data())
def test_canonical_form_ignores_the_symmetry_given(kind: CellKind, data: st.DataObject) -> None:
    size = len(REFERENCE[kind])
    ids = data.draw(st.lists(st.integers(0, 50), min_size=size, max_size=size, unique=True))
    symmetry = data.draw(st.sampled_from(symmetries(kind)))
    one = standard_cell(kind, ids)
    other = standard_cell(kind, [ids[p] for p in symmetry])
    assert one == other and hash(one) == hash(other) and cell_hash_of(one) == cell_hash_of(other)


@given(st.sampled_from(STANDARD), st.data())
def test_faces_in_any_order_and_rotation_are_the_same_cell(kind: CellKind,
                                                           data: st.DataObject) -> None:
    size = len(REFERENCE[kind])
    ids = data.draw(st.lists(st.integers(0, 50), min_size=size, max_size=size, unique=True))
    cell = standard_cell(kind, ids)
    faces = data.draw(st.permutations(cell.faces))
    turned = [face[s % len(face):] + face[:s % len(face)]
              for face, s in zip(faces, data.draw(st.lists(st.integers(0, 3), min_size=len(faces),
                                                           max_size=len(faces))), strict=True)]
    assert cell_of_faces(turned) == cell
    assert cell_of_arguments(cell_arguments(cell)) == cell


def test_a_mirrored_cell_is_not_the_same_cell() -> None:
    cell = standard_cell(CellKind.HEXAHEDRON, range(8))
    mirrored = cell_of_faces([reversed_face(face) for face in cell.faces])
    assert mirrored != cell and mirrored.kind == CellKind.HEXAHEDRON


def test_tetra_cells_hash_as_mesh3_tetrahedra() -> None:
    from geomexact.kernel.digest import cell_hash

    cell = standard_cell(CellKind.TETRA, (7, 3, 5, 2))
    assert cell.vertices == canonical_tetrahedron(7, 3, 5, 2)
    assert cell_hash_of(cell) == cell_hash(canonical_tetrahedron(7, 3, 5, 2))


def test_a_polyhedron_keeps_its_faces_canonical() -> None:
    # a cube with its top split into two triangles: no standard kind
    faces = [f for f in KIND_FACES[CellKind.HEXAHEDRON] if f != (4, 5, 6, 7)]
    faces += [(4, 5, 6), (4, 6, 7)]
    cell = cell_of_faces(faces)
    assert cell.kind == CellKind.POLYHEDRON and cell.vertices == tuple(range(8))
    assert cell_of_faces(reversed(faces)) == cell
    assert cell_of_arguments(cell_arguments(cell)) == cell
    points = {i: point3(*p) for i, p in enumerate(REFERENCE[CellKind.HEXAHEDRON])}
    assert cell_problems(cell, points) == [] and cell_volume(cell, points) == 1


@pytest.mark.parametrize("arguments", [(), (10, 1, 2, 3), (99, 1, 2, 3, 4), (10, 1, 1, 2, 3),
                                       (42, 2, 3, 1, 2), (42, 4, 3, 0, 1, 2)])
def test_malformed_cells_are_refused(arguments: tuple[int, ...]) -> None:
    with pytest.raises(PreconditionError):
        cell_of_arguments(arguments)
