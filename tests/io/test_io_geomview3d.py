"""Geomview OFF / VECT pictures of tetrahedral meshes, and tetrahedral VTU through meshio:
counts, the text parses, the tetrahedra come back."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from geomexact import io
from geomexact.errors import FormatError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3


def _mesh(third: bool = False) -> Mesh3:
    high = (Fraction(1, 3) if third else 1, 2, 3)
    return partition_cuboid(0b1011, Box((0, 0, 0), high)).mesh


def _off(text: str) -> tuple[list[tuple[float, ...]], list[list[int]], list[list[float]]]:
    rows = [line.split() for line in text.splitlines() if line.strip()]
    assert rows[0] == ["OFF"]
    nv, nf, _ = map(int, rows[1])
    points = [tuple(map(float, row)) for row in rows[2 : 2 + nv]]
    assert all(len(p) == 3 for p in points)
    faces, colours = [], []
    for row in rows[2 + nv :]:
        k = int(row[0])
        faces.append([int(v) for v in row[1 : 1 + k]])
        colours.append([float(c) for c in row[1 + k :]])
    assert len(faces) == nf
    return points, faces, colours


def test_tetrahedra_off(tmp_path: Path) -> None:
    mesh = _mesh()
    path = tmp_path / "m.off"
    report = io.write_with_report(path, mesh, format="geomview3d")
    assert report.rounded == 0
    points, faces, colours = _off(path.read_text())
    assert len(points) == mesh.vertex_count
    assert len(faces) == 4 * mesh.tetrahedron_count
    assert all(len(face) == 3 and len(set(face)) == 3 for face in faces)
    assert all(len(colour) == 4 and all(0 <= c <= 1 for c in colour) for colour in colours)
    # the four faces of a tetrahedron share its colour
    assert all(colours[i] == colours[i - i % 4] for i in range(len(colours)))


def test_boundary_off(tmp_path: Path) -> None:
    mesh = _mesh()
    path = tmp_path / "b.off"
    io.write(path, mesh, format="geomview3d-boundary")
    _, faces, _ = _off(path.read_text())
    assert sorted(map(tuple, faces)) == mesh.boundary_faces()


def test_vect(tmp_path: Path) -> None:
    mesh = _mesh()
    path = tmp_path / "m.vect"
    io.write(path, mesh)  # .vect selects the format
    rows = [line.split() for line in path.read_text().splitlines() if line.strip()]
    assert rows[0] == ["VECT"]
    lines, vertices, colours = map(int, rows[1])
    assert lines == len(mesh.edges()) and vertices == 2 * lines and colours == 1
    assert [int(n) for n in rows[2]] == [2] * lines
    assert sum(int(n) for n in rows[3]) == colours
    assert len(rows) == 4 + vertices + colours
    assert all(len(row) == 3 for row in rows[4 : 4 + vertices])
    assert len(rows[-1]) == 4


def test_rounded_numbers_are_counted_in_pictures(tmp_path: Path) -> None:
    mesh = _mesh(third=True)
    report = io.write_with_report(tmp_path / "m.vect", mesh)
    assert report.rounded > 0


def test_write_only(tmp_path: Path) -> None:
    path = tmp_path / "m.vect"
    io.write(path, _mesh())
    with pytest.raises(FormatError, match="write-only"):
        io.read(path)


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_meshio_tetra_round_trip(tmp_path: Path, suffix: str) -> None:
    mesh = _mesh()
    path = tmp_path / f"m{suffix}"
    report = io.write_with_report(path, mesh)
    assert report.rounded == 0
    back = io.read(path)
    assert isinstance(back, Mesh3)
    assert back.tetrahedra() == mesh.tetrahedra() and back == mesh


def test_meshio_rounding_counted(tmp_path: Path) -> None:
    mesh = _mesh(third=True)
    thirds = sum(
        1 for index in range(mesh.vertex_count)
        for value in mesh.vertices[index][:3] if value.denominator % 3 == 0
    )
    report = io.write_with_report(tmp_path / "m.vtu", mesh)
    assert report.rounded == thirds > 0
    back = io.read(tmp_path / "m.vtu")
    assert isinstance(back, Mesh3) and back.tetrahedra() == mesh.tetrahedra()
