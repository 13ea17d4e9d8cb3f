"""Pictures of 3D meshes with matplotlib: PNG, SVG or PDF.

:func:`plot_mesh3` draws a :class:`~geomexact.mesh3d.snapshot.Mesh3` or a mixed-cell
:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3` as its boundary surface, each face as
its polygon, shaded by a fixed light, seen from a chosen elevation and azimuth
(orthographic).  A clip plane (:class:`~geomexact.viz.scene3d.Clip`) removes the cells
whose centroid lies beyond it, whole (decided exactly), and shows the faces it cuts open;
faces can be coloured by their tetrahedron's radius ratio, or by their cell's kind.  Only
the faces that can be seen are drawn: the boundary faces of the kept cells, and of those
only the ones facing the viewer, painted from back to front.  So the cost grows with the
surface, not the volume: the numpy work on all cells is O(m log m) and matplotlib draws
O(m^(2/3)) faces on a regular mesh.

Coordinates are float copies of the exact ones (display only); the mesh is never changed.
Figures are made without pyplot, ``size`` inches at ``dpi`` exactly, as in
:mod:`geomexact.viz.pictures`.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import attrs
import numpy as np

from geomexact.mesh3d.mixed.cells import CellKind
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.viz.matplotlib_names import (
    Figure,
    Normalize,
    Patch,
    PolyCollection,
    ScalarMappable,
    colormaps,
    to_rgb,
)
from geomexact.viz.pictures import DEFAULT_DPI, DEFAULT_SIZE, titled_figure, write_figure
from geomexact.viz.scene3d import (
    KIND_ORDER,
    KIND_PLURALS,
    MATERIAL_FILLS,
    CellFaces,
    Clip,
    Mesh3D,
    cell_faces,
    faces_of_tetrahedra,
    kept_by_clip,
    kind_counts,
    material_label,
    material_ranks,
    mesh_xyz,
    radius_ratios,
)

Colour3 = Literal["plain", "quality", "kind", "material"]
COLOURS3: tuple[str, ...] = ("plain", "quality", "kind", "material")
"""How :func:`draw_mesh3` colours faces: one colour (cut faces another), radius ratio
(tetrahedral meshes), the cell's kind, or the cell's material (the last two with a
legend)."""

KIND_FILLS = {CellKind.TETRA: "#e07a5f", CellKind.PYRAMID: "#f2cc8f",
              CellKind.WEDGE: "#81b29a", CellKind.HEXAHEDRON: "#9fbfe0",
              CellKind.POLYHEDRON: "#b48ad8"}
"""The fill of each cell kind (the page uses the same colours)."""

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
    """For each face of :class:`~geomexact.viz.scene3d.CellFaces`, its cell (``owners``)
    and the cell on its other side (``neighbours``), or -1 on the mesh's boundary."""

    owners: np.ndarray
    neighbours: np.ndarray


def face_neighbours(cells: np.ndarray | CellFaces) -> FaceNeighbours:
    """The :class:`FaceNeighbours` of ``cells`` (:class:`CellFaces`, or tetrahedra as rows
    of 4 vertex ids: face f of cell c is then row 4 c + f), by sorting the faces' vertex
    sets: O(F log F) for F faces.  Two faces with one vertex set are one polygon."""
    faces = cells if isinstance(cells, CellFaces) else faces_of_tetrahedra(cells)
    sizes = faces.face_sizes()
    owners = faces.owners()
    neighbours = np.full(faces.face_count, -1, dtype=np.int64)
    if faces.face_count:
        keys = np.full((faces.face_count, int(sizes.max())), -1, dtype=np.int64)
        rows = np.repeat(np.arange(faces.face_count), sizes)
        columns = np.arange(len(faces.corners)) - faces.corner_offsets[rows]
        keys[rows, columns] = faces.corners
        keys = np.sort(keys, axis=1)
        order = np.lexsort(keys.T[::-1])
        ordered = keys[order]
        same = np.nonzero((ordered[1:] == ordered[:-1]).all(axis=1))[0]
        neighbours[order[same]] = owners[order[same + 1]]
        neighbours[order[same + 1]] = owners[order[same]]
    return FaceNeighbours(owners, neighbours)


