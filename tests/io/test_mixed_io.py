"""Mixed-cell meshes through files (issue 23, item 5): .vtu, .vtk and .msh round trips
compared cell by cell and by digest, cell data, the refusals of writing, and every bad
input read as a FormatError naming the file's cell (specs/formats/meshio.md)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import io
from geomexact.errors import FormatError, OverwriteError, PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed import (
    CellKind,
    MixedMesh3,
    MixedMeshData,
    box_grid_mesh,
    mixed_mesh_from_cells,
    standard_cell,
    validate_mixed,
)
from geomexact.mesh3d.mixed.ops import split_cell
from geomexact.mesh3d.snapshot import Mesh3

meshio = pytest.importorskip("meshio")
np = pytest.importorskip("numpy")

from helpers.mixed_files import (  # noqa: E402
    CUBE,
    UNIT,
    bad_files,
    every_kind_mesh,
    first_split,
    kinds_of,
    meshio_cells,
    octahedron,
    splits,
    write_cells,
)


def assert_same(back: Any, mesh: MixedMesh3) -> None:
    assert isinstance(back, MixedMesh3)
    assert back == mesh and back.digest == mesh.digest
    assert back.cell_list() == mesh.cell_list()


@pytest.mark.parametrize("suffix", [".vtu", ".vtk", ".msh"])
def test_box_grid_round_trips(tmp_path: Path, suffix: str) -> None:
    """A box grid written and read back is the same mesh; meshio reads the same cells in
    cell_list() order, with kind 12 each."""
    mesh = box_grid_mesh(Box((0, 0, 0), (1, "1.5", "0.75")), 2, 3, 2)
    path = tmp_path / f"grid{suffix}"
    report = io.write_with_report(path, mesh)
    assert report.rounded == 0 and report.paths == (path,)
    back, notes = io.read_with_notes(path)
    assert_same(back, mesh)
    assert notes == []
    cells, arrays = meshio_cells(path)
    assert cells == mesh.cell_list()
    assert arrays == {"kind": [12] * 12}


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_every_kind_round_trips(tmp_path: Path, suffix: str) -> None:
    """A mesh of tetra, pyramid, wedge, hexahedron and polyhedron cells, with a level
    array, round-trips exactly; meshio reads the same cells and arrays in order."""
    mesh = every_kind_mesh()
    levels = list(range(3, 3 + mesh.cell_count))
    path = tmp_path / f"every{suffix}"
    io.write(path, MixedMeshData(mesh, {"level": levels}))
    assert_same(io.read(path), mesh)
    cells, arrays = meshio_cells(path)
    assert cells == mesh.cell_list()
    assert arrays == {"kind": [int(cell.kind) for cell in cells], "level": levels}


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_octahedron_round_trips(tmp_path: Path, suffix: str) -> None:
    """A lone polyhedron (a grid of polyhedra only) round-trips."""
    mesh = octahedron()
    assert mesh.cell_list()[0].kind == CellKind.POLYHEDRON and not validate_mixed(mesh)
    io.write(tmp_path / f"o{suffix}", mesh)
    assert_same(io.read(tmp_path / f"o{suffix}"), mesh)


def test_standard_kinds_round_trip_through_msh(tmp_path: Path) -> None:
    """Without polyhedra the mesh goes to Gmsh text, its levels as ElementData."""
    halves = first_split(box_grid_mesh(UNIT, 1, 1, 1), box_grid_mesh(UNIT, 1, 1, 1)
                         .cell_list()[0])
    assert halves is not None
    mesh = next(split for split in splits(halves, halves.cell_list()[0])
                if CellKind.POLYHEDRON not in kinds_of(split))
    assert kinds_of(mesh) == {CellKind.TETRA, CellKind.PYRAMID, CellKind.WEDGE}
    path = tmp_path / "m.msh"
    io.write(path, MixedMeshData(mesh, {"level": [7] * mesh.cell_count}))
    assert_same(io.read(path), mesh)
    cells, arrays = meshio_cells(path)
    assert cells == mesh.cell_list() and arrays["level"] == [7] * mesh.cell_count


def test_msh_refuses_polyhedra(tmp_path: Path) -> None:
    """Gmsh has no polyhedron: a clear error naming the file, nothing written."""
    path = tmp_path / "p.msh"
    with pytest.raises(FormatError, match=r"p\.msh: Gmsh \.msh has no polyhedron cells") as e:
        io.write(path, every_kind_mesh())
    assert "\n" not in str(e.value)
    assert os.listdir(tmp_path) == []


def test_write_refusals(tmp_path: Path) -> None:
    """Exact numbers refused, an existing file kept, formats other than .vtu, .vtk and .msh
    refused; rounding counted like the Mesh3 writer's."""
    mesh = box_grid_mesh(Box((0, 0, 0), (1, "1/3", 1)), 1, 1, 1)
    with pytest.raises(FormatError, match="cannot hold exact numbers"):
        io.write(tmp_path / "a.vtu", mesh, numbers="exact")
    with pytest.raises(FormatError, match=r"written as \.vtu, \.vtk, \.msh only"):
        io.write(tmp_path / "a.ply", mesh)
    report = io.write_with_report(tmp_path / "a.vtu", mesh)
    assert report.rounded == 4  # y = 1/3 at four corners
    with pytest.raises(OverwriteError):
        io.write(tmp_path / "a.vtu", mesh)
    assert sorted(os.listdir(tmp_path)) == ["a.vtu"]


