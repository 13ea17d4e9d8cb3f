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


# --- issue 26, item 3: 2D meshes through Gmsh and VTK files ------------------------------
SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"


@pytest.mark.parametrize("suffix", [".msh", ".vtu", ".vtk"])
def test_segments_and_markers_survive_gmsh_and_vtk(capsys: pytest.CaptureFixture[str],
                                                   tmp_path: Path, suffix: str) -> None:
    """triangulate superior.poly -o x.msh: the 518 boundary segments and their markers are
    written (line cells, gmsh:physical and cell data) and read back; before, writing
    dropped them with a warning and reading ignored line cells."""
    out = tmp_path / f"superior{suffix}"
    code, _, err = run(capsys, "triangulate", SUPERIOR, "-o", out)
    assert code == 0 and "cannot hold" not in err
    code, out_text, _ = run(capsys, "info", out, "--json")
    assert code == 0 and '"constrained_edges": 518' in out_text
    from geomexact import io

    back, original = io.read(out), io.read(SUPERIOR)
    assert sorted(back.segments.values()) == sorted(m for _, _, m in original.segments)


def test_a_gmsh_file_s_physical_groups_are_read(tmp_path: Path) -> None:
    """A Gmsh 2.2 mesh as Gmsh writes it: physical lines are segment markers, a physical
    surface the triangles' attribute, a physical point a vertex marker."""
    from geomexact import io

    path = tmp_path / "g.msh"
    path.write_text(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n"
        "4 0 1 0\n$EndNodes\n$Elements\n7\n1 15 2 7 1 1\n2 1 2 11 1 1 2\n3 1 2 11 2 2 3\n"
        "4 1 2 12 3 3 4\n5 1 2 12 4 4 1\n6 2 2 5 1 1 2 3\n7 2 2 5 1 1 3 4\n$EndElements\n")
    mesh = io.read(path)
    assert dict(mesh.segments) == {(0, 1): 11, (1, 2): 11, (2, 3): 12, (0, 3): 12}
    assert set(mesh.triangle_attributes.values()) == {(5,)}
    assert dict(mesh.vertex_markers) == {0: 7}


def test_obj_says_which_formats_keep_segments(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path) -> None:
    code, _, err = run(capsys, "triangulate", SUPERIOR, "-o", tmp_path / "s.obj")
    assert code == 0
    assert ".obj files cannot hold 518 segments" in err and ".vtu, .vtk and .msh" in err


def test_exact_off_says_other_readers_refuse_it(capsys: pytest.CaptureFixture[str],
                                                tmp_path: Path) -> None:
    """--exact OFF with a p/q number: a warning naming the readers that refuse it and
    the exact formats; an OFF of decimals gets none."""
    third = tmp_path / "third.pslg"
    third.write_text("v 0 0\nv 1/3 0\nv 0 1\nt 0 1 2\n")
    code, _, err = run(capsys, "convert", third, tmp_path / "x.off", "--exact")
    assert code == 0 and "1/3" in (tmp_path / "x.off").read_text()
    assert "other programs' OFF readers" in err and ".pslg or .ele" in err
    source = tmp_path / "t.off"
    source.write_text("OFF\n3 1 0\n0 0 0\n0.5 0 0\n0 1 0\n3 0 1 2\n")
    code, _, err = run(capsys, "convert", source, tmp_path / "y.off", "--exact")
    assert code == 0 and "OFF readers" not in err
