"""``info``, ``check`` and ``convert`` on tetrahedral meshes (TetGen files), and the 2D
commands refusing them by name."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from geomexact import io
from geomexact.cli import main
from geomexact.mesh3d.cuboid.boxes import box_of_extents
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3


def _mesh() -> Mesh3:
    return partition_cuboid(0b101, box_of_extents(1, 2, 3)).mesh


def _written(tmp_path: Path) -> Path:
    path = tmp_path / "box.ele"
    io.write(path, _mesh())
    return path


def test_info_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _written(tmp_path)
    assert main(["info", str(path), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    mesh = _mesh()
    assert report["kind"] == "tetrahedral_mesh"
    assert report["vertices"] == mesh.vertex_count
    assert report["tetrahedra"] == mesh.tetrahedron_count
    assert report["boundary_faces"] == len(mesh.boundary_faces())
    assert report["volume"] == "6"
    assert isinstance(report["is_delaunay"], bool)
    assert report["digest"] == mesh.digest_text


def test_info_table(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["info", str(_written(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "tetrahedral mesh" in out and "tetrahedra" in out


def test_check_valid(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _written(tmp_path)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "valid" in out and _mesh().digest_text in out
    assert main(["check", str(path), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["valid"] is True and report["tetrahedra"] == _mesh().tetrahedron_count


def test_check_bad_file_names_the_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _written(tmp_path)
    text = path.read_text().splitlines()
    text[2] = text[2].split()[0] + " 0 0 0 0"
    path.write_text("\n".join(text) + "\n")
    assert main(["check", str(path)]) != 0
    assert f"{path}:3" in capsys.readouterr().err


def test_convert_to_tetgen_and_vtu(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _written(tmp_path)
    out = tmp_path / "copy" / "b.ele"
    out.parent.mkdir()
    assert main(["convert", str(path), str(out)]) == 0
    assert io.read(out) == _mesh()
    vtu = tmp_path / "box.vtu"
    assert main(["convert", str(path), str(vtu)]) == 0
    assert vtu.exists()
    back = io.read(vtu)
    assert isinstance(back, Mesh3)
    assert back.tetrahedra() == _mesh().tetrahedra()


def test_check_reports_violations(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Two tetrahedra sharing only an edge: the boundary is not a closed 2-manifold."""
    (tmp_path / "bow.node").write_text(
        "6 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 -1 0 0\n5 0 -1 -1\n"
    )
    (tmp_path / "bow.ele").write_text("2 4 0\n0 0 1 2 3\n1 0 3 4 5\n")
    code = main(["check", str(tmp_path / "bow.ele"), "--json"])
    report = json.loads(capsys.readouterr().out)
    assert code == 1 and report["valid"] is False
    assert [(v["kind"], v["elements"]) for v in report["violations"]] == [
        ("non-manifold-edge", [0, 3])]


def test_check_reports_a_non_manifold_vertex(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    """Two tetrahedra sharing only a vertex (issue 27, item 4: was "valid")."""
    (tmp_path / "tie.node").write_text(
        "7 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 -1 0 0\n5 0 -1 0\n6 0 0 -1\n"
    )
    (tmp_path / "tie.ele").write_text("2 4 0\n0 0 1 2 3\n1 0 4 6 5\n")
    assert main(["check", str(tmp_path / "tie.ele")]) == 1
    out = capsys.readouterr().out
    assert "invalid, 1 violation(s)" in out
    assert "non-manifold-vertex: the tetrahedra around vertex 0 form 2 groups" in out


def test_check_notes_unused_vertices(tmp_path: Path,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    """A vertex in no tetrahedron: valid with a warning; a violation with --strict."""
    (tmp_path / "u.node").write_text(
        "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 5 5 5\n")
    (tmp_path / "u.ele").write_text("1 4 0\n0 0 1 2 3\n")
    path = str(tmp_path / "u.ele")
    assert main(["check", path, "--json"]) == 0
    captured = capsys.readouterr()
    report = json.loads(captured.out)
    assert report["valid"] is True and report["violations"] == []
    assert report["warnings"] == [
        "vertex 4 is in no tetrahedron (unused; --strict makes it a violation)"]
    assert f"warning: {path}: vertex 4 is in no tetrahedron" in captured.err
    assert main(["check", path, "--strict", "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert [(v["kind"], v["elements"]) for v in report["violations"]] == [
        ("isolated-vertex", [4])]


def test_named_formats(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _written(tmp_path)
    assert main(["info", str(path), "--format", "tetgen", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == "tetgen"
    off = tmp_path / "pic.off"
    assert main(["convert", str(path), str(off), "--to", "geomview3d"]) == 0
    assert off.read_text().startswith("OFF\n")
    assert main(["convert", str(path), str(tmp_path / "w.vect")]) == 0
    assert (tmp_path / "w.vect").read_text().startswith("VECT\n")


def test_view_writes_the_3d_viewer_of_a_tetrahedral_mesh(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from geomexact import io
    from geomexact.cli import main
    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    mesh = partition_cuboid(70688, improve=True).mesh
    io.write(tmp_path / "c.ele", mesh)
    assert main(["view", str(tmp_path / "c.ele"), "-o", str(tmp_path / "c.html")]) == 0
    page = (tmp_path / "c.html").read_text(encoding="utf-8")
    assert "http://" not in page and "https://" not in page
    assert main(["view", str(tmp_path / "c.ele"), "-o", str(tmp_path / "c.png")]) == 0
    assert (tmp_path / "c.png").read_bytes().startswith(b"\x89PNG")


_NEEDS = {
    "refine": "2D triangle meshes and PSLGs",
    "triangulate": "2D PSLGs and triangle meshes (made Delaunay by flips)",
    "polylla": "a triangle mesh (or a PSLG, which is triangulated first)",
}


@pytest.mark.parametrize(("command", "options"), [
    ("refine", ["--max-area", "1"]), ("polylla", []), ("triangulate", []),
])
def test_2d_commands_name_a_tetrahedral_mesh(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                             command: str, options: list[str]) -> None:
    path = _written(tmp_path)
    assert main([command, str(path), "-o", str(tmp_path / "out.off"), *options]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err == (
        f"geomexact: error: {path}: is a tetrahedral mesh (3D): {command} works on "
        f"{_NEEDS[command]}; see geomexact octree for 3D meshing (check, info, convert and "
        "view also read tetrahedral and mixed-cell meshes)\n")
    assert not (tmp_path / "out.off").exists()
