"""Pictures of tetrahedral meshes (:mod:`geomexact.viz.pictures3d`): files of the right
size, only the visible faces drawn, an exact clip plane that removes tetrahedra and shows
the faces it opens, the mesh left unchanged, the smallest and the empty mesh."""

from __future__ import annotations

import struct
from fractions import Fraction
from pathlib import Path

import pytest
from helpers.mesh3d_cases import cube_grid
from matplotlib.figure import Figure

from geomexact.kernel.numbers import format_rational
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3, empty_mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra
from geomexact.viz.pictures import figure_bytes
from geomexact.viz.pictures3d import (
    Drawing3,
    draw_mesh3,
    face_neighbours,
    figure_mesh3,
    plot_mesh3,
)
from geomexact.viz.scene3d import clip_plane, tetrahedron_arrays


def _png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])
    return width, height


def _drawing(mesh: Mesh3, **options: object) -> Drawing3:
    fig = Figure()
    return draw_mesh3(fig.add_subplot(), mesh, **options)  # type: ignore[arg-type]


def _two_tetrahedra() -> Mesh3:
    """Two tetrahedra sharing the face (0, 1, 2), their apexes at z = 1 and z = -1."""
    points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1)]
    return mesh3_from_tetrahedra(points, [(0, 1, 2, 3), (0, 2, 1, 4)], orient=True)


@pytest.fixture(scope="module")
def cuboid() -> Mesh3:
    return partition_cuboid(262143, improve=True).mesh


@pytest.mark.parametrize(("suffix", "magic"), [(".png", b"\x89PNG"), (".svg", b"<?xml"),
                                               (".pdf", b"%PDF")])
def test_picture_is_written_in_each_format(cuboid: Mesh3, tmp_path: Path, suffix: str,
                                           magic: bytes) -> None:
    path = tmp_path / f"cuboid{suffix}"
    plot_mesh3(cuboid, path, clip=clip_plane("x", "1/2"), colour="quality")
    assert path.read_bytes().startswith(magic)
    with pytest.raises(FileExistsError):
        plot_mesh3(cuboid, path)


def test_png_has_the_requested_size(cuboid: Mesh3, tmp_path: Path) -> None:
    plot_mesh3(cuboid, tmp_path / "a.png")
    assert _png_size(tmp_path / "a.png") == (800, 600)
    plot_mesh3(cuboid, tmp_path / "b.png", size=(4.0, 3.0), dpi=50)
    assert _png_size(tmp_path / "b.png") == (200, 150)


def test_pictures_are_reproducible(cuboid: Mesh3) -> None:
    def svg() -> bytes:
        return figure_bytes(figure_mesh3(cuboid, clip=clip_plane("y", "0.5")), "svg")

    assert svg() == svg()


def test_unclipped_drawing_shows_the_boundary_facing_the_viewer() -> None:
    """A 6 × 6 × 6 grid of cubes: 432 boundary triangles, of which the three sides seen
    from the default view (216) are painted; nothing inside is drawn."""
    mesh = cube_grid(6, 6, 6)
    drawing = _drawing(mesh)
    assert drawing.tetrahedra == drawing.kept == mesh.tetrahedron_count == 1296
    assert drawing.surface == len(mesh.boundary_faces()) == 432
    assert drawing.cut == 0
    assert drawing.painted == 216


def test_clip_removes_the_tetrahedra_beyond_it_exactly(cuboid: Mesh3) -> None:
    arrays = tetrahedron_arrays(cuboid)
    for axis, position in (("x", Fraction(1, 2)), ("z", Fraction(1, 4)),
                           ("y", Fraction(3, 4))):
        drawing = _drawing(cuboid, clip=clip_plane(axis, format_rational(position)))
        index = "xyz".index(axis)
        expected = sum(
            1 for cell in cuboid.tetrahedra()
            if sum(Fraction(cuboid.point(v)[index]) for v in cell) / 4 <= position
        )
        assert drawing.kept == expected
        assert 0 < drawing.kept < drawing.tetrahedra == len(arrays.cells)
        assert drawing.cut > 0
    everything = _drawing(cuboid, clip=clip_plane("x", 1))
    assert everything.kept == everything.tetrahedra and everything.cut == 0
    nothing = _drawing(cuboid, clip=clip_plane("x", -1))
    assert nothing.kept == nothing.surface == nothing.painted == 0