def test_cell_data_record_checks() -> None:
    """Arrays are one int per cell, named usably, never ``kind``."""
    mesh = box_grid_mesh(UNIT, 2, 1, 1)
    data = MixedMeshData(mesh, {"level": [np.int64(2), 3]})
    assert data.cell_data == {"level": (2, 3)}
    for arrays, problem in [({"level": [1]}, "1 values for 2 cells"),
                            ({"kind": [1, 2]}, "written by the writers"),
                            ({"a b": [1, 2]}, "not a usable array name"),
                            ({"level": [1.5, 2]}, "not integers")]:
        with pytest.raises(PreconditionError, match=problem):
            MixedMeshData(mesh, arrays)


def test_tetrahedra_only_still_read_as_mesh3(tmp_path: Path) -> None:
    """A file of tetra cells is a Mesh3 as before; tetra beside a hexahedron is mixed (and
    checked: a hexahedron against the tetrahedra's triangulated face hangs)."""
    cube = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
            (0, 1, 1)]
    tetrahedra = [(0, 1, 3, 4), (1, 2, 3, 6), (1, 4, 5, 6), (3, 4, 6, 7), (1, 3, 4, 6)]
    points = np.array(cube + [(x + 1, y, z) for x, y, z in cube], dtype=float)
    meshio.Mesh(points[:8], [("tetra", np.array(tetrahedra))]).write(tmp_path / "t.vtu")
    assert isinstance(io.read(tmp_path / "t.vtu"), Mesh3)
    apart = np.array(cube + [(x + 2, y, z) for x, y, z in cube], dtype=float)
    meshio.Mesh(apart, [("tetra", np.array(tetrahedra)),
                        ("hexahedron", np.array([list(range(8, 16))]))]
                ).write(tmp_path / "h.vtu")
    mixed = io.read(tmp_path / "h.vtu")
    assert isinstance(mixed, MixedMesh3) and mixed.cell_count == 6
    meshio.Mesh(points, [("tetra", np.array(tetrahedra)),
                         ("hexahedron", np.array([[1, 9, 10, 2, 5, 13, 14, 6]]))]
                ).write(tmp_path / "touch.vtu")
    with pytest.raises(FormatError, match="cell 5: hanging-face"):
        io.read(tmp_path / "touch.vtu")


# -----------------------------------------------------------------------------------------
# bad files
# -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("case", ["non-planar", "non-convex", "hanging", "inverted",
                                  "repeated", "out of range"])
def test_bad_files_are_format_errors(tmp_path: Path, case: str) -> None:
    """Each bad file is one FormatError naming the file and the cell, never a mesh."""
    path, problem = bad_files(tmp_path)[case]
    with pytest.raises(FormatError) as error:
        io.read(path)
    assert str(error.value).startswith(f"{path}: ") and problem in str(error.value)


def test_all_inverted_cells_are_mirrored_with_a_note(tmp_path: Path) -> None:
    """A file whose every cell is inverted (the other handedness) is read mirrored, with
    a note, as the tetrahedral readers do."""
    path = write_cells(tmp_path / "mirror.vtu", CUBE,
                       [("hexahedron", [[4, 5, 6, 7, 0, 1, 2, 3]])])
    mesh, notes = io.read_with_notes(path)
    assert_same(mesh, mixed_mesh_from_cells(CUBE, [standard_cell(CellKind.HEXAHEDRON,
                                                                 range(8))]))
    assert notes == ["the only cell was inverted (negative volume); mirrored it"]


def test_broken_face_stream_is_a_format_error(tmp_path: Path) -> None:
    """A polyhedron whose face stream overruns its cell: meshio cannot read it."""
    path = tmp_path / "broken.vtk"
    from geomexact.io.vtk_polyhedra import legacy_vtk_text

    path.write_text(legacy_vtk_text([(0.0, 0.0, 0.0)] * 4, [42], [[4, 3, 0, 1, 2, 3, 0]],
                                    {}))
    with pytest.raises(FormatError, match="meshio cannot read it: a polyhedron's face stream"):
        io.read(path)


# -----------------------------------------------------------------------------------------
# property
# -----------------------------------------------------------------------------------------
@st.composite
def split_grids(draw: st.DrawFn) -> MixedMesh3:
    """A box grid of 1 to 2 cells a side, then up to 4 random splits."""
    sizes = [draw(st.integers(1, 2)) for _ in range(3)]
    mesh = box_grid_mesh(Box((0, 0, 0), (1, "0.5", 2)), *sizes)
    for _ in range(draw(st.integers(0, 4))):
        cells = mesh.cell_list()
        cell = cells[draw(st.integers(0, len(cells) - 1))]
        plane = draw(st.lists(st.sampled_from(cell.vertices), min_size=3, max_size=3,
                              unique=True))
        try:
            mesh = split_cell(mesh, cell, plane)
        except PreconditionError:
            continue
    return mesh


@settings(max_examples=25, deadline=None)
@given(split_grids(), st.sampled_from([".vtu", ".vtk", ".msh"]))
def test_split_grids_round_trip(tmp_path_factory: pytest.TempPathFactory, mesh: MixedMesh3,
                                suffix: str) -> None:
    """Random box grids with random splits read back as the same mesh (Gmsh: when they
    have no polyhedron)."""
    if suffix == ".msh" and any(c.kind == CellKind.POLYHEDRON for c in mesh.cell_list()):
        suffix = ".vtu"
    path = tmp_path_factory.mktemp("split") / f"m{suffix}"
    io.write(path, mesh)
    assert_same(io.read(path), mesh)
