"""The line-tagged PSLG text format (.pslg): PSLGs (v/s/h/r records) and meshes
(v/t/n/s records) round-trip exactly; the n records are checked."""

from __future__ import annotations

import tempfile
from pathlib import Path

import attrs
import pytest
from helpers.io_cases import grid_meshes, pslgs, write
from hypothesis import given

from geomexact import Mesh2, io, mesh_from_triangles, mpq, point2
from geomexact.errors import FormatError
from geomexact.mesh2d.pslg import PSLG, RegionSeed


@given(pslgs())
def test_pslg_round_trips_exactly(pslg: PSLG) -> None:
    """A PSLG with markers, attributes, segments, holes and regions round-trips (vertex
    attributes come after a marker column: markers 0 stand for "none" then)."""
    if pslg.vertex_attributes and not pslg.vertex_markers:
        pslg = attrs.evolve(pslg, vertex_markers=(0,) * len(pslg.vertices))
    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "p.pslg"
        io.write(target, pslg, exact=True)
        assert io.read(target) == pslg


@given(grid_meshes())
def test_mesh_round_trips_exactly(mesh: Mesh2) -> None:
    """A mesh with markers, attributes and segments round-trips, neighbours checked."""
    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.pslg"
        io.write(target, mesh, exact=True)
        again, notes = io.read_with_notes(target)
        assert again == mesh
        if mesh.triangle_count:
            assert "the neighbour records agree with the adjacency" in notes


def test_pslg_text(tmp_path: Path) -> None:
    """The records a PSLG is written as."""
    pslg = PSLG(
        vertices=[point2(0, 0), point2(1, 0), point2(0, mpq(1, 3))],
        segments=[(0, 1, 2), (1, 2, 0)],
        holes=[point2(mpq(1, 10), mpq(1, 10))],
        regions=[RegionSeed(point2(1, 1), mpq(-1)), RegionSeed(point2(2, 2), mpq(3), mpq(1, 2))],
    )
    io.write(tmp_path / "p.pslg", pslg, exact=True)
    assert (tmp_path / "p.pslg").read_text().splitlines() == [
        "v 0 0", "v 1 0", "v 0 1/3", "s 0 1 2", "s 1 2 0", "h 0.1 0.1", "r 1 1 -1",
        "r 2 2 3 0.5",
    ]


def test_mesh_text(tmp_path: Path) -> None:
    """The records a mesh is written as: v, t (canonical order), n, s."""
    mesh = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 1, 4)],
        vertex_markers=[1, 0, 0, 0],
    )
    io.write(tmp_path / "m.pslg", mesh, exact=True)
    assert (tmp_path / "m.pslg").read_text().splitlines() == [
        "v 0 0 1", "v 1 0 0", "v 1 1 0", "v 0 1 0", "t 0 1 2", "t 0 2 3", "n -1 1 -1",
        "n -1 -1 0", "s 0 1 4",
    ]


def test_records_in_any_order_with_comments(tmp_path: Path) -> None:
    """Records may come in any order; '#' comments and blank lines are ignored."""
    write(tmp_path, "o.pslg", "# square\nt 0 1 2\n\nv 0 0\nv 1 0 # x\nv 0 1\n")
    mesh = io.read(tmp_path / "o.pslg")
    assert mesh == mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])


def test_clockwise_triangles_are_reversed(tmp_path: Path) -> None:
    """All-clockwise t records are oriented, with a note."""
    write(tmp_path, "cw.pslg", "v 0 0\nv 1 0\nv 0 1\nt 0 2 1\n")
    mesh, notes = io.read_with_notes(tmp_path / "cw.pslg")
    assert isinstance(mesh, Mesh2) and mesh.triangles() == [(0, 1, 2)]
    assert notes == ["the only triangle was clockwise; reversed it"]


@pytest.mark.parametrize(
    ("text", "line", "fragment"),
    [
        ("v 0 0\nv 1 0\nv 0 1\nt 0 1 2\nh 5 5\n", 5, "belong to a PSLG"),
        ("v 0 0\nv 1 0\nn -1 -1 -1\n", 3, "neighbour records need triangle records"),
        ("v 0 0\nv 1 0\nv 0 1\nt 0 1 2\nn -1 -1 -1\nn -1 -1 -1\n", 6,
         "2 neighbour records for 1 triangles"),
        ("v 0 0\nv 1 0\ns 0 0\n", 3, "has equal ends"),
        ("v 0 0\nv 1 0\ns 0 2\n", 3, "vertex 2 is out of range"),
        ("v 0 0 1 5\nv 1 0 1\n", 2, "has 0 attributes, but the first vertex has 1"),
        ("v 0\n", 1, "needs 3 fields"),
        ("r 0 0\n", 1, "a region record is"),
        ("v 0 0 x\n", 1, "marker of vertex 0: 'x' is not an integer"),
    ],
)
def test_bad_records(tmp_path: Path, text: str, line: int, fragment: str) -> None:
    """Bad records name their line."""
    write(tmp_path, "b.pslg", text)
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "b.pslg")
    assert caught.value.line == line
    assert fragment in caught.value.problem
