"""Draw the distinct co-spherical cells of ``docs/polyhedral-cells.md``.

Runs the polyhedral census over the 4,096 edge-midpoint patterns of the unit cube (bits 0
to 11: the 1-irregular cubes of Contreras and Hitschfeld-Kahler), and draws every
distinct cell with five or more vertices, one PNG per vertex count under
``docs/images/``: each cell inside the cube's wireframe, its hull shaded, its count of
occurrences above it.  Prints the census table the page shows.

Usage::

    .venv/bin/python docs/polyhedral_pictures.py [--out docs/images] [--force]
"""

from __future__ import annotations

import argparse
import itertools
import math
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from scipy.spatial import ConvexHull

from geomexact.io.files import write_bytes_atomic
from geomexact.mesh3d.cuboid.polyhedral_census import CellShape, polyhedral_census
from geomexact.viz.pictures import figure_bytes

COLUMNS = 8


def _cube_edges() -> list[tuple[tuple[int, ...], tuple[int, ...]]]:
    corners = list(itertools.product((0, 2), repeat=3))
    return [(a, b) for a, b in itertools.combinations(corners, 2)
            if sum(x != y for x, y in zip(a, b, strict=True)) == 1]


def picture(size: int, shapes: list[tuple[CellShape, int]]) -> Figure:
    """The cells of ``size`` vertices, in rows of :data:`COLUMNS`."""
    rows = math.ceil(len(shapes) / COLUMNS)
    fig = Figure(figsize=(COLUMNS * 1.5, rows * 1.6 + 0.4), dpi=90)
    FigureCanvasAgg(fig)
    for index, (shape, count) in enumerate(shapes):
        ax = fig.add_subplot(rows, COLUMNS, index + 1, projection="3d")
        for a, b in _cube_edges():
            ax.plot(*zip(a, b, strict=True), color="0.8", linewidth=0.6)
        hull = ConvexHull(shape)
        ax.add_collection3d(Poly3DCollection(
            [[shape[v] for v in simplex] for simplex in hull.simplices],
            facecolor="#4c8ed9", edgecolor="#1d3f6e", linewidth=0.3, alpha=0.55))
        ax.scatter(*zip(*shape, strict=True), s=6, color="#1d3f6e")
        ax.set_xlim(0, 2)
        ax.set_ylim(0, 2)
        ax.set_zlim(0, 2)
        ax.set_axis_off()
        ax.set_title(f"{count:,}", fontsize=7, pad=-4)
    fig.suptitle(f"co-spherical cells of {size} vertices ({len(shapes)} shapes; the number "
                 "above each: how many cells of that shape in the 4,096 patterns)",
                 fontsize=9)
    return fig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/images")
    parser.add_argument("--force", action="store_true")
    args = parser.parse_args()
    census = polyhedral_census(range(1 << 12))
    print("| vertices | distinct shapes | cells |")
    print("|---|---|---|")
    for size, (shapes, cells) in census.by_vertex_count().items():
        print(f"| {size} | {shapes} | {cells:,} |")
    print(f"\n{census.patterns} patterns, {census.tetrahedra:,} tetrahedra, "
          f"{census.cells:,} cells")
    by_size: dict[int, list[tuple[CellShape, int]]] = {}
    for shape, count in census.shapes.items():
        if len(shape) > 4:
            by_size.setdefault(len(shape), []).append((shape, count))
    for size, shapes in sorted(by_size.items()):
        shapes.sort(key=lambda item: (-item[1], item[0]))
        path = Path(args.out) / f"polyhedral-cells-{size}.png"
        write_bytes_atomic(path, figure_bytes(picture(size, shapes), "png"),
                           overwrite=args.force)
        print(f"![cells of {size} vertices](images/{path.name})")


if __name__ == "__main__":
    main()
