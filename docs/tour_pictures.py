"""Draw the pictures of ``docs/tour.md``: each algorithm run by the package on a small
input and drawn by ``geomexact.viz``.

The documentation build calls :func:`make_all` (``docs/_site_tools.py``, at
``builder-inited``) with ``docs/_generated/tour``; it writes one PNG per picture and one
Markdown fragment (``NAME.md``: the picture and a caption with the counts of the run)
that ``docs/tour.md`` includes.  Nothing here is committed: the pictures are remade by
each build (a few seconds each).

Usage::

    .venv/bin/python docs/tour_pictures.py [--out docs/_generated/tour] [--only NAME]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure

from geomexact import (
    Circle,
    MaxArea,
    Mesh2,
    Polygon,
    convex_decomposition,
    io,
    mesh_from_triangles,
    polylla,
    refine,
    total_area,
    triangulate,
)
from geomexact.viz.pictures import QUALITY_BOUNDS, QUALITY_COLORS, draw, figure_bytes

PANEL = (4.2, 4.0)
"""Inches of one panel (at 100 dpi)."""


def superior() -> Mesh2:
    """The constrained Delaunay triangulation of the bundled Lake Superior PSLG."""
    path = resources.files("geomexact") / "data" / "superior.poly"
    result = triangulate(io.read(str(path)))
    return result.mesh


def unit_square() -> Mesh2:
    """The unit square cut by its diagonal."""
    return mesh_from_triangles([("0", "0"), ("1", "0"), ("1", "1"), ("0", "1")],
                               [(0, 1, 2), (0, 2, 3)])


def _panels(count: int, height: float = PANEL[1],
            bar: float = 0.0) -> tuple[Figure, list[Any]]:
    """A figure of ``count`` panels side by side (and ``bar`` inches on the right)."""
    total = PANEL[0] * count + bar
    fig = Figure(figsize=(total, height), dpi=100)
    FigureCanvasAgg(fig)
    width = PANEL[0] / total
    axes = [fig.add_axes((index * width + 0.005, 0.02, width - 0.01, 0.76))
            for index in range(count)]
    return fig, axes


def _angle_bar(fig: Figure, bar: float) -> None:
    """The colour bar of ``color_by="min_angle"`` in the last ``bar`` inches."""
    cmap = ListedColormap(list(QUALITY_COLORS))
    width = fig.get_figwidth()
    cax = fig.add_axes((1 - 0.7 * bar / width, 0.12, 0.15 * bar / width, 0.6))
    fig.colorbar(ScalarMappable(BoundaryNorm(QUALITY_BOUNDS, cmap.N), cmap), cax=cax,
                 label="smallest angle (°)")


def lepp_methods() -> tuple[Figure, str]:
    """Lake Superior refined to one max area by the three Lepp methods."""
    mesh = superior()
    limit = total_area(mesh) / 800
    fig, axes = _panels(3, 4.0, bar=1.0)
    counts = []
    for ax, method in zip(axes, ("bisection", "centroid", "quasi"), strict=True):
        result = refine(mesh, MaxArea(limit), method=method)
        draw(ax, result.mesh, color_by="min_angle", colorbar=False)
        ax.set_title(f"method={method!r}\n{result.mesh.triangle_count:,} triangles, "
                     f"{len(result.trace):,} steps", fontsize=10)
        counts.append(f"{method} {result.mesh.triangle_count:,} triangles in "
                      f"{len(result.trace):,} steps")
    _angle_bar(fig, 1.0)
    fig.suptitle("Lake Superior (528 triangles), MaxArea(total / 800), filled by smallest "
                 "angle", fontsize=11)
    caption = ("The constrained Delaunay triangulation of the bundled Lake Superior PSLG "
               "refined to `MaxArea(total_area(mesh) / 800)` by each method: "
               + "; ".join(counts) + ".")
    return fig, caption


CIRCLE = Circle("0.3", "0.3", "0.2")
STAR = Polygon([("0.55", "0.55"), ("0.95", "0.6"), ("0.7", "0.7"), ("0.75", "0.95"),
                ("0.6", "0.72")])


def local_refinement() -> tuple[Figure, str]:
    """The unit square refined finely inside a circle, and inside a polygon."""
    square = refine(unit_square(), MaxArea("1/128"), method="bisection").mesh
    fig, axes = _panels(2)
    counts = []
    for ax, (name, region) in zip(axes, (("Circle(0.3, 0.3, 0.2)", CIRCLE),
                                         ("a Polygon of 5 vertices", STAR)), strict=True):
        result = refine(square, MaxArea("1/4000"), region=region, method="bisection")
        draw(ax, result.mesh)
        if isinstance(region, Circle):
            centre = (float(region.center_x), float(region.center_y))
            ax.add_patch(_circle_patch(centre, float(region.radius)))
        else:
            ax.add_patch(_polygon_patch([(float(p.x), float(p.y)) for p in region.vertices]))
        ax.set_title(f"region={name}\n{result.mesh.triangle_count:,} triangles", fontsize=10)
        counts.append(f"{result.mesh.triangle_count:,} triangles ({name})")
    fig.suptitle("the unit square, MaxArea(1/4000) in a region, Lepp bisection", fontsize=11)
    caption = (f"The unit square refined by Lepp bisection to `MaxArea(\"1/128\")` "
               f"({square.triangle_count} triangles), then to "
               "`MaxArea(\"1/4000\")` only in a region (dashed): " + " and ".join(counts)
               + ". A triangle is in the region when one of its vertices is; Lepp keeps "
               "the mesh conforming, so the refinement grades out of the region.")
    return fig, caption


def _circle_patch(centre: tuple[float, float], radius: float) -> object:
    from matplotlib.patches import Circle as CirclePatch

    return CirclePatch(centre, radius, fill=False, edgecolor="#c62828", linestyle="--",
                       linewidth=1.2)


def _polygon_patch(points: list[tuple[float, float]]) -> object:
    from matplotlib.patches import Polygon as PolygonPatch

    return PolygonPatch(points, closed=True, fill=False, edgecolor="#c62828",
                        linestyle="--", linewidth=1.2)


def polylla_convex() -> tuple[Figure, str]:
    """A triangle mesh, its Polylla mesh, and the convex decomposition of that."""
    start = superior()
    mesh = refine(start, MaxArea(total_area(start) / 600), method="quasi").mesh
    polygons = polylla(mesh)
    convex = convex_decomposition(polygons)
    fig, axes = _panels(3, 4.0)
    draw(axes[0], mesh)
    axes[0].set_title(f"triangles\n{mesh.triangle_count:,}", fontsize=10)
    draw(axes[1], polygons)
    axes[1].set_title(f"polylla(mesh)\n{len(polygons.polygons):,} polygons, "
                      f"{convex.nonconvex_before:,} not convex (orange)", fontsize=10)
    draw(axes[2], convex.mesh)
    axes[2].set_title(f"convex_decomposition(...)\n{len(convex.mesh.polygons):,} convex "
                      f"polygons, {len(convex.inserted_edges):,} edges inserted", fontsize=10)
    fig.suptitle("Polylla, then its convex decomposition (Lake Superior, quasi-Delaunay "
                 "refinement)", fontsize=11)
    caption = (f"A triangle mesh of Lake Superior ({mesh.triangle_count:,} triangles), its "
               f"Polylla mesh ({len(polygons.polygons):,} polygons, "
               f"{convex.nonconvex_before:,} of them not convex, in orange) and the convex "
               f"decomposition of that ({len(convex.mesh.polygons):,} convex polygons: "
               f"{len(convex.inserted_edges):,} triangle edges put back).")
    return fig, caption


def cuboid_flips() -> tuple[Figure, str]:
    """One cuboid pattern before and after Joe's flips (``docs/cuboid_pictures.py``)."""
    import cuboid_pictures  # docs/, on sys.path beside this file

    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    run = partition_cuboid(70688, improve=True)
    fig = cuboid_pictures.picture("70688", run)
    caption = (f"Pattern 70688 of the 1-irregular cuboid: the partition as made "
               f"({run.partition.tetrahedron_count} tetrahedra) and after Joe's flips "
               f"({run.mesh.tetrahedron_count}; {cuboid_pictures._flips(run)}), clipped at "
               f"x = 1/2, faces coloured by radius ratio.")
    return fig, caption


