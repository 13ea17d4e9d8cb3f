"""Integer cell data read back (:func:`geomexact.io.cell_arrays.read_cell_arrays`): aligned
with the cells of the mesh ``io.read`` gives, whatever order and orientation the file
holds them in; Gmsh's doubles count when integral; other arrays and formats give none."""

from __future__ import annotations

import random
from pathlib import Path

import numpy as np
import pytest
from helpers.mesh3d_cases import cube_grid
from helpers.mixed_files import every_kind_mesh

from geomexact import io
from geomexact.errors import FormatError
from geomexact.io.cell_arrays import material_array, read_cell_arrays
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.cells import CellKind, standard_cell
from geomexact.mesh3d.mixed.conversion import box_grid_mesh
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.snapshot import Mesh3

meshio = pytest.importorskip("meshio")


def _label(vertices: object) -> int:
    """A value that depends on a cell's vertex set only (what the file must give back)."""
    ids = sorted(vertices)  # type: ignore[call-overload]
    return 7 * ids[0] + ids[-1] - 1000


def _shuffled_tetra_file(path: Path, mesh: Mesh3, seed: int) -> Path:
    """``mesh``'s tetrahedra in a random order, each turned negative (two corners
    swapped: the reader mirrors all of them), with ``material`` by vertex set, a float
    ``quality`` and a vector ``normal`` array, and a boundary triangle block first."""
    rng = random.Random(seed)
    rows = [list(t) for t in mesh.tetrahedra()]
    rng.shuffle(rows)
    rows = [[b, a, c, d] for a, b, c, d in rows]
    points = np.array([[float(p.x), float(p.y), float(p.z)]
                       for p in (mesh.point(v) for v in range(mesh.vertex_count))])
    triangles = np.array([list(face) for face in mesh.boundary_faces()][:3])
    cells = [("triangle", triangles), ("tetra", np.array(rows))]
    cell_data = {
        "material": [np.zeros(len(triangles), dtype=np.int32),
                     np.array([_label(r) for r in rows], dtype=np.int32)],
        "quality": [np.zeros(len(triangles)), np.full(len(rows), 0.5)],
        "normal": [np.zeros((len(triangles), 3)), np.zeros((len(rows), 3))],
    }
    meshio.Mesh(points, cells, cell_data=cell_data).write(path)
    return path


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_tetrahedra_in_any_order_are_aligned(tmp_path: Path, suffix: str) -> None:
    """Shuffled, mirrored tetrahedra: each of ``mesh.tetrahedra()`` gets its own value;
    only the integer one-component array is returned."""
    path = _shuffled_tetra_file(tmp_path / f"grid{suffix}", cube_grid(2, 2, 1), seed=3)
    mesh = io.read(path)
    assert isinstance(mesh, Mesh3)
    arrays = read_cell_arrays(path)
    assert set(arrays) == {"material"}
    assert arrays["material"].dtype == np.int64
    assert arrays["material"].tolist() == [_label(t) for t in mesh.tetrahedra()]
    assert read_cell_arrays(path, mesh=mesh)["material"].tolist() == \
        arrays["material"].tolist()


def _mixed_with_labels(mesh: MixedMesh3) -> MixedMeshData:
    return MixedMeshData(mesh, {"material": [_label(c.vertices) for c in mesh.cell_list()],
                                "big": [2**40 + i for i in range(mesh.cell_count)]})


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_mixed_cells_with_polyhedra_are_aligned(tmp_path: Path, suffix: str) -> None:
    """Every kind of cell, polyhedra too: the arrays follow ``cell_list()``; ``kind``
    gives each cell's VTK type."""
    mesh = every_kind_mesh()
    path = tmp_path / f"every{suffix}"
    io.write(path, _mixed_with_labels(mesh))
    read = io.read(path)
    assert isinstance(read, MixedMesh3)
    arrays = read_cell_arrays(path)
    assert arrays["material"].tolist() == [_label(c.vertices) for c in read.cell_list()]
    assert arrays["kind"].tolist() == [int(c.kind) for c in read.cell_list()]
    assert arrays["big"].min() >= 2**40


def _tetrahedra_as_mixed(mesh: Mesh3) -> MixedMesh3:
    points = [mesh.point(v) for v in range(mesh.vertex_count)]
    return mixed_mesh_from_cells(points, [standard_cell(CellKind.TETRA, list(t))
                                          for t in mesh.tetrahedra()])


@pytest.mark.parametrize("case", ["hexahedra", "tetrahedra"])
def test_gmsh_doubles_read_as_integers(tmp_path: Path, case: str) -> None:
    """Gmsh 2.2 keeps cell data as doubles: integral ones come back as int64, aligned with
    a mixed mesh's cells or, tetrahedra only, with the ``Mesh3`` the file reads as; the
    all-zero ``gmsh:physical`` meshio adds is no material array."""
    mesh = (box_grid_mesh(Box((0, 0, 0), (2, 3, 1)), 2, 3, 1) if case == "hexahedra"
            else _tetrahedra_as_mixed(cube_grid(2, 1, 1)))
    path = tmp_path / "part.msh"
    io.write(path, _mixed_with_labels(mesh))
    read = io.read(path)
    arrays = read_cell_arrays(path)
    assert arrays["material"].dtype == np.int64
    cells = (read.cell_list() if isinstance(read, MixedMesh3) else read.tetrahedra())
    assert isinstance(read, MixedMesh3 if case == "hexahedra" else Mesh3)
    assert arrays["material"].tolist() == [
        _label(c.vertices if isinstance(read, MixedMesh3) else c) for c in cells]
    assert not arrays["gmsh:physical"].any()
    assert material_array({"gmsh:physical": arrays["gmsh:physical"]}) is None
    assert material_array(arrays)[0] == "material"  # type: ignore[index]


def test_material_array_takes_the_first_name() -> None:
    region, material = np.array([1]), np.array([2])
    assert material_array({"region": region, "material": material}) == \
        ("material", material)
    assert material_array({"region": region})[0] == "region"  # type: ignore[index]
    assert material_array({"kind": region}) is None


def test_formats_without_cell_data_and_2d_files(tmp_path: Path) -> None:
    """A tetgen ``.ele`` has no cell data here: ``{}``; a 2D meshio file is refused."""
    path = tmp_path / "grid.ele"
    io.write(path, cube_grid(1, 1, 1))
    assert read_cell_arrays(path) == {}
    flat = tmp_path / "flat.vtu"
    meshio.Mesh(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]),
                [("triangle", np.array([[0, 1, 2]]))],
                cell_data={"material": [np.array([4])]}).write(flat)
    with pytest.raises(FormatError, match="tetrahedral and mixed-cell"):
        read_cell_arrays(flat)
