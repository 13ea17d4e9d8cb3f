"""Pictures (geomexact.viz.pictures): PNG/SVG/PDF files of a fixed pixel size, with content,
for meshes, PSLGs, polygon meshes and trace steps."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from geomexact import io
from geomexact.errors import OverwriteError, TraceError
from geomexact.kernel.points import point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.viz.pictures import (
    figure_bytes,
    min_angles,
    picture_format,
    plot,
    plot_step,
)

SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"


@pytest.fixture(scope="module")
def superior() -> PSLG:
    pslg = io.read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    return pslg


@pytest.fixture(scope="module")
def superior_mesh(superior: PSLG) -> Mesh2:
    return triangulate(superior).mesh


def picture(path: Path) -> np.ndarray:
    """The RGB(A) pixels of a PNG, asserting it is a real picture with content."""
    assert path.stat().st_size > 5000, path
    pixels = imread(path)
    inked = (pixels[..., :3] < 0.9).any(axis=-1).mean()
    assert inked > 0.002, f"{path} looks blank ({inked:.4f} of the pixels inked)"
    return pixels


def test_png_has_a_fixed_size_and_content(tmp_path: Path, superior_mesh: Mesh2) -> None:
    """plot writes an 800 × 600 PNG by default, and size × dpi otherwise, whatever the
    mesh's shape."""
    plot(superior_mesh, tmp_path / "default.png")
    assert picture(tmp_path / "default.png").shape[:2] == (600, 800)
    plot(superior_mesh, tmp_path / "small.png", size=(4, 3), dpi=50)
    assert picture(tmp_path / "small.png").shape[:2] == (150, 200)
    tall = mesh_from_triangles([(0, 0), (1, 0), (0, 50)], [(0, 1, 2)])
    plot(tall, tmp_path / "tall.png")
    assert picture(tmp_path / "tall.png").shape[:2] == (600, 800)


@pytest.mark.parametrize("color_by", ["none", "min_angle", "area", "region"])
def test_colour_modes_draw_different_pictures(tmp_path: Path, superior_mesh: Mesh2,
                                              color_by: str) -> None:
    """Each colouring gives a valid picture; the quality and area ones differ from the
    plain one."""
    plot(superior_mesh, tmp_path / f"{color_by}.png", color_by=color_by)
    pixels = picture(tmp_path / f"{color_by}.png")
    if color_by in ("min_angle", "area"):
        plot(superior_mesh, tmp_path / "plain.png")
        assert not np.array_equal(pixels, imread(tmp_path / "plain.png"))


def test_unknown_colouring_and_format_are_refused(tmp_path: Path) -> None:
    """An unknown color_by or picture extension: ValueError, nothing written."""
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    with pytest.raises(ValueError, match="color_by"):
        plot(mesh, tmp_path / "x.png", color_by="rainbow")
    with pytest.raises(ValueError, match=r"\.png"):
        plot(mesh, tmp_path / "x.jpg")
    assert picture_format("A.SVG") == "svg"
    assert not list(tmp_path.iterdir())


def test_plot_refuses_to_overwrite(tmp_path: Path) -> None:
    """An existing picture is kept unless overwrite=True."""
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    target = tmp_path / "x.png"
    target.write_bytes(b"keep")
    with pytest.raises(OverwriteError):
        plot(mesh, target)
    assert target.read_bytes() == b"keep"
    plot(mesh, target, overwrite=True)
    picture(target)


def test_svg_and_pdf_are_reproducible(tmp_path: Path, superior_mesh: Mesh2) -> None:
    """SVG and PDF carry no date: the same mesh gives the same bytes."""
    for suffix in ("svg", "pdf"):
        first = figure_bytes(plot(superior_mesh), suffix)
        second = figure_bytes(plot(superior_mesh), suffix)
        assert first == second, suffix
    plot(superior_mesh, tmp_path / "mesh.svg")
    text = (tmp_path / "mesh.svg").read_text(encoding="utf-8")
    assert text.lstrip().startswith("<?xml") and "<svg" in text


def test_pslg_and_polygon_mesh_pictures(tmp_path: Path, superior: PSLG) -> None:
    """A PSLG (vertices, segments, holes) and a polygon mesh (non-convex polygon
    highlighted) both draw."""
    plot(superior, tmp_path / "pslg.png")
    picture(tmp_path / "pslg.png")
    points = [point2(*p) for p in [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2), (3, 0),
                                   (3, 1)]]
    mesh = PolygonMesh(points, [(0, 1, 2, 3, 4, 5), (1, 6, 7, 2)])
    plot(mesh, tmp_path / "polygons.png", highlight_edges=[(1, 2)])
    pixels = picture(tmp_path / "polygons.png")
    orange = (np.abs(pixels[..., 0] - 0xF6 / 255) < 0.02) & \
             (np.abs(pixels[..., 1] - 0xC6 / 255) < 0.02)
    assert orange.sum() > 1000  # the L-shaped polygon is filled as non-convex


def test_plot_step_highlights_the_step(tmp_path: Path, superior: PSLG) -> None:
    """The picture of step k differs from that of step k-1 and has the orange fill of the
    triangles step k added; steps outside the trace are refused."""
    run = triangulate(superior)
    plot_step(superior, run.trace, 1500, tmp_path / "step.png")
    plot_step(superior, run.trace, 1499, tmp_path / "before.png")
    step = picture(tmp_path / "step.png")
    assert not np.array_equal(step, picture(tmp_path / "before.png"))
    orange = (step[..., 0] > 0.9) & (np.abs(step[..., 1] - 0.7) < 0.15) & (step[..., 2] < 0.5)
    assert orange.sum() > 0
    fig = plot_step(superior, run.trace)
    assert "2517 of 2517" in fig.texts[0].get_text()
    with pytest.raises(ValueError, match="outside"):
        plot_step(superior, run.trace, len(run.trace) + 1)
    with pytest.raises(TraceError):
        plot_step(mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)]), run.trace)


def test_min_angles_of_known_triangles() -> None:
    """The colouring's smallest angles: 45° for a right isosceles triangle, 60° for an
    equilateral one (doubles)."""
    xy = np.array([[0, 0], [1, 0], [0, 1], [0.5, 3 ** 0.5 / 2]], dtype=float)
    angles = min_angles(xy, np.array([[0, 1, 2], [0, 1, 3]]))
    assert angles == pytest.approx([45, 60])


def test_polygon_pictures_have_a_legend() -> None:
    """Issue 26, item 6: a Polylla picture says what its fills and orange edges are, with
    their counts (convex, non-convex polygons; inserted edges)."""
    from geomexact.viz.pictures import figure

    shapes = PolygonMesh(vertices=[point2(x, y) for x, y in
                                   [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2), (3, 0),
                                    (3, 1)]],
                         polygons=[(0, 1, 2, 3, 4, 5), (1, 6, 7, 2)])
    labels = [text.get_text() for text in figure(shapes).axes[0].get_legend().get_texts()]
    assert labels == ["convex polygon (1)", "non-convex polygon (1)"]
    fig = figure(shapes, highlight_edges=[(1, 2)])
    labels = [text.get_text() for text in fig.axes[0].get_legend().get_texts()]
    assert labels == ["convex polygon (1)", "non-convex polygon (1)", "inserted edge (1)"]
