"""Pictures of meshes too fine for their edges (issue 26, item 6): edges under a few
pixels are left out (said on the picture) and the faces are filled by smallest angle, so
the picture shows the mesh's quality instead of a solid square; a coarse mesh keeps its
edges and its plain fill."""

from __future__ import annotations

import pytest

pytest.importorskip("matplotlib")

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

from geomexact import mpq, point2, triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.viz.pictures import draw


def _square(area: object) -> object:
    corners = [point2(0, 0), point2(1, 0), point2(1, 1), point2(0, 1)]
    mesh = triangulate(PSLG(vertices=corners, segments=[(0, 1, 1), (1, 2, 1), (2, 3, 1),
                                                        (3, 0, 1)])).mesh
    return refine(mesh, MaxArea(area)).mesh


def _drawn(mesh: object, inches: float) -> tuple[Figure, object]:
    fig = Figure(figsize=(inches, inches), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.05, 0.05, 0.8, 0.9))
    draw(ax, mesh)  # type: ignore[arg-type]
    return fig, ax


def test_a_dense_mesh_drops_its_edges_and_shows_quality() -> None:
    mesh = _square(mpq(1, 20_000))  # ~32,768 triangles: edges under a pixel at 4 inches
    fig, ax = _drawn(mesh, 4)
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]  # type: ignore[attr-defined]
    assert len(lines) == 2  # the boundary and the segments only
    texts = [t.get_text() for t in ax.texts]  # type: ignore[attr-defined]
    assert any("edges under 3 px left out" in text for text in texts)
    assert len(fig.axes) == 2  # the smallest-angle colour bar


def test_a_coarse_mesh_keeps_its_edges() -> None:
    mesh = _square(mpq(1, 50))
    fig, ax = _drawn(mesh, 8)
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]  # type: ignore[attr-defined]
    assert len(lines) == 3  # the edges, the boundary and the segments
    assert len(fig.axes) == 1  # plain fill, no colour bar
