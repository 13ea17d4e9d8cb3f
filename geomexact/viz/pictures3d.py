"""Pictures of tetrahedral meshes with matplotlib: PNG, SVG or PDF.

:func:`plot_mesh3` draws a :class:`~geomexact.mesh3d.snapshot.Mesh3` as its boundary
surface, shaded by a fixed light, seen from a chosen elevation and azimuth (orthographic).
A clip plane (:class:`~geomexact.viz.scene3d.Clip`) removes the tetrahedra whose centroid
lies beyond it (decided exactly) and shows the faces it cuts open; faces can be coloured by
their tetrahedron's radius ratio.  Only the faces that can be seen are drawn: the boundary
faces of the kept tetrahedra, and of those only the ones facing the viewer, painted from
back to front.  So the cost grows with the surface, not the volume: the numpy work on all
tetrahedra is O(m log m) and matplotlib draws O(m^(2/3)) faces on a regular mesh.

Coordinates are float copies of the exact ones (display only); the mesh is never changed.
Figures are made without pyplot, ``size`` inches at ``dpi`` exactly, as in
:mod:`geomexact.viz.pictures`.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Literal

import attrs
import numpy as np

from geomexact.errors import MissingDependencyError

try:
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize, to_rgb
    from matplotlib.figure import Figure
except ImportError as error:  # the "pictures" extra
    raise MissingDependencyError("matplotlib", "pictures", "pictures") from error

from geomexact.io.files import write_bytes_atomic
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.viz.pictures import DEFAULT_DPI, DEFAULT_SIZE, figure_bytes, picture_format
from geomexact.viz.scene3d import Clip, kept_by_clip, radius_ratios, tetrahedron_arrays

Colour3 = Literal["plain", "quality"]
COLOURS3: tuple[str, ...] = ("plain", "quality")
"""How :func:`draw_mesh3` colours faces: one colour (cut faces another), or radius ratio."""

FACE_CORNERS = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)
"""The face opposite corner i of a positive tetrahedron, oriented outward (its normal
by the right-hand rule points away from corner i)."""

LIGHT = np.array([0.25, -0.5, 1.0]) / math.sqrt(0.25**2 + 0.5**2 + 1.0)
"""The direction the light comes from, fixed in the mesh's coordinates."""

SURFACE_FILL = "#9fbfe0"
CUT_FILL = "#f0b27a"
EDGE_COLOUR = "#1d2b3a"
QUALITY_MAP = "RdYlGn"
DEFAULT_ELEVATION = 30.0
DEFAULT_AZIMUTH = -60.0


@attrs.frozen(eq=False)
class FaceNeighbours:
    """For the 4 m faces of ``cells`` (face f of cell c at row 4 c + f, as
    :data:`FACE_CORNERS`), the cell on its other side, or -1 on the mesh's boundary."""

    cells: np.ndarray
    neighbours: np.ndarray


def face_neighbours(cells: np.ndarray) -> FaceNeighbours:
    """The :class:`FaceNeighbours` of ``cells`` (m × 4 vertex ids), by sorting the 4 m
    faces: O(m log m)."""
    faces = np.sort(cells[:, FACE_CORNERS].reshape(-1, 3), axis=1)
    neighbours = np.full(len(faces), -1, dtype=np.int64)
    if len(faces):
        order = np.lexsort((faces[:, 2], faces[:, 1], faces[:, 0]))
        ordered = faces[order]
        same = np.nonzero((ordered[1:] == ordered[:-1]).all(axis=1))[0]
        neighbours[order[same]] = order[same + 1] // 4
        neighbours[order[same + 1]] = order[same] // 4
    return FaceNeighbours(cells, neighbours)


@attrs.frozen(eq=False)
class VisibleFaces:
    """The faces of the kept tetrahedra with no kept tetrahedron behind them: ``slots``
    (rows 4 c + f into :class:`FaceNeighbours`), ``cut`` (True for a face the clip opened:
    its neighbour exists but was removed), and the counts of tetrahedra."""

    slots: np.ndarray
    cut: np.ndarray
    tetrahedra: int
    kept: int


