"""Draw the octree meshes of ``docs/octree.md``.

Each picture is made by :func:`geomexact.mesh3d.octree.pipeline.generate` with the stages
that the ``geomexact octree`` command line printed beside it builds, and drawn by
``geomexact.viz.pictures3d`` (the drawing of ``geomexact view x.ele -o x.png --clip x
1/2``): one PNG under ``docs/images/`` each, clipped at x = 1/2 (the grid: y = 1/2) so that
the inside shows (the grid is seen from the other side, where its cut faces).
It prints the Markdown line ``docs/octree.md`` embeds for each picture, with the counts of
the run.

Usage::

    .venv/bin/python docs/octree_pictures.py [--out docs/images] [--force]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path

import attrs
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from geomexact.io.files import write_bytes_atomic
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.pipeline import OctreeMesh, generate
from geomexact.mesh3d.octree.regions import BallRegion, SphereSurfaceRegion
from geomexact.mesh3d.octree.stages import (
    BoxGrid,
    DelaunayPartition,
    PatternPartition,
    RefineWhere,
)
from geomexact.viz.pictures import figure_bytes
from geomexact.viz.pictures3d import DEFAULT_AZIMUTH, QUALITY_MAP, draw_mesh3
from geomexact.viz.scene3d import clip_plane

UNIT = Box((0, 0, 0), (1, 1, 1))
CENTRE = ("1/2", "1/2", "1/2")
RADIUS = "3/10"


@attrs.frozen
class Example:
    """One picture: its file, the command that makes the same mesh, and the runs (one per
    panel, with the panel's title)."""

    name: str
    command: str
    panels: tuple[tuple[str, Callable[[], OctreeMesh]], ...]
    colour: str = "plain"
    axis: str = "x"
    azimuth: float = DEFAULT_AZIMUTH
    clip: str = "1/2"


def _sphere(level: int, surface: bool, final: object = None) -> Callable[[], OctreeMesh]:
    region = (SphereSurfaceRegion if surface else BallRegion)(CENTRE, RADIUS)
    return lambda: generate(UNIT, refinement=RefineWhere(level, region=region),
                            final=final or PatternPartition(), trace=False)


def _stretched() -> OctreeMesh:
    box = Box((0, 0, 0), (2, 1, 1))
    region = SphereSurfaceRegion((1, "1/2", "1/2"), RADIUS)
    return generate(box, initial=BoxGrid(2, 1, 1), refinement=RefineWhere(4, region=region),
                    trace=False)


SPHERE = "--refine-sphere 0.5 0.5 0.5 0.3"
EXAMPLES = (
    Example("octree-sphere-surface.png", f"geomexact octree {SPHERE} --surface --level 6",
            (("the sphere's surface, level 6", _sphere(6, True)),)),
    Example("octree-ball.png", f"geomexact octree {SPHERE} --level 5",
            (("the solid ball, level 5", _sphere(5, False)),)),
    Example("octree-delaunay.png",
            f"geomexact octree {SPHERE} --surface --level 4 [--final delaunay]",
            (("patterns (--final patterns)", _sphere(4, True)),
             ("after Joe's flips (--final delaunay)",
              _sphere(4, True, DelaunayPartition()))),
            colour="quality"),
    Example("octree-grid.png", "geomexact octree --box 0 0 0 2 1 1 --grid 2 1 1 "
            "--refine-sphere 1 0.5 0.5 0.3 --surface --level 4",
            (("[0,2]x[0,1]x[0,1], grid 2 x 1 x 1, a sphere's surface to level 4",
              _stretched),), axis="y", azimuth=120.0),
)


def picture(example: Example, runs: list[OctreeMesh]) -> tuple[Figure, list[str]]:
    """The panels of one example, 450 pixels wide each, and one caption per panel."""
    count = len(runs)
    width = 4.5 * count + (0.6 if example.colour == "quality" else 0.0)
    fig = Figure(figsize=(width, 4.6), dpi=100)
    FigureCanvasAgg(fig)
    captions = []
    for index, ((label, _), run) in enumerate(zip(example.panels, runs, strict=True)):
        left = index * 4.5 / width
        ax = fig.add_axes((left + 0.01, 0.02, 4.5 / width - 0.02, 0.84))
        drawing = draw_mesh3(ax, run.mesh, clip=clip_plane(example.axis, example.clip),
                             colour=example.colour, azimuth=example.azimuth,
                             colorbar=False)  # type: ignore[arg-type]
        quality = run.quality()
        caption = (f"{label}: {run.octree.leaf_count:,} leaves, {drawing.tetrahedra:,} "
                   f"tetrahedra, {run.mesh.vertex_count:,} vertices; dihedral angles "
                   f"{quality.min_dihedral:.1f}°–{quality.max_dihedral:.1f}°")
        captions.append(caption)
        ax.set_title(f"{label}\n{drawing.tetrahedra:,} tetrahedra ({drawing.kept:,} with "
                     f"{example.axis} ≤ {example.clip} shown)", fontsize=9)
    if example.colour == "quality":
        bar = fig.add_axes((1 - 0.5 / width, 0.12, 0.15 / width, 0.6))
        fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), QUALITY_MAP), cax=bar,
                     label="radius ratio")
    return fig, captions


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "images")
    parser.add_argument("--force", action="store_true", help="replace existing pictures")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for example in EXAMPLES:
        began = time.perf_counter()
        runs = [make() for _, make in example.panels]
        fig, captions = picture(example, runs)
        data = figure_bytes(fig, "png")
        write_bytes_atomic(args.out / example.name, data, overwrite=args.force)
        print(f"![{captions[0].split(':')[0]}](images/{example.name})  ")
        print(f"`{example.command}` — " + "; ".join(captions)
              + f" ({len(data) // 1024} KB, {time.perf_counter() - began:.1f} s)\n")


if __name__ == "__main__":
    main()
