"""Mellado's text format (Vertices / Triangles / Neighbors of v / t / n lines): round
trips, both neighbour forms, the index base, and file:line errors for bad files."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from helpers.io_cases import geometric_triangles, grid_meshes, write
from hypothesis import given

from geomexact import Mesh2, io, validate
from geomexact.errors import FormatError

SQUARE = """Vertices 4
v 0 0
v 1 0
v 1 1
v 0 1
Triangles 2
t 0 1 2
t 0 2 3
"""


@given(grid_meshes(extras=False))
def test_round_trip_keeps_the_mesh(mesh: Mesh2) -> None:
    """Written exactly and read back: the same triangles; the neighbour lines it writes
    pass the reader's check."""
    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.mellado"
        io.write(target, mesh, exact=True)
        again, notes = io.read_with_notes(target)
        assert isinstance(again, Mesh2)
        assert geometric_triangles(again) == geometric_triangles(mesh)
        assert validate(again) == []
        assert "Neighbors: one line per triangle" in notes


def test_written_text_is_zero_based_with_triangle_neighbours(tmp_path: Path) -> None:
    """The writer's exact text for the unit square."""
    write(tmp_path, "s.mellado", SQUARE)
    mesh = io.read(tmp_path / "s.mellado")
    io.write(tmp_path / "out.mellado", mesh)
    assert (tmp_path / "out.mellado").read_text() == SQUARE + "Neighbors 2\nn -1 1 -1\nn -1 -1 0\n"


def test_vertex_neighbour_form_is_accepted(tmp_path: Path) -> None:
    """One n line per vertex (its neighbouring vertices), in any order."""
    write(tmp_path, "s.mellado", SQUARE + "Neighbors\nn 1 2 3\nn 0 2\nn 3 1 0\nn 0 2\n")
    mesh, notes = io.read_with_notes(tmp_path / "s.mellado", format="mellado")
    assert isinstance(mesh, Mesh2) and mesh.triangle_count == 2
    assert "Neighbors: one line per vertex" in notes


def test_one_based_file_is_read_and_noted(tmp_path: Path) -> None:
    """Indices 1…N with no 0 are 1-based."""
    text = SQUARE.replace("t 0 1 2", "t 1 2 3").replace("t 0 2 3", "t 1 3 4")
    write(tmp_path, "s.mellado", text)
    mesh, notes = io.read_with_notes(tmp_path / "s.mellado")
    assert isinstance(mesh, Mesh2) and mesh.triangle_count == 2
    assert any("1-based" in note for note in notes)


@pytest.mark.parametrize(("text", "line", "fragment"), [
    ("v 0 0\n", 1, "data before the first section"),
    ("Vertices\nv 0\n", 2, "'v x y'"),
    ("Vertices\nv 0 zero\n", 2, "y"),
    ("Vertices 3\nv 0 0\nv 1 0\nTriangles\nt 0 1 2\n", 1, "announces 3"),
    (SQUARE.replace("t 0 2 3", "t 0 2 7"), 8, "out of range"),
    (SQUARE.replace("t 0 2 3", "x 0 2 3"), 8, "starts with 't'"),
    (SQUARE + "Neighbors\nn -1 1 -1\nn -1 -1 1\n", 11, "the file says 1"),
    (SQUARE + "Neighbors\nn 1 2 3\nn 0 2\nn 3 1\nn 0 2\n", 12, "vertex 2"),
    (SQUARE + "Neighbors\nn 1\n", 10, "neither one per triangle"),
    (SQUARE.replace("t 0 2 3", "t 0 2 q"), 8, "integer"),
])
def test_bad_files_name_the_file_and_line(
    tmp_path: Path, text: str, line: int, fragment: str
) -> None:
    """Every problem is a FormatError with the file and the line."""
    write(tmp_path, "bad.mellado", text)
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "bad.mellado")
    message = str(caught.value)
    assert f"bad.mellado:{line}" in message, message
    assert fragment in message, message


def test_lepp_delaunay_course_mesh_round_trips(tmp_path: Path) -> None:
    """A mesh written as a triangle list, converted: same triangles."""
    write(tmp_path, "t.txt", "0 0 1 0 0 1\n1 0 1 1 0 1\n")
    mesh = io.read(tmp_path / "t.txt")
    io.write(tmp_path / "t.mellado", mesh)
    again = io.read(tmp_path / "t.mellado")
    assert isinstance(mesh, Mesh2) and isinstance(again, Mesh2)
    assert geometric_triangles(again) == geometric_triangles(mesh)


def test_a_txt_in_mellado_s_text_is_read_as_it(tmp_path: Path) -> None:
    """Mellado's programs write .txt: a .txt whose first data line is a section header
    is Mellado's text (issue 26, item 8), any other .txt still a triangle list, and a
    bad Mellado .txt names its line as the Mellado reader does."""
    text = ("# written by the study's program\nVertices 4\nv 0 0\nv 1 0\nv 1 1\nv 0 1\n"
            "Triangles 2\nt 0 1 2\nt 0 2 3\n")
    (tmp_path / "run.txt").write_text(text)
    (tmp_path / "run.mellado").write_text(text)
    as_txt, as_mellado = io.read(tmp_path / "run.txt"), io.read(tmp_path / "run.mellado")
    assert isinstance(as_txt, Mesh2) and as_txt.digest == as_mellado.digest
    (tmp_path / "list.txt").write_text("0 0 1 0 1 1\n0 0 1 1 0 1\n")
    listed = io.read(tmp_path / "list.txt")
    assert isinstance(listed, Mesh2) and listed.triangle_count == 2
    (tmp_path / "bad.txt").write_text("Vertices\nv 0 0\nq 1 1\n")
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "bad.txt")
    assert caught.value.line == 3
