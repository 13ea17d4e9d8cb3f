"""Nothing dropped or rounded away silently (issue 27, item 3): solid cells geomexact does
not read, coordinates that round to the same double, and a census written under a
Parquet name are refusals (exit 2, nothing written), not warnings."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from helpers.command import run

meshio = pytest.importorskip("meshio")
np = pytest.importorskip("numpy")


def _hex_and_tetrahedra(path: Path) -> None:
    """One hexahedron beside five tetrahedra (a unit cube's), as meshio writes them."""
    cube = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1),
            (0, 1, 1)]
    shifted = [(x + 2, y, z) for x, y, z in cube]
    tetrahedra = [(0, 1, 3, 4), (1, 2, 3, 6), (1, 4, 5, 6), (3, 4, 6, 7), (1, 3, 4, 6)]
    mesh = meshio.Mesh(np.array(cube + shifted, dtype=float),
                       [("tetra", np.array(tetrahedra)),
                        ("hexahedron", np.array([list(range(8, 16))]))])
    mesh.write(path)


def test_convert_refuses_a_file_with_hexahedra(capsys: pytest.CaptureFixture[str],
                                               tmp_path: Path) -> None:
    """convert hex.vtu out.ele: exit 2, and no file written (it wrote the 5 tetrahedra
    and exited 0); the file is a mixed-cell mesh, which .ele cannot hold."""
    source = tmp_path / "hex.vtu"
    _hex_and_tetrahedra(source)
    code, out, err = run(capsys, "convert", source, tmp_path / "out.ele")
    assert code == 2 and out == ""
    assert "not a mixed mesh" in err
    assert sorted(os.listdir(tmp_path)) == ["hex.vtu"]


def test_boundary_triangles_of_a_tetrahedral_file_are_still_ignored(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """Triangles beside tetrahedra are the boundary (Gmsh writes them): read, noted."""
    points = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], dtype=float)
    meshio.Mesh(points, [("tetra", np.array([[0, 1, 2, 3]])),
                         ("triangle", np.array([[0, 2, 1]]))]).write(tmp_path / "t.vtu")
    code, _, _ = run(capsys, "convert", tmp_path / "t.vtu", tmp_path / "t.ele")
    assert code == 0 and (tmp_path / "t.ele").exists()


def test_coordinates_that_round_together_are_refused(capsys: pytest.CaptureFixture[str],
                                                     tmp_path: Path) -> None:
    """Coordinates near 1e-400 all round to 0 in a VTU: exit 2, nothing written (it wrote
    every vertex as 0 and exited 0 with a warning)."""
    source = tmp_path / "tiny.off"
    source.write_text("OFF\n3 1 0\n0 0 0\n1e-400 0 0\n0 1e-400 0\n3 0 1 2\n")
    code, _, err = run(capsys, "convert", source, tmp_path / "o.vtu")
    assert code == 2
    assert "the rounded mesh is not the mesh" in err and "nothing was written" in err
    assert ".geomexact-staging" not in err
    assert sorted(os.listdir(tmp_path)) == ["tiny.off"]
    code, _, err = run(capsys, "convert", source, tmp_path / "o.vtu", "--float")
    assert code == 0 and "the rounded file does not read back" in err  # asked for: written


def test_a_rounding_that_keeps_the_mesh_is_a_warning(capsys: pytest.CaptureFixture[str],
                                                     tmp_path: Path) -> None:
    """1/3 rounds but the mesh stays the mesh: written, with the warning."""
    source = tmp_path / "third.off"
    source.write_text("OFF\n3 1 0\n0 0 0\n1/3 0 0\n0 1 0\n3 0 1 2\n")
    code, _, err = run(capsys, "convert", source, tmp_path / "o.vtu")
    assert code == 0 and "rounded to the nearest double" in err
    assert (tmp_path / "o.vtu").exists()


def test_census_refuses_a_parquet_name_for_its_csv(capsys: pytest.CaptureFixture[str],
                                                  tmp_path: Path) -> None:
    """census -o x.parquet wrote CSV text into x.parquet: now exit 2, nothing written."""
    code, _, err = run(capsys, "census", "--patterns", "1-2", "--workers", "1",
                       "-o", tmp_path / "x.parquet")
    assert code == 2 and "give a name ending in .csv" in err
    assert os.listdir(tmp_path) == []
