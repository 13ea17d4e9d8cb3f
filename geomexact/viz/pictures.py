"""Pictures of meshes with matplotlib: PNG, SVG or PDF.

:func:`plot` draws a triangle mesh (constrained edges highlighted, optionally filled by
minimum angle, area or region), a polygon mesh (non-convex polygons and chosen edges
highlighted) or a PSLG (vertices, segments, holes, region seeds); :func:`plot_step` draws
the mesh after step k of a trace with the triangles that step added and removed.  Figures
are made without pyplot (no global state, safe in threads and servers), with a fixed size
in pixels: ``size`` inches times ``dpi`` (no tight bounding box), so a picture's size does
not depend on its content.
"""

from __future__ import annotations

import io as _io
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any, Literal, cast

import numpy as np

from geomexact.io.files import write_bytes_atomic
from geomexact.mesh2d.quality import areas, min_angles
from geomexact.mesh2d.snapshot import Edge, Triangle
from geomexact.trace.record import Trace
from geomexact.viz.matplotlib_names import (
    BoundaryNorm,
    Figure,
    FigureCanvasAgg,
    LineCollection,
    ListedColormap,
    LogNorm,
    Normalize,
    PolyCollection,
    rc_context,
)
from geomexact.viz.scene import (
    Scene,
    Viewable,
    doubles,
    history_of,
    indices,
    scene_of,
    trace_start,
)

ColorBy = Literal["none", "min_angle", "area", "region"]
COLOR_BY: tuple[str, ...] = ("none", "min_angle", "area", "region")

PICTURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
"""Extensions :func:`plot` writes, and matplotlib's name for each."""

DEFAULT_SIZE = (8.0, 6.0)
DEFAULT_DPI = 100

EDGE_COLOR = "#3b5b8c"
BOUNDARY_COLOR = "#10233f"
SEGMENT_COLOR = "#b3261e"
PLAIN_FILL = "#e3ecf7"
NONCONVEX_FILL = "#f6c6a8"
ADDED_FILL = "#ff8c00"
REMOVED_COLOR = "#7b1fa2"
HIGHLIGHT_COLOR = "#e65100"
QUALITY_BOUNDS = (0, 10, 20, 30, 40, 50, 60)
QUALITY_COLORS = ("#d7301f", "#fc8d59", "#fdcc8a", "#c7e9b4", "#7fcdbb", "#2c7fb8")


def picture_format(path: str | Path) -> str:
    """matplotlib's format name for ``path``'s extension; ``ValueError`` for others."""
    suffix = Path(path).suffix.lower()
    if suffix not in PICTURE_FORMATS:
        known = ", ".join(sorted(PICTURE_FORMATS))
        raise ValueError(f"{path}: a picture must be one of {known}")
    return PICTURE_FORMATS[suffix]


def _xy(scene: Scene) -> np.ndarray:
    return np.frombuffer(scene.xy.tobytes(), dtype=np.float64).reshape(-1, 2)


def _ids(values: Iterable[int], width: int) -> np.ndarray:
    flat = np.fromiter(values, dtype=np.int64)
    return flat.reshape(-1, width)


def _unique_edges(faces: Sequence[Sequence[int]]) -> tuple[np.ndarray, np.ndarray]:
    """All edges (u < v) of the faces, and the boundary ones (in one face only)."""
    pairs = []
    for face in faces:
        count = len(face)
        for index in range(count):
            u, v = face[index], face[(index + 1) % count]
            pairs.append((u, v) if u < v else (v, u))
    if not pairs:
        empty = np.zeros((0, 2), dtype=np.int64)
        return empty, empty
    return _counted_edges(np.array(pairs, dtype=np.int64))