def test_a_centroid_on_the_plane_is_kept() -> None:
    """The centroids of the two tetrahedra are at z = 1/4 and z = -1/4."""
    mesh = _two_tetrahedra()
    assert _drawing(mesh, clip=clip_plane("z", "1/4")).kept == 2
    below = _drawing(mesh, clip=clip_plane("z", "0.2499999999999999999999"))
    assert below.kept == 1 and below.cut == 1 and below.surface == 3


def test_two_tetrahedra(tmp_path: Path) -> None:
    mesh = _two_tetrahedra()
    drawing = _drawing(mesh)
    assert (drawing.tetrahedra, drawing.kept, drawing.surface, drawing.cut) == (2, 2, 6, 0)
    assert 0 < drawing.painted < 6
    adjacency = face_neighbours(tetrahedron_arrays(mesh).cells)
    assert sorted(adjacency.neighbours.tolist()) == [-1] * 6 + [0, 1]
    shrunk = _drawing(mesh, shrink=0.3)
    assert 0 < shrunk.painted <= 8
    plot_mesh3(mesh, tmp_path / "two.png", title="two tetrahedra")
    assert _png_size(tmp_path / "two.png") == (800, 600)


def test_empty_mesh_gives_an_empty_picture(tmp_path: Path) -> None:
    """An empty mesh is drawn as an empty picture (no error), titled with its counts."""
    drawing = _drawing(empty_mesh3())
    assert (drawing.vertices, drawing.tetrahedra, drawing.painted) == (0, 0, 0)
    fig = plot_mesh3(empty_mesh3(), tmp_path / "empty.png")
    assert fig._suptitle is not None
    assert fig._suptitle.get_text() == "0 vertices, 0 tetrahedra"
    assert _png_size(tmp_path / "empty.png") == (800, 600)


def test_the_mesh_is_not_changed(cuboid: Mesh3) -> None:
    before = (cuboid.digest, cuboid.tetrahedra(), dict(cuboid.vertices), dict(cuboid.faces))
    _drawing(cuboid, clip=clip_plane("x", "1/2"), colour="quality", shrink=0.2)
    plot_mesh3(cuboid, clip=clip_plane("z", "1/3"))
    assert (cuboid.digest, cuboid.tetrahedra(), dict(cuboid.vertices),
            dict(cuboid.faces)) == before
    assert all(type(p.x).__name__ == "mpq" for p in cuboid.vertices.values())


def test_arrays_are_the_mesh_in_doubles(cuboid: Mesh3) -> None:
    arrays = tetrahedron_arrays(cuboid)
    assert [tuple(row) for row in arrays.cells.tolist()] == cuboid.tetrahedra()
    assert arrays.xyz.tolist() == [[p.fx, p.fy, p.fz] for p in
                                   (cuboid.point(v) for v in range(cuboid.vertex_count))]


def test_options_are_checked(cuboid: Mesh3) -> None:
    with pytest.raises(ValueError, match="colour"):
        _drawing(cuboid, colour="rainbow")
    with pytest.raises(ValueError, match="shrink"):
        _drawing(cuboid, shrink=1.0)
    with pytest.raises(ValueError, match="axis"):
        clip_plane("w", 1)
    with pytest.raises(ValueError):
        clip_plane("x", "half")
    with pytest.raises(TypeError, match="Mesh3"):
        _drawing("not a mesh")  # type: ignore[arg-type]
