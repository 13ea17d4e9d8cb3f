"""Triangle lists ('x1 y1 x2 y2 x3 y3' per line): vertices merged by exact coordinates in
first-appearance order, each triangle oriented on its own."""

from __future__ import annotations

import tempfile
from pathlib import Path

from helpers.io_cases import geometric_triangles, grid_meshes, write
from hypothesis import given

from geomexact import Mesh2, io, mesh_from_triangles, mpq, validate


@given(grid_meshes(extras=False))
def test_round_trip_keeps_the_triangles(mesh: Mesh2) -> None:
    """Written exactly and read back: the same triangles (as exact coordinates); ids
    follow first appearance in the file."""
    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "t.txt"
        io.write(target, mesh, exact=True)
        again = io.read(target)
        assert isinstance(again, Mesh2)
        assert geometric_triangles(again) == geometric_triangles(mesh)
        assert validate(again) == []


def test_vertices_are_merged_in_first_appearance_order(tmp_path: Path) -> None:
    """Equal exact coordinates are one vertex, whatever their text (1, 1.0, 2/2)."""
    write(tmp_path, "t.txt", "0 0 1 0 0 1\n1.0 0 1 1 -0 2/2\n")
    mesh, notes = io.read_with_notes(tmp_path / "t.txt")
    assert isinstance(mesh, Mesh2)
    assert mesh.vertex_count == 4
    assert [mesh.point(v)[:2] for v in range(4)] == [
        (mpq(0), mpq(0)), (mpq(1), mpq(0)), (mpq(0), mpq(1)), (mpq(1), mpq(1))
    ]
    assert mesh.triangle_count == 2
    assert notes == []


def test_each_triangle_is_oriented_on_its_own(tmp_path: Path) -> None:
    """Mixed orientations are fine here: the clockwise ones are reversed and counted."""
    write(tmp_path, "m.txt", "0 0 1 0 1 1\n0 0 0 1 1 1\n")
    mesh, notes = io.read_with_notes(tmp_path / "m.txt")
    assert mesh == mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)]
    )
    assert notes == ["1 of 2 triangles were clockwise; reversed it"]


def test_written_text(tmp_path: Path) -> None:
    """One line per triangle, canonical order, counter-clockwise."""
    mesh = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    io.write(tmp_path / "w.txt", mesh)
    assert (tmp_path / "w.txt").read_text() == "0 0 1 0 1 1\n0 0 1 1 0 1\n"


def test_empty_file(tmp_path: Path) -> None:
    """No triangles: an empty mesh, noted."""
    write(tmp_path, "e.txt", "# nothing\n\n")
    mesh, notes = io.read_with_notes(tmp_path / "e.txt")
    assert isinstance(mesh, Mesh2) and mesh.vertex_count == 0
    assert notes == ["the file lists no triangles"]