def _counted_edges(pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows (u < v) of ``pairs``, sorted, and those that occur once.  Each
    row is one int64 key (u << 32 | v: ids are below 2^32), so the sort is of integers,
    not of rows (``np.unique(axis=0)`` took 2.7 s of a 500,000-triangle picture)."""
    keys = (pairs[:, 0] << 32) | pairs[:, 1]
    distinct, counts = np.unique(keys, return_counts=True)
    edges = np.column_stack((distinct >> 32, distinct & 0xFFFFFFFF))
    return edges, edges[counts == 1]


def _triangle_edges(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if not len(triangles):
        empty = np.zeros((0, 2), dtype=np.int64)
        return empty, empty
    pairs = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    pairs.sort(axis=1)
    return _counted_edges(pairs.astype(np.int64))


def _polygons(array: np.ndarray) -> Sequence[Any]:
    """An (n, k, 2) array as the sequence of polygons matplotlib's collections take."""
    return cast(Sequence[Any], array)


def _lines(xy: np.ndarray, edges: np.ndarray, **style: Any) -> LineCollection:
    return LineCollection(_polygons(xy[edges] if len(edges) else np.zeros((0, 2, 2))),
                          **style)


MIN_EDGE_PIXELS = 3
"""Below this median edge length on the picture, a triangle mesh's edges are left out
(they would paint every face over) and a plain fill becomes the smallest-angle fill."""


def _edge_pixels(ax: Any, xy: np.ndarray, triangles: np.ndarray) -> float:
    """The median length, in pixels of ``ax``, of the first edges of (up to 20,000 of) the
    triangles, the whole mesh fitted in the axes."""
    finite = xy[np.isfinite(xy).all(axis=1)]
    if not len(finite):
        return float("inf")
    extent = float(max(np.ptp(finite[:, 0]), np.ptp(finite[:, 1]))) * 1.06
    box = ax.get_window_extent()
    pixels = min(box.width, box.height)
    sample = triangles[:: max(1, len(triangles) // 20_000)]
    lengths = np.hypot(*(xy[sample[:, 1]] - xy[sample[:, 0]]).T)
    if extent <= 0 or not len(lengths):
        return float("inf")
    return float(np.median(lengths) / extent * pixels)


def _polygon_legend(ax: Any, polygons: int, nonconvex: int, inserted: int) -> None:
    """The key of a polygon mesh's picture, above it: what the fills and the orange
    edges are, with their counts."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Any] = [Patch(facecolor=PLAIN_FILL, edgecolor=EDGE_COLOR,
                                label=f"convex polygon ({polygons - nonconvex:,})")]
    if nonconvex:
        handles.append(Patch(facecolor=NONCONVEX_FILL, edgecolor=EDGE_COLOR,
                             label=f"non-convex polygon ({nonconvex:,})"))
    if inserted:
        handles.append(Line2D([], [], color=HIGHLIGHT_COLOR, linewidth=2.0,
                              label=f"inserted edge ({inserted:,})"))
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.0),
              ncol=len(handles), fontsize=8, frameon=False)


def draw(
    ax: Any,
    value: Viewable | Scene,
    *,
    color_by: ColorBy = "none",
    highlight_triangles: Iterable[Triangle] = (),
    removed_triangles: Iterable[Triangle] = (),
    highlight_edges: Iterable[Edge] = (),
    show_vertices: bool | None = None,
    colorbar: bool = True,
) -> Scene:
    """Draw ``value`` into the matplotlib axes ``ax``; return its scene.

    Triangle meshes: edges, boundary (dark, thicker), constrained edges (red); filled
    plainly or by ``color_by`` (a mesh whose edges would be under
    :data:`MIN_EDGE_PIXELS` on the picture: no edges, and filled by smallest angle unless
    ``color_by`` says otherwise) (``"min_angle"`` in 10° bands, ``"area"`` on a log scale,
    ``"region"`` by the first triangle attribute), with a colour bar.  Polygon meshes:
    non-convex polygons filled in orange.  PSLGs: vertices, segments, holes (×) and region
    seeds (+).  ``highlight_triangles`` are filled in orange, ``removed_triangles`` outlined
    dashed in purple, ``highlight_edges`` drawn thick in orange.  ``show_vertices``
    (dots at the vertices) defaults to "when there are no faces" (a PSLG, a point set).
    """
    if color_by not in COLOR_BY:
        raise ValueError(f"color_by must be one of {', '.join(COLOR_BY)}, not {color_by!r}")
    scene = value if isinstance(value, Scene) else scene_of(value, summary=False,
                                                             exact_budget=0)
    xy = _xy(scene)
    ax.set_aspect("equal")
    ax.set_axis_off()
    faces_drawn = False
    if scene.kind == "triangles" and scene.triangle_count:
        triangles = _ids(scene.triangles, 3)
        # edges shorter than a few pixels only paint the faces over: leave them out, and
        # show the faces' quality instead of a plain fill
        dense = _edge_pixels(ax, xy, triangles) < MIN_EDGE_PIXELS
        if dense and color_by == "none":
            color_by = "min_angle"
        collection = PolyCollection(_polygons(xy[triangles]), edgecolors="none", linewidths=0)
        values = None
        if color_by == "min_angle":
            values = min_angles(xy, triangles)
            cmap = ListedColormap(list(QUALITY_COLORS))
            collection.set_cmap(cmap)
            collection.set_norm(BoundaryNorm(QUALITY_BOUNDS, cmap.N))
            label = "smallest angle (°)"
        elif color_by == "area":
            values = areas(xy, triangles)
            positive = values[values > 0]
            low = float(positive.min()) if len(positive) else 1.0
            high = float(values.max()) if len(values) else 1.0
            collection.set_cmap("viridis")
            collection.set_norm(LogNorm(low, max(high, low * (1 + 1e-9))))
            values = np.maximum(values, low)
            label = "area"
        elif color_by == "region" and scene.regions is not None:
            values = np.frombuffer(scene.regions.tobytes(), dtype=np.float64)
            finite = values[np.isfinite(values)]
            low = float(finite.min()) if len(finite) else 0.0
            high = float(finite.max()) if len(finite) else 1.0
            collection.set_cmap("tab10")
            collection.set_norm(Normalize(low, high if high > low else low + 1))
            label = "region attribute"
        if values is None:
            collection.set_facecolor(PLAIN_FILL)
        else:
            collection.set_array(values)
        ax.add_collection(collection)
        if values is not None and colorbar:
            ax.figure.colorbar(collection, ax=ax, shrink=0.8, label=label)
        edges, boundary = _triangle_edges(triangles)
        if dense:
            ax.text(1.0, 0.0, f"edges under {MIN_EDGE_PIXELS} px left out",
                    transform=ax.transAxes, fontsize=8, color="#555555", ha="right",
                    va="bottom")
        else:
            ax.add_collection(_lines(xy, edges, colors=EDGE_COLOR, linewidths=0.35))
        ax.add_collection(_lines(xy, boundary, colors=BOUNDARY_COLOR, linewidths=1.0))
        faces_drawn = True
    elif scene.kind == "polygons" and scene.polygon_count:
        polygons = [scene.polygon(index) for index in range(scene.polygon_count)]
        nonconvex = set(scene.nonconvex)
        colors = [NONCONVEX_FILL if index in nonconvex else PLAIN_FILL
                  for index in range(len(polygons))]
        ax.add_collection(PolyCollection([xy[list(p)] for p in polygons], facecolors=colors,
                                         edgecolors="none"))
        edges, boundary = _unique_edges(polygons)
        ax.add_collection(_lines(xy, edges, colors=EDGE_COLOR, linewidths=0.5))
        ax.add_collection(_lines(xy, boundary, colors=BOUNDARY_COLOR, linewidths=1.0))
        faces_drawn = True
    if len(scene.segments):
        ax.add_collection(_lines(xy, _ids(scene.segments, 2), colors=SEGMENT_COLOR,
                                 linewidths=1.2))
    added = [tuple(t) for t in highlight_triangles]
    if added:
        ax.add_collection(PolyCollection(_polygons(xy[np.array(added, dtype=np.int64)]),
                                         facecolors=ADDED_FILL, edgecolors=HIGHLIGHT_COLOR,
                                         alpha=0.7, linewidths=0.8))
    removed = [tuple(t) for t in removed_triangles]
    if removed:
        ax.add_collection(PolyCollection(_polygons(xy[np.array(removed, dtype=np.int64)]),
                                         facecolors="none", edgecolors=REMOVED_COLOR,
                                         linestyles="--", linewidths=0.9))
    marked = [tuple(e) for e in highlight_edges]
    if marked:
        ax.add_collection(_lines(xy, np.array(marked, dtype=np.int64), colors=HIGHLIGHT_COLOR,
                                 linewidths=2.0))
    if scene.kind == "polygons" and scene.polygon_count:
        _polygon_legend(ax, scene.polygon_count, len(scene.nonconvex), len(marked))
    count = scene.vertex_count
    if show_vertices is None:
        show_vertices = not faces_drawn
    if show_vertices and count:
        ax.plot(xy[:, 0], xy[:, 1], ".", color="#1f3b73",
                markersize=3 if count <= 2000 else 1, linestyle="none")
    if len(scene.holes):
        holes = np.frombuffer(scene.holes.tobytes()).reshape(-1, 2)
        ax.plot(holes[:, 0], holes[:, 1], "x", color="#c62828", markersize=6)
    if len(scene.seeds):
        seeds = np.frombuffer(scene.seeds.tobytes()).reshape(-1, 2)
        ax.plot(seeds[:, 0], seeds[:, 1], "+", color="#2e7d32", markersize=7)
    if scene.scale_exponent:
        # the axes are off: say how the drawing was scaled (exactly, to fit the doubles)
        ax.text(0.0, 0.0, f"coordinates × 2^{-scene.scale_exponent}", transform=ax.transAxes,
                fontsize=8, color="#555555", ha="left", va="bottom")
    if count:
        finite = xy[np.isfinite(xy).all(axis=1)]
        x0, y0 = finite.min(axis=0)
        x1, y1 = finite.max(axis=0)
        pad = 0.03 * max(x1 - x0, y1 - y0) or 1.0
        ax.set_xlim(x0 - pad, x1 + pad)
        ax.set_ylim(y0 - pad, y1 + pad)
    return scene


def figure(
    value: Viewable | Scene,
    *,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A new matplotlib :class:`Figure` (not registered with pyplot) showing ``value``;
    ``options`` go to :func:`draw`."""
    return titled_figure(size, dpi, title,
                         lambda ax: _default_title(draw(ax, value, **options)))


def titled_figure(
    size: tuple[float, float], dpi: int, title: str | None, draw_on: Callable[[Any], str]
) -> Figure:
    """A new :class:`Figure` (not registered with pyplot) of ``size`` inches at ``dpi``
    with one axes, which ``draw_on`` draws on, returning the default title; above it,
    ``title``, or that default when ``title`` is None."""
    fig = Figure(figsize=size, dpi=dpi)
    FigureCanvasAgg(fig)
    default = draw_on(fig.add_axes((0.02, 0.02, 0.96, 0.9)))
    fig.suptitle(title if title is not None else default, fontsize=11)
    return fig


def _default_title(scene: Scene) -> str:
    if scene.kind == "triangles":
        return f"{scene.vertex_count:,} vertices, {scene.triangle_count:,} triangles"
    if scene.kind == "polygons":
        return f"{scene.vertex_count:,} vertices, {scene.polygon_count:,} polygons"
    return f"PSLG: {scene.vertex_count:,} vertices, {len(scene.segments) // 2:,} segments"


def figure_bytes(fig: Figure, format: str = "png") -> bytes:
    """The figure encoded as ``format`` (png, svg or pdf).  No creation date and fixed
    SVG ids: equal figures give equal bytes."""
    buffer = _io.BytesIO()
    metadata: dict[str, Any] = {"png": {"Software": None}, "svg": {"Date": None},
                                "pdf": {"CreationDate": None}}.get(format, {})
    # a fixed salt: SVG element ids are hashes, random by default
    with rc_context({"svg.hashsalt": "geomexact"}):
        fig.savefig(buffer, format=format, metadata=metadata)
    return buffer.getvalue()


def write_figure(fig: Figure, path: str | Path, *, overwrite: bool) -> None:
    """Write ``fig`` to ``path`` in the format its extension names (:func:`figure_bytes`),
    atomically, refusing to replace a file unless ``overwrite``."""
    write_bytes_atomic(path, figure_bytes(fig, picture_format(path)), overwrite=overwrite)


def plot(
    value: Viewable,
    path: str | Path | None = None,
    *,
    overwrite: bool = False,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A picture of a mesh, PSLG or polygon mesh; written to ``path`` (``.png``, ``.svg``
    or ``.pdf``, atomically, refusing to replace a file unless ``overwrite``) when given.

    ``options``: ``color_by`` (``"none"``, ``"min_angle"``, ``"area"``, ``"region"``),
    ``highlight_triangles``, ``removed_triangles``, ``highlight_edges``, ``show_vertices``
    (see :func:`draw`).  The picture is ``size`` inches at ``dpi`` (default 800 × 600
    pixels).  Returns the figure (for further drawing; it is not shown anywhere).
    """
    fig = figure(value, title=title, size=size, dpi=dpi, **options)
    if path is not None:
        write_figure(fig, path, overwrite=overwrite)
    return fig


def plot_step(
    start: Viewable,
    trace: Trace,
    step: int | None = None,
    path: str | Path | None = None,
    *,
    overwrite: bool = False,
    title: str | None = None,
    **options: Any,
) -> Figure:
    """A picture of the mesh after ``step`` steps of ``trace`` (all when None) on
    ``start`` (a mesh, or the PSLG a triangulation started from), with the triangles that
    step added filled in orange and those it removed outlined in purple.  The trace is
    replayed with every digest checked."""
    history = history_of(trace_start(start), trace)
    chosen = history.steps if step is None else step
    if not 0 <= chosen <= history.steps:
        raise ValueError(f"step {chosen} is outside 0..{history.steps}")
    final = history.final
    triangles = history.triangles_at(chosen)
    segments = history.segments_at(chosen)
    base = scene_of(final, summary=False, exact_budget=0)
    count = history.vertex_counts[chosen]
    scene = Scene(
        kind="triangles",
        xy=doubles(base.xy[: 2 * count]),
        exact=None,
        triangles=indices(v for t in triangles for v in t),
        segments=indices(v for s in segments for v in s),
        scale_exponent=base.scale_exponent,
    )
    added: list[Triangle] = []
    removed: list[Triangle] = []
    if chosen:
        added, removed = history.step_changes(chosen)
        alive = set(triangles)
        removed = [t for t in removed if t not in alive]
    if title is None:
        label = history.labels[chosen - 1] if chosen else "the input"
        title = (f"step {chosen} of {history.steps}: {label} — "
                 f"{len(triangles):,} triangles")
    fig = figure(scene, title=title, highlight_triangles=added, removed_triangles=removed,
                 **options)
    if path is not None:
        write_figure(fig, path, overwrite=overwrite)
    return fig