def visible_faces(adjacency: FaceNeighbours, kept: np.ndarray) -> VisibleFaces:
    """The boundary faces of the set of cells ``kept`` (a boolean mask): O(m)."""
    cells = len(adjacency.cells)
    owner_kept = np.repeat(kept, 4)
    other = adjacency.neighbours
    other_kept = np.zeros(len(other), dtype=bool)
    inside = other >= 0
    other_kept[inside] = kept[other[inside]]
    slots = np.nonzero(owner_kept & ~other_kept)[0]
    return VisibleFaces(slots, inside[slots], cells, int(np.count_nonzero(kept)))


@attrs.frozen
class Drawing3:
    """What :func:`draw_mesh3` drew: the mesh's tetrahedra, those the clip kept, the
    boundary faces of the kept set (``surface`` on the mesh's boundary, ``cut`` opened by
    the clip) and the faces painted (those facing the viewer, or every shrunk face)."""

    vertices: int
    tetrahedra: int
    kept: int
    surface: int
    cut: int
    painted: int
    clip: Clip | None


def _view_axes(elevation: float, azimuth: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Screen right, screen up and the direction toward the viewer (matplotlib's
    convention: azimuth about z from the x axis, elevation above the xy plane)."""
    e, a = math.radians(elevation), math.radians(azimuth)
    eye = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.array([-math.sin(a), math.cos(a), 0.0])
    up = np.cross(eye, right)
    return right, up, eye


def draw_mesh3(
    ax: Any,
    mesh: Mesh3,
    *,
    clip: Clip | None = None,
    colour: Colour3 = "plain",
    elevation: float = DEFAULT_ELEVATION,
    azimuth: float = DEFAULT_AZIMUTH,
    shrink: float = 0.0,
    colorbar: bool = True,
) -> Drawing3:
    """Draw ``mesh`` into the matplotlib axes ``ax`` (a plain 2D axes: the projection is
    done here); return what was drawn (:class:`Drawing3`).

    The boundary surface of the kept tetrahedra is drawn, lit by :data:`LIGHT`; with
    ``clip``, the tetrahedra whose centroid is beyond the plane are removed (exactly) and
    the faces that opens are filled in orange.  ``colour="quality"`` fills every face by
    its tetrahedron's radius ratio (0 flat … 1 regular, with a colour bar).  ``shrink``
    (0 ≤ shrink < 1) moves each kept tetrahedron's corners toward its centroid and draws
    all its faces (O(kept) faces: for small meshes).  An empty mesh, or a clip that keeps
    nothing, gives an empty drawing.
    """
    if colour not in COLOURS3:
        raise ValueError(f"colour must be one of {', '.join(COLOURS3)}, not {colour!r}")
    if not 0.0 <= shrink < 1.0:
        raise ValueError(f"shrink must be in [0, 1), not {shrink!r}")
    if not isinstance(mesh, Mesh3):
        raise TypeError(f"draw_mesh3 draws a Mesh3, not {type(mesh).__name__}")
    arrays = tetrahedron_arrays(mesh)
    xyz, cells = arrays.xyz, arrays.cells
    if not np.isfinite(xyz).all():
        raise ValueError("a coordinate is beyond the range of doubles: cannot draw it")
    kept = kept_by_clip(mesh, cells, clip)
    adjacency = face_neighbours(cells)
    found = visible_faces(adjacency, kept)
    slots, cut = found.slots, found.cut
    if shrink:
        slots = np.nonzero(np.repeat(kept, 4))[0]
        cut = np.zeros(len(slots), dtype=bool)
    owners = slots // 4
    corners = cells[owners[:, None], FACE_CORNERS[slots % 4]]
    points = xyz[corners]  # (faces, 3 corners, xyz)
    if shrink and len(points):
        centroids = xyz[cells[owners]].mean(axis=1)
        points = points + (centroids[:, None, :] - points) * shrink
    right, up, eye = _view_axes(elevation, azimuth)
    normals = np.cross(points[:, 1] - points[:, 0], points[:, 2] - points[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    facing = normals @ eye > 0
    points, normals, lengths = points[facing], normals[facing], lengths[facing]
    owners, cut = owners[facing], cut[facing]
    depth = points @ eye
    order = np.argsort(depth.mean(axis=1), kind="stable")  # far first
    points, normals, lengths = points[order], normals[order], lengths[order]
    owners, cut = owners[order], cut[order]
    shade = 0.4 + 0.6 * np.clip((normals @ LIGHT) / np.where(lengths > 0, lengths, 1.0),
                                0.0, 1.0)
    mappable = None
    if colour == "quality":
        norm = Normalize(0.0, 1.0)
        cmap = colormaps[QUALITY_MAP]
        base = cmap(norm(radius_ratios(xyz, cells[owners])))[:, :3]
        mappable = ScalarMappable(norm=norm, cmap=cmap)
    else:
        base = np.where(cut[:, None], np.array(to_rgb(CUT_FILL)),
                        np.array(to_rgb(SURFACE_FILL)))
    fills = np.clip(base * shade[:, None], 0.0, 1.0)
    screen = np.stack((points @ right, points @ up), axis=-1)
    painted = len(screen)
    width = 0.5 if painted < 2_000 else 0.25 if painted < 20_000 else 0.1
    ax.add_collection(PolyCollection(list(screen), facecolors=fills, edgecolors=EDGE_COLOUR,
                                     linewidths=width))
    ax.set_aspect("equal")
    ax.set_axis_off()
    if len(xyz):
        # framed on the whole mesh, so that a clip does not move the picture
        flat = np.stack((xyz @ right, xyz @ up), axis=-1)
        (x0, y0), (x1, y1) = flat.min(axis=0), flat.max(axis=0)
        pad = 0.04 * max(x1 - x0, y1 - y0) or 1.0
        ax.set_xlim(x0 - pad, x1 + pad)
        ax.set_ylim(y0 - pad, y1 + pad)
    if mappable is not None and colorbar:
        ax.figure.colorbar(mappable, ax=ax, shrink=0.7, label="radius ratio (3r/R)")
    return Drawing3(vertices=mesh.vertex_count, tetrahedra=found.tetrahedra, kept=found.kept,
                    surface=int(np.count_nonzero(~found.cut)),
                    cut=int(np.count_nonzero(found.cut)), painted=painted, clip=clip)


def default_title3(drawing: Drawing3) -> str:
    """``"V vertices, T tetrahedra"``, with the clip and what it kept when there is one."""
    title = f"{drawing.vertices:,} vertices, {drawing.tetrahedra:,} tetrahedra"
    if drawing.clip is not None:
        title += f" — clip {drawing.clip.text()}: {drawing.kept:,} kept"
    return title


def figure_mesh3(
    mesh: Mesh3,
    *,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A new matplotlib :class:`Figure` (not registered with pyplot) showing ``mesh``;
    ``options`` go to :func:`draw_mesh3`.  The default title counts vertices and
    tetrahedra (and what a clip kept)."""
    fig = Figure(figsize=size, dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.02, 0.02, 0.96, 0.9))
    drawing = draw_mesh3(ax, mesh, **options)
    fig.suptitle(title if title is not None else default_title3(drawing), fontsize=11)
    return fig


