"""The mixed-mesh checker on hand-made bad meshes: one test per kind of violation (a
non-planar quad, a non-convex cell, a quad against two triangles, an inverted cell, a
hole in the boundary, ...), each found exactly, and nothing found on valid meshes."""

from __future__ import annotations

import attrs
import immutables
import pytest
from helpers.mesh3d_cases import cube_grid

from geomexact.errors import InvalidMeshError
from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cells import (
    KIND_FACES,
    Cell,
    CellKind,
    Face,
    cell_of_faces,
    reversed_face,
    standard_cell,
)
from geomexact.mesh3d.mixed.conversion import box_grid_mesh, from_tetrahedral
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import check_mixed, validate_mixed


class Points:
    """Vertex ids handed out by point, in first-use order."""

    def __init__(self) -> None:
        self.points: list[tuple[object, object, object]] = []

    def __call__(self, x: object, y: object, z: object) -> int:
        key = (mpq(x), mpq(y), mpq(z))  # type: ignore[call-overload]
        if key not in self.points:
            self.points.append(key)
        return self.points.index(key)


def box_cell(ids: Points, low: tuple[int, int, int], high: tuple[int, int, int]) -> Cell:
    (x0, y0, z0), (x1, y1, z1) = low, high
    corners = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
               (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    return standard_cell(CellKind.HEXAHEDRON, [ids(*c) for c in corners])


def kinds(mesh: MixedMesh3, volume: object = None) -> list[str]:
    return [v.kind for v in validate_mixed(mesh, volume=volume)]  # type: ignore[arg-type]


def test_valid_meshes_have_no_violation() -> None:
    box = Box((0, 0, 0), (1, "1/2", 3))
    assert validate_mixed(box_grid_mesh(box, 2, 3, 1), volume=box.volume) == []
    assert validate_mixed(from_tetrahedral(cube_grid(1, 2, 1)), volume=2) == []
    assert check_mixed(box_grid_mesh(box, 1, 1, 1)) is not None


def test_a_non_planar_quad() -> None:
    ids = Points()
    cell = box_cell(ids, (0, 0, 0), (1, 1, 1))
    points = list(ids.points)
    points[ids(1, 1, 1)] = (1, 1, "3/2")  # the top quad is no longer planar
    mesh = mixed_mesh_from_cells(points, [cell])
    assert set(kinds(mesh)) == {"non-planar-face"}
    with pytest.raises(InvalidMeshError, match="non-planar-face"):
        check_mixed(mesh)


def test_a_non_convex_cell_with_planar_faces() -> None:
    # a triangular pyramid whose bottom is dented: the second apex is above the base
    points = [(0, 0, 0), (3, 0, 0), (0, 3, 0), (1, 1, 3), (1, 1, 1)]
    faces = [(0, 1, 3), (1, 2, 3), (2, 0, 3), (1, 0, 4), (2, 1, 4), (0, 2, 4)]
    mesh = mixed_mesh_from_cells(points, [cell_of_faces(faces)])
    assert kinds(mesh) == ["non-convex-cell"]


def test_a_non_convex_face() -> None:
    ell = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]  # an L: (1, 1) is reflex
    points = [(x, y, 0) for x, y in ell] + [(x, y, 1) for x, y in ell]
    faces: list[Face] = [(5, 4, 3, 2, 1, 0), (6, 7, 8, 9, 10, 11)]
    faces += [(i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6) for i in range(6)]
    mesh = mixed_mesh_from_cells(points, [cell_of_faces(faces)])
    assert kinds(mesh) == ["non-convex-face", "non-convex-face"]


def test_a_quad_against_two_triangles_is_a_hanging_face() -> None:
    ids = Points()
    left = box_cell(ids, (0, 0, 0), (1, 1, 1))
    right = box_cell(ids, (1, 0, 0), (2, 1, 1))
    shared = next(f for f in right.faces if reversed_face(f) in left.faces)
    a, b, c, d = shared
    split = cell_of_faces([f for f in right.faces if f != shared] + [(a, b, c), (a, c, d)])
    mesh = mixed_mesh_from_cells(ids.points, [left, split])
    assert kinds(mesh, 2) == ["hanging-face"]
    assert validate_mixed(mixed_mesh_from_cells(ids.points, [left, right]), volume=2) == []


