"""geomexact info, check and convert on mixed-cell mesh files, and the command's ``write``
taking a mixed mesh with cell data (issue 23, item 5)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from helpers.command import run

from geomexact import io
from geomexact.cli.writing import write
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed import MixedMesh3, MixedMeshData, box_grid_mesh

meshio = pytest.importorskip("meshio")
np = pytest.importorskip("numpy")

from helpers.mixed_files import bad_files, every_kind_mesh  # noqa: E402

GRID = box_grid_mesh(Box((0, 0, 0), (2, 1, 1)), 2, 1, 1)


def test_info_counts_cells_by_kind(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """info reports the cells of each kind, the exact volume and the digest."""
    mesh = every_kind_mesh()
    io.write(tmp_path / "m.vtu", mesh)
    code, out, _ = run(capsys, "info", tmp_path / "m.vtu", "--json")
    report = json.loads(out)
    assert code == 0 and report["kind"] == "mixed_mesh"
    assert report["cells"] == mesh.cell_count and report["digest"] == mesh.digest_text
    assert report["cells_by_kind"] == {
        "tetrahedra": 2, "pyramids": 1, "wedges": 1, "hexahedra": 11, "polyhedra": 6}
    assert report["volume"] == "222"  # 6^3 (1 + 1/36)
    code, out, _ = run(capsys, "info", tmp_path / "m.vtu")
    assert code == 0 and "mixed mesh" in out
    assert "tetrahedra 2, pyramids 1, wedges 1, hexahedra 11, polyhedra 6" in out


def test_check_validates_a_mixed_file(capsys: pytest.CaptureFixture[str],
                                      tmp_path: Path) -> None:
    """check: valid, with counts and digest; --json too."""
    io.write(tmp_path / "g.vtk", GRID)
    code, out, _ = run(capsys, "check", tmp_path / "g.vtk")
    assert code == 0
    assert out.strip() == (f"{tmp_path / 'g.vtk'}: valid (12 vertices, 2 cells, 2 hexahedra, "
                           f"digest {GRID.digest_text})")
    code, out, _ = run(capsys, "check", tmp_path / "g.vtk", "--json")
    report = json.loads(out)
    assert code == 0 and report["valid"] and report["cells_by_kind"] == {"hexahedra": 2}


@pytest.mark.parametrize("target", ["m.msh", "m.vtk", "m.vtu"])
def test_convert_keeps_the_mesh(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                target: str) -> None:
    """convert m.vtu to .msh, .vtk and back: the same mesh."""
    io.write(tmp_path / "g.vtu", GRID)
    code, out, _ = run(capsys, "convert", tmp_path / "g.vtu", tmp_path / target)
    assert code == 0 and out.strip() == f"wrote {tmp_path / target}"
    assert io.read(tmp_path / target) == GRID


def test_convert_refuses_polyhedra_in_msh(capsys: pytest.CaptureFixture[str],
                                          tmp_path: Path) -> None:
    """A mesh with polyhedra cannot be Gmsh: one line naming the file, exit 2, nothing
    written."""
    io.write(tmp_path / "p.vtu", every_kind_mesh())
    code, out, err = run(capsys, "convert", tmp_path / "p.vtu", tmp_path / "p.msh")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "p.msh: Gmsh .msh has no polyhedron cells" in err
    assert sorted(os.listdir(tmp_path)) == ["p.vtu"]


@pytest.mark.parametrize("case", ["non-planar", "non-convex", "hanging", "inverted"])
def test_bad_files_exit_2_and_write_nothing(capsys: pytest.CaptureFixture[str],
                                            tmp_path: Path, case: str) -> None:
    """A bad mixed file: exit 2 naming the file and the problem, no output, no traceback."""
    source = tmp_path / "in"
    source.mkdir()
    path, problem = bad_files(source)[case]
    code, out, err = run(capsys, "convert", path, tmp_path / "out.vtu")
    assert code == 2 and out == ""
    assert str(path) in err and problem in err and "Traceback" not in err
    assert not (tmp_path / "out.vtu").exists()
    code, _, err = run(capsys, "check", path)
    assert code == 2 and problem in err


def test_write_takes_cell_data(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """The command's write() takes a MixedMeshData (the octree's levels) and refuses an
    existing file without overwrite."""
    data = MixedMeshData(GRID, {"level": [1, 2]})
    assert write(tmp_path / "l.vtu", data, None, overwrite=False) == [tmp_path / "l.vtu"]
    read = meshio.read(tmp_path / "l.vtu")
    assert np.concatenate(read.cell_data["level"]).tolist() == [1, 2]
    back = io.read(tmp_path / "l.vtu")
    assert isinstance(back, MixedMesh3) and back == GRID
    with pytest.raises(FileExistsError):
        write(tmp_path / "l.vtu", data, None, overwrite=False)
    assert write(tmp_path / "l.vtu", data, "meshio", overwrite=True) == [tmp_path / "l.vtu"]
    capsys.readouterr()


def test_rounded_mixed_write_warns(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """Coordinates that are not doubles are rounded with a warning counting them, and the
    rounded file is read back to check its cells."""
    mesh = box_grid_mesh(Box((0, 0, 0), (1, "1/3", 1)), 1, 1, 1)
    write(tmp_path / "r.vtu", mesh, None, overwrite=False)
    err = capsys.readouterr().err
    assert "4 numbers rounded to the nearest double" in err