@attrs.frozen(eq=False)
class VisibleFaces:
    """The faces of the kept cells with no kept cell behind them: ``slots`` (face indices
    into :class:`FaceNeighbours`), ``cut`` (True for a face the clip opened: its
    neighbour exists but was removed), and the counts of cells."""

    slots: np.ndarray
    cut: np.ndarray
    cells: int
    kept: int


def visible_faces(adjacency: FaceNeighbours, kept: np.ndarray) -> VisibleFaces:
    """The boundary faces of the set of cells ``kept`` (a boolean mask): O(F)."""
    owner_kept = kept[adjacency.owners]
    other = adjacency.neighbours
    other_kept = np.zeros(len(other), dtype=bool)
    inside = other >= 0
    other_kept[inside] = kept[other[inside]]
    slots = np.nonzero(owner_kept & ~other_kept)[0]
    return VisibleFaces(slots, inside[slots], len(kept), int(np.count_nonzero(kept)))


@attrs.frozen
class Drawing3:
    """What :func:`draw_mesh3` drew: the mesh's cells (``tetrahedra`` of them
    tetrahedra; ``kinds`` the counts by kind's plural name, in
    :data:`~geomexact.viz.scene3d.KIND_ORDER`), those the clip kept, the boundary faces of
    the kept set (``surface`` on the mesh's boundary, ``cut`` opened by the clip) and the
    faces painted (those facing the viewer, or every shrunk face), ``sizes`` the painted
    faces' corner counts, ``{corners: faces}``."""

    vertices: int
    tetrahedra: int
    kept: int
    surface: int
    cut: int
    painted: int
    clip: Clip | None
    cells: int = 0
    kinds: dict[str, int] = attrs.field(factory=dict)
    sizes: dict[int, int] = attrs.field(factory=dict)
    mixed: bool = False
    legend: tuple[str, ...] = ()


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
    mesh: Mesh3D,
    *,
    clip: Clip | None = None,
    colour: Colour3 | None = None,
    elevation: float = DEFAULT_ELEVATION,
    azimuth: float = DEFAULT_AZIMUTH,
    shrink: float = 0.0,
    colorbar: bool = True,
    materials: np.ndarray | Sequence[int] | None = None,
    material_names: Mapping[int, str] | None = None,
) -> Drawing3:
    """Draw ``mesh`` (a ``Mesh3`` or a ``MixedMesh3``) into the matplotlib axes ``ax`` (a
    plain 2D axes: the projection is done here); return what was drawn
    (:class:`Drawing3`).

    The boundary surface of the kept cells is drawn, each face as its polygon (outlined
    without diagonals), lit by :data:`LIGHT`; with ``clip``, the cells whose centroid is
    beyond the plane are removed whole (exactly) and the faces that opens are drawn, in
    orange when plain.  ``colour``: ``"plain"`` (a ``Mesh3``'s default), ``"quality"``
    (each tetrahedron's radius ratio, 0 flat … 1 regular, with a colour bar; a
    ``Mesh3`` only), ``"kind"`` (each cell's kind, with a legend; a ``MixedMesh3``'s
    default) or ``"material"`` (each cell's id in ``materials``, one per cell in
    ``tetrahedra()`` or ``cell_list()`` order, with a legend of the ids, named by
    ``material_names`` where it names them; colours :data:`MATERIAL_FILLS` in
    increasing order of id).  ``shrink`` (0 ≤ shrink < 1) moves each kept cell's corners toward its
    centroid and draws all its faces (O(kept) faces: for small meshes).  An empty mesh,
    or a clip that keeps nothing, gives an empty drawing.
    """
    if not isinstance(mesh, Mesh3 | MixedMesh3):
        raise TypeError(f"draw_mesh3 draws a Mesh3 or a MixedMesh3, not "
                        f"{type(mesh).__name__}")
    mixed = isinstance(mesh, MixedMesh3)
    colour = colour or ("kind" if mixed else "plain")
    if colour not in COLOURS3:
        raise ValueError(f"colour must be one of {', '.join(COLOURS3)}, not {colour!r}")
    if colour == "quality" and mixed:
        raise ValueError("colour 'quality' (radius ratio) is for tetrahedral meshes: a "
                         "mixed mesh is coloured by 'kind' or 'plain'")
    if not 0.0 <= shrink < 1.0:
        raise ValueError(f"shrink must be in [0, 1), not {shrink!r}")
    if colour == "material" and materials is None:
        raise ValueError("colour 'material' needs materials: each cell's material id")
    xyz = mesh_xyz(mesh)
    if not np.isfinite(xyz).all():
        raise ValueError("a coordinate is beyond the range of doubles: cannot draw it")
    faces = cell_faces(mesh)
    if colour == "material":
        material_ids, ranks = material_ranks(materials if materials is not None else [])
        if len(ranks) != faces.cell_count:
            raise ValueError(f"materials has {len(ranks)} values for {faces.cell_count} "
                             "cells")
    kept = kept_by_clip(mesh, faces, clip)
    adjacency = face_neighbours(faces)
    found = visible_faces(adjacency, kept)
    slots, cut = found.slots, found.cut
    if shrink:
        slots = np.nonzero(kept[adjacency.owners])[0]
        cut = np.zeros(len(slots), dtype=bool)
    owners = adjacency.owners[slots]
    polygons = _polygons(faces, slots)
    points = xyz[polygons.corners]  # (corners, xyz)
    if shrink and len(points):
        centroids = np.add.reduceat(xyz[faces.vertices], faces.vertex_offsets[:-1]) / \
            np.diff(faces.vertex_offsets)[:, None]
        owner_of_corner = np.repeat(owners, polygons.sizes)
        points = points + (centroids[owner_of_corner] - points) * shrink
    right, up, eye = _view_axes(elevation, azimuth)
    normals = polygons.normals(points)
    lengths = np.linalg.norm(normals, axis=1)
    facing = normals @ eye > 0
    depth = polygons.means(points @ eye)
    order = np.nonzero(facing)[0]
    order = order[np.argsort(depth[order], kind="stable")]  # far first
    normals, lengths, owners, cut = normals[order], lengths[order], owners[order], cut[order]
    shade = 0.4 + 0.6 * np.clip((normals @ LIGHT) / np.where(lengths > 0, lengths, 1.0),
                                0.0, 1.0)
    mappable = None
    if colour == "quality":
        norm = Normalize(0.0, 1.0)
        cmap = colormaps[QUALITY_MAP]
        tetrahedra = faces.vertices.reshape(-1, 4)
        base = cmap(norm(radius_ratios(xyz, tetrahedra[owners])))[:, :3]
        mappable = ScalarMappable(norm=norm, cmap=cmap)
    elif colour == "kind":
        palette = np.zeros((256, 3))
        for kind, fill in KIND_FILLS.items():
            palette[int(kind)] = to_rgb(fill)
        base = palette[faces.kinds[owners]]
    elif colour == "material":
        fills = np.array([to_rgb(fill) for fill in MATERIAL_FILLS])
        base = fills[ranks[owners] % len(fills)]
    else:
        base = np.where(cut[:, None], np.array(to_rgb(CUT_FILL)),
                        np.array(to_rgb(SURFACE_FILL)))
    fills = np.clip(base * shade[:, None], 0.0, 1.0)
    flat_points = np.stack((points @ right, points @ up), axis=-1)
    screen = [flat_points[polygons.offsets[i]:polygons.offsets[i + 1]] for i in order]
    painted = len(screen)
    width = 0.5 if painted < 2_000 else 0.25 if painted < 20_000 else 0.1
    ax.add_collection(PolyCollection(screen, facecolors=fills, edgecolors=EDGE_COLOUR,
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
    counts = kind_counts(faces.kinds)
    handles = []
    if colour == "kind":
        handles = [Patch(facecolor=KIND_FILLS[kind], edgecolor=EDGE_COLOUR,
                         label=KIND_PLURALS[kind]) for kind in KIND_ORDER
                   if KIND_PLURALS[kind] in counts]
    elif colour == "material":
        handles = [Patch(facecolor=MATERIAL_FILLS[rank % len(MATERIAL_FILLS)],
                         edgecolor=EDGE_COLOUR, label=material_label(material, material_names))
                   for rank, material in enumerate(material_ids)]
    if handles:
        ax.legend(handles=handles, loc="upper left", fontsize=8, frameon=False)
    sizes, numbers = np.unique(polygons.sizes[order], return_counts=True)
    return Drawing3(vertices=mesh.vertex_count,
                    tetrahedra=counts.get(KIND_PLURALS[CellKind.TETRA], 0), kept=found.kept,
                    surface=int(np.count_nonzero(~found.cut)),
                    cut=int(np.count_nonzero(found.cut)), painted=painted, clip=clip,
                    cells=found.cells, kinds=counts,
                    sizes={int(k): int(n) for k, n in zip(sizes, numbers, strict=True)},
                    mixed=mixed, legend=tuple(str(h.get_label()) for h in handles))


@attrs.frozen(eq=False)
class _Polygons:
    """Chosen faces as one corner array: face i has the vertex ids
    ``corners[offsets[i]:offsets[i + 1]]``, ``sizes[i]`` of them."""

    corners: np.ndarray
    offsets: np.ndarray
    sizes: np.ndarray

    def means(self, values: np.ndarray) -> np.ndarray:
        """The mean over each face's corners of per-corner ``values``."""
        if not len(self.sizes):
            return np.zeros(0)
        means: np.ndarray = np.add.reduceat(values, self.offsets[:-1]) / self.sizes
        return means

    def normals(self, points: np.ndarray) -> np.ndarray:
        """Each face's Newell normal (twice its vector area; for a triangle the cross
        product of its sides) from per-corner ``points``."""
        if not len(self.sizes):
            return np.zeros((0, 3))
        following = np.arange(len(points)) + 1
        following[self.offsets[1:] - 1] = self.offsets[:-1]
        normals: np.ndarray = np.add.reduceat(np.cross(points, points[following]),
                                              self.offsets[:-1])
        return normals


def _polygons(faces: CellFaces, slots: np.ndarray) -> _Polygons:
    """The faces ``slots`` of ``faces`` as :class:`_Polygons`."""
    starts = faces.corner_offsets[slots]
    sizes = faces.corner_offsets[slots + 1] - starts
    offsets = np.zeros(len(slots) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    positions = np.arange(offsets[-1]) - np.repeat(offsets[:-1] - starts, sizes)
    return _Polygons(faces.corners[positions], offsets, sizes)


_ONE = {"tetrahedra": "tetrahedron", "pyramids": "pyramid", "wedges": "wedge",
        "hexahedra": "hexahedron", "polyhedra": "polyhedron"}


def default_title3(drawing: Drawing3) -> str:
    """``"V vertices, T tetrahedra"`` (a mixed mesh: ``"V vertices, C cells"`` and a
    line ``"20 hexahedra, 2 wedges"``), with the clip and what it kept when there is
    one (a mixed mesh: on a line of its own)."""
    title = f"{drawing.vertices:,} vertices, {drawing.tetrahedra:,} tetrahedra"
    if drawing.mixed:
        title = f"{drawing.vertices:,} vertices, {drawing.cells:,} cells"
        if drawing.kinds:
            title += "\n" + ", ".join(f"{n:,} {_ONE.get(name, name) if n == 1 else name}"
                                       for name, n in drawing.kinds.items())
    if drawing.clip is not None:
        # its own line: a mixed mesh's counts by kind fill the first
        title += ("\n" if drawing.mixed else " — ") + (
            f"clip {drawing.clip.text()}: {drawing.kept:,} kept")
    return title


def figure_mesh3(
    mesh: Mesh3D,
    *,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A new matplotlib :class:`Figure` (not registered with pyplot) showing ``mesh``;
    ``options`` go to :func:`draw_mesh3`.  The default title counts vertices and cells
    (and what a clip kept)."""
    return titled_figure(size, dpi, title,
                         lambda ax: default_title3(draw_mesh3(ax, mesh, **options)))


def plot_mesh3(
    mesh: Mesh3D,
    path: str | Path | None = None,
    *,
    overwrite: bool = False,
    title: str | None = None,
    size: tuple[float, float] = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    **options: Any,
) -> Figure:
    """A picture of a 3D mesh (``Mesh3`` or ``MixedMesh3``); written to ``path``
    (``.png``, ``.svg`` or ``.pdf``, atomically, refusing to replace a file unless
    ``overwrite``) when given.

    ``options``: ``clip`` (a :class:`~geomexact.viz.scene3d.Clip`, see
    :func:`~geomexact.viz.scene3d.clip_plane`), ``colour`` (``"plain"``, ``"quality"``,
    ``"kind"`` or ``"material"``, with ``materials`` and ``material_names``),
    ``elevation`` and ``azimuth`` (degrees, default 30 and -60),
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
        write_figure(fig, path, overwrite=overwrite)
    return fig


__all__ = [
    "COLOURS3",
    "KIND_FILLS",
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
