"""Two meshes side by side in one picture, for debugging with traces: the meshes of two
traces after the step where they part (``geomexact trace diff --picture``), or the mesh
before and after the first failing step (``geomexact trace bisect -o``).

Triangle meshes are drawn by :func:`geomexact.viz.pictures.draw` with chosen triangles
filled in orange; tetrahedral meshes by :func:`geomexact.viz.pictures3d.draw_mesh3`,
which cannot highlight cells (:func:`highlights_cells` says which).  Figures are made
without pyplot, ``size`` inches at ``dpi`` exactly, the same bytes for the same meshes."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.viz.matplotlib_names import Figure, FigureCanvasAgg
from geomexact.viz.pictures import DEFAULT_DPI, draw, write_figure
from geomexact.viz.pictures3d import draw_mesh3

__all__ = ["PAIR_SIZE", "figure_pair", "highlights_cells", "plot_pair"]

PAIR_SIZE = (12.0, 6.0)
"""The default size of a picture of two meshes, in inches (1200 × 600 pixels)."""


def highlights_cells(mesh: Mesh2 | Mesh3) -> bool:
    """True when :func:`figure_pair` can highlight cells of ``mesh`` (a triangle mesh)."""
    return isinstance(mesh, Mesh2)


def _frame(meshes: Sequence[Mesh2 | Mesh3], axes: Sequence[Any]) -> None:
    """Give 2D drawings the same limits, so that both show the same region."""
    if not all(isinstance(mesh, Mesh2) for mesh in meshes):
        return
    lows = [ax.get_xlim() for ax in axes]
    highs = [ax.get_ylim() for ax in axes]
    x = (min(low[0] for low in lows), max(low[1] for low in lows))
    y = (min(high[0] for high in highs), max(high[1] for high in highs))
    for ax in axes:
        ax.set_xlim(*x)
        ax.set_ylim(*y)


def figure_pair(
    left: Mesh2 | Mesh3,
    right: Mesh2 | Mesh3,
    *,
    titles: tuple[str, str] = ("", ""),
    highlights: tuple[Iterable[tuple[int, ...]], Iterable[tuple[int, ...]]] = ((), ()),
    title: str | None = None,
    size: tuple[float, float] = PAIR_SIZE,
    dpi: int = DEFAULT_DPI,
) -> Figure:
    """A new figure with ``left`` and ``right`` side by side, each under its title; in a
    triangle mesh the triangles of its ``highlights`` entry are filled in orange (in a
    tetrahedral mesh nothing is highlighted: see :func:`highlights_cells`)."""
    fig = Figure(figsize=size, dpi=dpi)
    FigureCanvasAgg(fig)
    axes = [fig.add_axes((0.01, 0.02, 0.48, 0.86)), fig.add_axes((0.51, 0.02, 0.48, 0.86))]
    for ax, mesh, label, cells in zip(axes, (left, right), titles, highlights, strict=True):
        if isinstance(mesh, Mesh2):
            draw(ax, mesh, highlight_triangles=[(t[0], t[1], t[2]) for t in cells])
        else:
            draw_mesh3(ax, mesh)
        ax.set_title(label, fontsize=10)
    _frame((left, right), axes)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def plot_pair(
    left: Mesh2 | Mesh3,
    right: Mesh2 | Mesh3,
    path: str | Path | None = None,
    *,
    overwrite: bool = False,
    **options: Any,
) -> Figure:
    """:func:`figure_pair`, written to ``path`` (``.png``, ``.svg`` or ``.pdf``,
    atomically, refusing to replace a file unless ``overwrite``) when given."""
    fig = figure_pair(left, right, **options)
    if path is not None:
        write_figure(fig, path, overwrite=overwrite)
    return fig
