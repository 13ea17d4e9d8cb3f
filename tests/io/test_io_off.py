"""OFF: triangle meshes and polygon meshes, header variants, comments, the Geomview
wrapper, orientation, and exact round trips."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from helpers.io_cases import grid_meshes, plain, write
from hypothesis import given

from geomexact import Mesh2, io, mesh_from_triangles, mpq, point2
from geomexact.errors import FormatError
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh

TRIANGLE = "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"


@given(grid_meshes())
def test_mesh_round_trips_exactly(mesh: Mesh2) -> None:
    """OFF keeps vertices and triangles exactly (exact=True); not markers, attributes
    or segments."""
    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.off"
        io.write(target, mesh, exact=True)
        assert io.read(target) == plain(mesh)


def test_polygon_mesh_round_trips(tmp_path: Path) -> None:
    """A polygon mesh (a square and a triangle) writes and reads back equal."""
    polygons = PolygonMesh(
        vertices=[point2(0, 0), point2(1, 0), point2(1, 1), point2(0, 1), point2(2, mpq(1, 3))],
        polygons=[(0, 1, 2, 3), (1, 4, 2)],
    )
    io.write(tmp_path / "p.off", polygons, exact=True)
    assert io.read(tmp_path / "p.off") == polygons
    assert (tmp_path / "p.off").read_text().splitlines()[-2:] == ["4 0 1 2 3", "3 1 4 2"]


def test_clockwise_polygons_are_reversed(tmp_path: Path) -> None:
    """All-clockwise polygons are reversed (keeping the first vertex), with a note."""
    write(tmp_path, "cw.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 3 2 1\n")
    value, notes = io.read_with_notes(tmp_path / "cw.off")
    assert isinstance(value, PolygonMesh)
    assert value.polygons == ((0, 1, 2, 3),)
    assert notes == ["the only face was clockwise; reversed it"]


def test_mixed_polygon_orientations_are_rejected(tmp_path: Path) -> None:
    """A clockwise and a counter-clockwise polygon: error naming both lines."""
    write(
        tmp_path,
        "mix.off",
        "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 1 4 2\n4 0 3 2 1\n",
    )
    with pytest.raises(FormatError, match=r"face 2 \(0 3 2 1\) on line 10 is clockwise but "
                       r"face 0 \(0 1 2 3\) on line 8 is counter-clockwise") as caught:
        io.read(tmp_path / "mix.off")
    assert caught.value.line == 10


@pytest.mark.parametrize(
    "text",
    [
        "OFF\n" + TRIANGLE,
        TRIANGLE,  # the keyword is optional
        "OFF " + TRIANGLE,  # counts on the keyword's line
        "COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n",
        "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
        "STCNOFF\n3 1\n0 0 0 0 0 1 1 1 1 1 0 0\n1 0 0 0 0 1 1 1 1 1 0 0\n"
        "0 1 0 0 0 1 1 1 1 1 0 0\n3 0 1 2 255 0 0\n",
        "# leading comment\nOFF # trailing\n\n3 1 0\n0 0 0\n1 0 0 # x\n0 1 0\n\n3 0 1 2\n",
        "OFF\n3 1 0\n0.0 0.0 0.0\n1.0 0.0 -0.0\n0 1e0 0e5\n3 0 1 2\n",
    ],
)
def test_header_variants(tmp_path: Path, text: str) -> None:
    """OFF, no keyword, counts after it, C/N/ST variants (extra columns ignored),
    comments, blank lines, -0.0 and 0e5 as z."""
    write(tmp_path, "v.off", text)
    mesh = io.read(tmp_path / "v.off")
    assert mesh == mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])


@pytest.mark.parametrize(
    "text",
    [
        "{ appearance {+edge +face linewidth 2} LIST\nOFF\n" + TRIANGLE + "}\n",
        "{ LIST { OFF\n" + TRIANGLE + "} }\n",
        "{\nappearance {\n  +edge\n  material { ambient 1 1 1 }\n}\nOFF\n" + TRIANGLE + "}\n",
        "{ OFF\n" + TRIANGLE + "}\n",
    ],
)
def test_geomview_wrapper(tmp_path: Path, text: str) -> None:
    """The old Geomview block around an OFF object is read through, line numbers kept."""
    write(tmp_path, "w.off", text)
    value, notes = io.read_with_notes(tmp_path / "w.off")
    assert value == mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    assert "read the OFF object inside a Geomview '{ … }' wrapper" in notes


def test_wrapper_keeps_line_numbers(tmp_path: Path) -> None:
    """An error inside a wrapped OFF names its true line."""
    write(tmp_path, "w.off", "{ appearance {+edge} LIST\nOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 q\n"
          "3 0 1 2\n}\n")
    with pytest.raises(FormatError, match="z of vertex 2") as caught:
        io.read(tmp_path / "w.off")
    assert caught.value.line == 6


def test_mesh_off_text(tmp_path: Path) -> None:
    """The written text: header, counts, 'x y 0' vertex lines, '3 a b c' faces."""
    mesh = mesh_from_triangles([(0, 0), (mpq(1, 2), 0), (0, mpq(1, 3))], [(0, 1, 2)])
    io.write(tmp_path / "m.off", mesh, exact=True)
    assert (tmp_path / "m.off").read_text() == (
        "OFF\n3 1 0\n0 0 0\n0.5 0 0\n0 1/3 0\n3 0 1 2\n"
    )
    io.write(tmp_path / "f.off", mesh)
    assert (tmp_path / "f.off").read_text() == (
        "OFF\n3 1 0\n0 0 0\n0.5 0 0\n0 0.3333333333333333 0\n3 0 1 2\n"
    )


def test_empty_off_is_an_empty_mesh(tmp_path: Path) -> None:
    """No faces: a mesh with vertices and no triangles."""
    write(tmp_path, "e.off", "OFF\n2 0 0\n0 0 0\n1 1 0\n")
    mesh = io.read(tmp_path / "e.off")
    assert isinstance(mesh, Mesh2)
    assert (mesh.vertex_count, mesh.triangle_count) == (2, 0)