def test_a_quad_against_four_quads_with_one_missing_leaves_a_hole() -> None:
    ids = Points()
    big = box_cell(ids, (0, 0, 0), (2, 2, 2))
    small = [box_cell(ids, (2, y, z), (3, y + 1, z + 1)) for y in (0, 1) for z in (0, 1)]
    full = mixed_mesh_from_cells(ids.points, [big, *small])
    assert kinds(full, 12) == ["hanging-face"]
    holed = mixed_mesh_from_cells(ids.points, [big, *small[:3]])
    found = kinds(holed, 12)
    assert "hanging-face" in found and "open-boundary" in found and "volume-mismatch" in found


def test_an_inverted_cell() -> None:
    ids = Points()
    left = box_cell(ids, (0, 0, 0), (1, 1, 1))
    right = box_cell(ids, (1, 0, 0), (2, 1, 1))
    inverted = cell_of_faces([reversed_face(f) for f in right.faces])
    mesh = mixed_mesh_from_cells(ids.points, [left, inverted])
    # its outward faces now run along the left cube's: the boundary touches itself too
    assert kinds(mesh)[:2] == ["non-positive-volume", "face-orientation"]
    assert set(kinds(mesh)[2:]) == {"non-manifold-edge"}


def test_a_face_of_three_cells() -> None:
    ids = Points()
    left = box_cell(ids, (0, 0, 0), (1, 1, 1))
    right = box_cell(ids, (1, 0, 0), (2, 1, 1))
    shared = next(f for f in right.faces if reversed_face(f) in left.faces)
    apex = ids(3, "1/2", "1/2")
    a, b, c, d = shared
    pyramid = cell_of_faces([shared, (b, a, apex), (c, b, apex), (d, c, apex), (a, d, apex)])
    mesh = mixed_mesh_from_cells(ids.points, [left, right, pyramid])
    assert "non-manifold-face" in kinds(mesh)


def test_cells_touching_along_an_edge_only() -> None:
    ids = Points()
    cells = [box_cell(ids, (0, 0, 0), (1, 1, 1)), box_cell(ids, (1, 1, 0), (2, 2, 1))]
    assert kinds(mixed_mesh_from_cells(ids.points, cells)) == ["non-manifold-edge"] * 2


def test_an_open_cell_and_coincident_vertices() -> None:
    hexahedron = KIND_FACES[CellKind.HEXAHEDRON]
    cube = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    vtk = [cube[i] for i in (0, 1, 3, 2, 4, 5, 7, 6)]
    open_cell = cell_of_faces(hexahedron[1:])
    found = kinds(mixed_mesh_from_cells(vtk, [open_cell]))
    assert found[0] == "cell-surface" and set(found[1:]) == {"open-boundary"}
    flat = standard_cell(CellKind.TETRA, (0, 1, 2, 3))
    found = kinds(mixed_mesh_from_cells([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 0, 0)], [flat]))
    assert found[0] == "coincident-vertices"  # then its two flat faces overlap: hanging


def test_a_wrong_volume_digest_and_face_table() -> None:
    box = Box((0, 0, 0), (2, 1, 1))
    mesh = box_grid_mesh(box, 2, 1, 1)
    assert kinds(mesh, 3) == ["volume-mismatch"]
    assert kinds(attrs.evolve(mesh, digest=mesh.digest ^ 1)) == ["digest"]
    assert kinds(attrs.evolve(mesh, faces=immutables.Map())) == ["adjacency"]
    missing = attrs.evolve(mesh, vertices=mesh.vertices.delete(0))
    assert kinds(missing)[:2] == ["vertex-ids", "missing-vertex"]