def plot_mesh3(
    mesh: Mesh3,
    path: str | Path | None = None,
    *,
    overwrite: bool = False,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A picture of a tetrahedral mesh; written to ``path`` (``.png``, ``.svg`` or
    ``.pdf``, atomically, refusing to replace a file unless ``overwrite``) when given.

    ``options``: ``clip`` (a :class:`~geomexact.viz.scene3d.Clip`, see
    :func:`~geomexact.viz.scene3d.clip_plane`), ``colour`` (``"plain"`` or
    ``"quality"``), ``elevation`` and ``azimuth`` (degrees, default 30 and -60),
    ``shrink``, ``colorbar`` (see :func:`draw_mesh3`).  ``size`` inches at ``dpi``
    (default 800 × 600 pixels); the same bytes for the same mesh and options.

    >>> from geomexact.mesh3d.cuboid.partition import partition_cuboid
    >>> from geomexact.viz.scene3d import clip_plane
    >>> fig = plot_mesh3(partition_cuboid(70688).mesh, clip=clip_plane("x", "1/2"))
    >>> fig.get_size_inches().tolist()
    [8.0, 6.0]
    """
    fig = figure_mesh3(mesh, title=title, size=size, dpi=dpi, **options)
    if path is not None:
        write_bytes_atomic(path, figure_bytes(fig, picture_format(path)), overwrite=overwrite)
    return fig


__all__ = [
    "COLOURS3",
    "Drawing3",
    "FaceNeighbours",
    "VisibleFaces",
    "default_title3",
    "draw_mesh3",
    "face_neighbours",
    "figure_mesh3",
    "plot_mesh3",
    "visible_faces",
]