def octree_clip() -> tuple[Figure, str]:
    """The octree mesher around a sphere's surface at level 4, clipped at x = 1/2."""
    import octree_pictures  # docs/, on sys.path beside this file

    example = octree_pictures.Example(
        "tour-octree.png",
        f"geomexact octree {octree_pictures.SPHERE} --surface --level 4",
        (("the sphere's surface, level 4", octree_pictures._sphere(4, True)),),
        colour="quality")
    runs = [make() for _, make in example.panels]
    fig, captions = octree_pictures.picture(example, runs)
    caption = (f"`{example.command}`: {captions[0]}. Clipped at x = 1/2, faces coloured by "
               f"radius ratio.")
    return fig, caption


PICTURES: dict[str, Callable[[], tuple[Figure, str]]] = {
    "lepp-methods": lepp_methods,
    "local-refinement": local_refinement,
    "polylla-convex": polylla_convex,
    "cuboid-flips": cuboid_flips,
    "octree-clip": octree_clip,
}
"""Each picture of the tour by name: a function returning the figure and its caption."""


def fragment(name: str, caption: str, seconds: float) -> str:
    """The Markdown that ``docs/tour.md`` includes for one picture."""
    return (f"![{name}](/_generated/tour/{name}.png)\n\n{caption} *(Drawn by "
            f"`docs/tour_pictures.py` at this build, in {seconds:.1f} s.)*\n")


def make_one(name: str, out: Path) -> float:
    """Make one picture and its fragment under ``out``; return the seconds it took."""
    began = time.perf_counter()
    fig, caption = PICTURES[name]()
    (out / f"{name}.png").write_bytes(figure_bytes(fig, "png"))
    seconds = time.perf_counter() - began
    (out / f"{name}.md").write_text(fragment(name, caption, seconds), encoding="utf-8")
    return seconds


def make_all(out: Path, only: list[str] | None = None) -> dict[str, float]:
    """Make every picture (or ``only`` those) under ``out``; return the seconds of each."""
    out.mkdir(parents=True, exist_ok=True)
    return {name: make_one(name, out) for name in (only or list(PICTURES))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path,
                        default=Path(__file__).parent / "_generated" / "tour")
    parser.add_argument("--only", action="append", choices=list(PICTURES))
    args = parser.parse_args()
    for name, seconds in make_all(args.out, args.only).items():
        print(f"{name}: {seconds:.1f} s")


if __name__ == "__main__":
    main()
