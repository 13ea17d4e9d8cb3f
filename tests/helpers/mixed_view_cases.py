"""A small mixed mesh with every kind of cell, for the viewer and picture tests: a 3 x 3 x 2
box grid of hexahedra in which one hexahedron is split into two wedges and one of them
into a tetrahedron and a pyramid, two hexahedra are merged into a polyhedron, a corner of
another is cut off (a tetrahedron and a polyhedron), and a pentagonal prism (a polyhedron
with two pentagons) stands on the grid's top."""

from __future__ import annotations

from itertools import combinations

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point3
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cells import Cell, CellKind, cell_of_faces, polygon_key
from geomexact.mesh3d.mixed.conversion import box_grid_mesh
from geomexact.mesh3d.mixed.ops import merge_cells, split_cell
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed

NX, NY, NZ = 3, 3, 2


def _vertex(i: int, j: int, k: int) -> int:
    return (i * (NY + 1) + j) * (NZ + 1) + k


def _hexahedron(mesh: MixedMesh3, i: int, j: int, k: int) -> Cell:
    corners = {_vertex(i + a, j + b, k + c) for a in (0, 1) for b in (0, 1) for c in (0, 1)}
    return next(cell for cell in mesh.cell_list() if set(cell.vertices) == corners)


def _split_into(mesh: MixedMesh3, cell: Cell, kinds: set[CellKind],
                keep: CellKind | None = None) -> MixedMesh3:
    """Split ``cell`` by the first plane through three of its vertices (sorted) that gives
    pieces of ``kinds`` (and leaves a cell of kind ``keep`` in the mesh)."""
    for plane in combinations(sorted(cell.vertices), 3):
        try:
            after = split_cell(mesh, cell, plane)
        except PreconditionError:
            continue
        new = set(after.cell_list()) - set(mesh.cell_list())
        pieces = {piece.kind for piece in new if set(piece.vertices) <= set(cell.vertices)}
        if pieces == kinds and (keep is None or any(c.kind == keep
                                                    for c in after.cell_list())):
            return after
    raise AssertionError(f"no plane splits {cell} into {kinds}")


def _with_pentagonal_prism(mesh: MixedMesh3) -> MixedMesh3:
    """``mesh`` with a pentagonal prism on the top face of the hexahedron (0, 0, 1)."""
    third, sixth = mpq(1, 3), mpq(1, 6)
    points = [mesh.point(v) for v in range(mesh.vertex_count)]
    # the pentagon in the xz plane, counter-clockwise seen from -y; its base on z = 1
    pentagon = [(0, 1), (third, 1), (third, 1 + sixth), (sixth, 1 + third), (0, 1 + sixth)]
    ids: dict[tuple[int, int], int] = {}
    for side, y in enumerate((mpq(0), third)):
        for corner, (x, z) in enumerate(pentagon):
            if z == 1:
                ids[side, corner] = _vertex(0 if x == 0 else 1, side, NZ)
            else:
                ids[side, corner] = len(points)
                points.append(point3(x, y, z))
    front = [ids[0, c] for c in range(5)]
    back = [ids[1, c] for c in reversed(range(5))]
    sides = [[ids[0, c], ids[1, c], ids[1, (c + 1) % 5], ids[0, (c + 1) % 5]]
             for c in range(5)]
    prism = cell_of_faces([front, back, *sides])
    result = mixed_mesh_from_cells(points, [*mesh.cell_list(), prism])
    if validate_mixed(result):  # the other orientation
        prism = cell_of_faces([face[::-1] for face in [front, back, *sides]])
        result = mixed_mesh_from_cells(points, [*mesh.cell_list(), prism])
    return result


def every_kind_mesh() -> MixedMesh3:
    """The mesh of this module's docstring: valid, of volume 1 + 1/36 (the prism)."""
    mesh = box_grid_mesh(Box((0, 0, 0), (1, 1, 1)), NX, NY, NZ)
    mesh = _split_into(mesh, _hexahedron(mesh, 2, 2, 0), {CellKind.WEDGE})
    wedge = next(c for c in mesh.cell_list() if c.kind == CellKind.WEDGE)
    mesh = _split_into(mesh, wedge, {CellKind.TETRA, CellKind.PYRAMID}, keep=CellKind.WEDGE)
    first, second = _hexahedron(mesh, 0, 0, 0), _hexahedron(mesh, 1, 0, 0)
    shared = next(f for f in first.faces if polygon_key(f) in
                  {polygon_key(g) for g in second.faces})
    mesh = merge_cells(mesh, shared)
    mesh = _split_into(mesh, _hexahedron(mesh, 0, 2, 1), {CellKind.TETRA, CellKind.POLYHEDRON})
    return _with_pentagonal_prism(mesh)
