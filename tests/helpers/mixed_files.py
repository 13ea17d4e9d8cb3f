"""Mixed-cell meshes and files for the file tests (tests/io/test_mixed_io.py,
tests/cli/test_cli_mixed_files.py): a mesh with a cell of every kind and double
coordinates, an octahedron, splits of a cell, and bad files, each with what its error
says."""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from geomexact.errors import PreconditionError
from geomexact.io.meshio_bridge import meshio_fixed
from geomexact.io.vtk_polyhedra import face_stream, vtu_text
from geomexact.kernel.points import point3
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed import (
    Cell,
    CellKind,
    MixedMesh3,
    box_grid_mesh,
    cell_of_faces,
    mixed_mesh_from_cells,
    standard_cell,
    validate_mixed,
)
from geomexact.mesh3d.mixed.ops import split_cell
from helpers.mixed_view_cases import every_kind_mesh as viewer_every_kind_mesh

UNIT = Box((0, 0, 0), (1, 1, 1))
KINDS = {"tetra": CellKind.TETRA, "pyramid": CellKind.PYRAMID, "wedge": CellKind.WEDGE,
         "hexahedron": CellKind.HEXAHEDRON}
GMSH_WEDGE = (0, 2, 1, 3, 5, 4)  # meshio's wedge is Gmsh's: each triangle reversed


def splits(mesh: MixedMesh3, cell: Cell) -> list[MixedMesh3]:
    """The meshes with ``cell`` split by each plane through three of its vertices that
    splits it (in lexicographic order of the planes)."""
    found = []
    for plane in itertools.combinations(cell.vertices, 3):
        try:
            found.append(split_cell(mesh, cell, plane))
        except PreconditionError:
            continue
    return found


def first_split(mesh: MixedMesh3, cell: Cell) -> MixedMesh3 | None:
    """The first of :func:`splits`, or None."""
    return next(iter(splits(mesh, cell)), None)


def kinds_of(mesh: MixedMesh3) -> set[CellKind]:
    return {cell.kind for cell in mesh.cell_list()}


def every_kind_mesh() -> MixedMesh3:
    """The viewer tests' mesh with every kind of cell (``mixed_view_cases``: thirds and
    sixths) scaled by 6: integer coordinates, which doubles hold exactly."""
    mesh = viewer_every_kind_mesh()
    points = [point3(p.x * 6, p.y * 6, p.z * 6) for p in
              (mesh.point(v) for v in range(mesh.vertex_count))]
    scaled = mixed_mesh_from_cells(points, mesh.cell_list())
    assert not validate_mixed(scaled) and kinds_of(scaled) == set(CellKind)
    return scaled


def octahedron() -> MixedMesh3:
    """One octahedron: a polyhedron of eight triangles."""
    points = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5),
             (0, 3, 5)]
    return mixed_mesh_from_cells(points, [cell_of_faces(faces)])


CUBE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
        (0, 1, 1)]


def write_cells(path: Path, points: Sequence[Sequence[float]], blocks: list[Any]) -> Path:
    """A file of meshio ``blocks`` (polyhedra through geomexact's VTU text)."""
    import meshio
    import numpy as np

    if any(kind.startswith("polyhedron") for kind, _ in blocks):
        types, entries = [], []
        for kind, rows in blocks:
            for row in rows:
                types.append(42 if kind.startswith("polyhedron") else int(KINDS[kind]))
                entries.append(face_stream(row) if kind.startswith("polyhedron") else row)
        rows3 = [tuple(float(c) for c in p) for p in points]
        path.write_text(vtu_text(rows3, types, entries, {}))  # type: ignore[arg-type]
        return path
    meshio.Mesh(np.array(points, dtype=float),
                [(kind, np.array(rows)) for kind, rows in blocks]).write(path)
    return path


def bad_files(tmp_path: Path) -> dict[str, tuple[Path, str]]:
    """Each bad input: (file, what its error says)."""
    bent = [list(p) for p in CUBE]
    bent[6][2] = 1.5  # a top corner lifted: the top face is not planar
    dented = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, -0.5), (0, 0, -1)]
    octahedron_faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5),
                        (3, 1, 5), (0, 3, 5)]
    grid = box_grid_mesh(Box((0, 0, 0), (2, 1, 1)), 2, 1, 1)
    hexahedra = grid.cell_list()
    split = next(mesh for mesh in splits(grid, hexahedra[1])
                 if kinds_of(mesh) == {CellKind.WEDGE, CellKind.POLYHEDRON})  # face cut
    wedges = [cell.vertices for cell in split.cell_list() if cell.kind == CellKind.WEDGE]
    grid_points = [(float(p.x), float(p.y), float(p.z)) for p in
                   (grid.point(v) for v in range(grid.vertex_count))]
    inverted = [4, 5, 6, 7, 0, 1, 2, 3]
    shifted = CUBE + [(x + 1, y, z) for x, y, z in CUBE]
    return {
        "non-planar": (write_cells(tmp_path / "bent.vtu", bent,
                                   [("hexahedron", [list(range(8))])]),
                       "cell 0: non-planar-face"),
        "non-convex": (write_cells(tmp_path / "dented.vtu", dented,
                                   [("polyhedron", [octahedron_faces])]),
                       "cell 0: non-convex-cell"),
        "hanging": (write_cells(tmp_path / "hanging.vtu", grid_points,
                                [("hexahedron", [list(hexahedra[0].vertices)]),
                                 ("wedge", [[w[i] for i in GMSH_WEDGE] for w in wedges])]),
                    "hanging-face"),
        "inverted": (write_cells(tmp_path / "inverted.vtu", shifted,
                                 [("hexahedron", [list(range(8)),
                                                  [8 + i for i in inverted]])]),
                     "cells have mixed orientations: cell 1"),
        "repeated": (write_cells(tmp_path / "twice.vtk", CUBE,
                                 [("hexahedron", [list(range(8)), [1, 2, 3, 0, 5, 6, 7, 4]])]),
                     "cell 1 repeats cell 0"),
        "out of range": (write_cells(tmp_path / "range.vtu", CUBE,
                                     [("pyramid", [[0, 1, 2, 3, 9]])]),
                         "cell 0: vertex 9 is out of range"),
    }


def meshio_cells(path: Path) -> tuple[list[Cell], dict[str, list[int]]]:
    """The cells of ``path`` as meshio reads them (polyhedra readable), canonical, in the
    file's order, and its cell data flattened."""
    import meshio
    import numpy as np

    with meshio_fixed():
        data = meshio.read(path, file_format="gmsh" if path.suffix == ".msh" else None)
    cells: list[Cell] = []
    for block in data.cells:
        if block.type.startswith("polyhedron"):
            cells += [cell_of_faces([[int(v) for v in face] for face in row])
                      for row in block.data]
        else:
            kind = KINDS[block.type]
            for row in block.data.tolist():
                ids = [row[i] for i in GMSH_WEDGE] if kind == CellKind.WEDGE else row
                cells.append(standard_cell(kind, ids))
    arrays = {name: [int(v) for part in parts for v in np.asarray(part).ravel()]
              for name, parts in data.cell_data.items() if not name.startswith("gmsh:")}
    return cells, arrays
