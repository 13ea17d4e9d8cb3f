"""The 3D viewer page: one self-contained HTML file showing a tetrahedral mesh
(:class:`~geomexact.mesh3d.snapshot.Mesh3`) or a mixed-cell mesh
(:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`) with rotation, zoom, shrunk cells, a
clip plane, colour by quality, cell kind, material or creating step, and a step slider over a trace;
and the arrays both the page and the pictures (:mod:`geomexact.viz.pictures3d`) draw from:
:func:`tetrahedron_arrays`, :func:`cell_faces` (every cell as its polygon faces),
:func:`radius_ratios`, :class:`Clip` and :func:`kept_by_clip`.

Payload (``"format": "geomexact-view3d"``, version 2): the final vertices as base64
little-endian ``Float64Array`` xyz (vertex ids are insertion order, so every earlier step
uses a prefix), and every tetrahedron that ever existed during the trace once
(``Uint32Array`` of 4 ids each) with its ``birth`` and ``death`` step (``Int32Array``:
alive at step s when ``birth <= s < death``), its radius ratio in 1/255ths (``Uint8Array``,
display only) and the operation that created it (an index into ``ops``: ``"input"`` first,
then the sorted operation names).  A mixed mesh's payload adds every cell's kind and its
faces as outward polygons (CSR arrays); a page of materials adds each cell's material
(an index into the distinct ids).  Exact statistics (volume as a rational's text, digests,
the clip position) travel as strings.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import base64
import html
from array import array
from collections.abc import Mapping, Sequence
from fractions import Fraction
from itertools import chain
from pathlib import Path
from typing import Any

import attrs
import numpy as np
from gmpy2 import mpq

from geomexact.io.files import write_text_atomic
from geomexact.kernel import digest as _digest
from geomexact.kernel.numbers import Rational, format_rational, to_rational
from geomexact.kernel.points import Point3
from geomexact.mesh3d.mixed.cells import Cell, CellKind
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, mixed_volume
from geomexact.mesh3d.snapshot import Mesh3, signed_volume6
from geomexact.trace.playback import check_start, replay_iter
from geomexact.trace.record import Trace
from geomexact.viz.scene import little_endian
from geomexact.viz.viewer import (
    VIEWER_CSP,
    fill_page,
    page_css,
    page_script,
    payload_json,
)

PAYLOAD3_FORMAT = "geomexact-view3d"
PAYLOAD3_VERSION = 2
COLOUR_MODES = ("quality", "step", "plain")
"""How the page colours a tetrahedral mesh: radius ratio, creating operation, one colour."""
MIXED_COLOUR_MODES = ("kind", "step", "plain")
"""How the page colours a mixed mesh: cell kind, creating operation, one colour."""

Mesh3D = Mesh3 | MixedMesh3
"""What the 3D page and pictures draw."""

KIND_ORDER = (CellKind.TETRA, CellKind.PYRAMID, CellKind.WEDGE, CellKind.HEXAHEDRON,
              CellKind.POLYHEDRON)
"""The order in which cell kinds are counted, listed and coloured."""
KIND_PLURALS = {CellKind.TETRA: "tetrahedra", CellKind.PYRAMID: "pyramids",
                CellKind.WEDGE: "wedges", CellKind.HEXAHEDRON: "hexahedra",
                CellKind.POLYHEDRON: "polyhedra"}

MATERIAL_FILLS = ("#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#b07aa1", "#edc948",
                  "#76b7b2", "#ff9da7", "#9c755f", "#bab0ac")
"""The fill of the k-th material in increasing order of id (cycling after the tenth);
the page uses the same colours."""


def material_ranks(materials: np.ndarray | Sequence[int]) -> tuple[list[int], np.ndarray]:
    """(the distinct material ids, increasing; each cell's index among them): the colour
    of a cell is ``MATERIAL_FILLS[rank % len(MATERIAL_FILLS)]``."""
    values = np.asarray(materials, dtype=np.int64).reshape(-1)
    ids, ranks = np.unique(values, return_inverse=True)
    return [int(m) for m in ids], ranks.astype(np.int64).reshape(-1)


def material_label(material: int, names: Mapping[int, str] | None = None) -> str:
    """``"material 2"``, or ``"material 2 (oxide)"`` when ``names`` names it."""
    name = (names or {}).get(material)
    return f"material {material}" + (f" ({name})" if name else "")


def _b64(values: array[Any]) -> str:
    return base64.b64encode(little_endian(values)).decode("ascii")


@attrs.frozen(eq=False)
class TetrahedronArrays:
    """A :class:`Mesh3` as numpy arrays, for drawing: ``xyz`` (n × 3 doubles of the exact
    coordinates, vertex ids as rows) and ``cells`` (m × 4 ids, every tetrahedron once,
    canonical and positively oriented, in sorted order: ``mesh.tetrahedra()``).  Copies:
    the mesh is never changed."""

    xyz: np.ndarray
    cells: np.ndarray


def tetrahedron_arrays(mesh: Mesh3) -> TetrahedronArrays:
    """The arrays of ``mesh`` (:class:`TetrahedronArrays`), in O(m log m) numpy work after
    one pass over the face table."""
    return TetrahedronArrays(mesh_xyz(mesh), _tetrahedron_rows(mesh))


def _tetrahedron_rows(mesh: Mesh3) -> np.ndarray:
    """``mesh.tetrahedra()`` as an m × 4 array, read from the face table."""
    count = len(mesh.faces)
    faces = np.fromiter(chain.from_iterable(mesh.faces.keys()), dtype=np.int64,
                        count=3 * count).reshape(-1, 3)
    apices = np.fromiter(mesh.faces.values(), dtype=np.int64, count=count)
    # each tetrahedron once: the face opposite its smallest vertex (the face key starts at
    # its own smallest id a); (d, a, c, b) is the canonical tetrahedron (see
    # canonical_tetrahedron: d first, then the face (c, b, a) rotated to start at a)
    chosen = apices < faces[:, 0]
    cells = np.column_stack((apices[chosen], faces[chosen][:, [0, 2, 1]]))
    rows: np.ndarray = (cells[np.lexsort(cells.T[::-1])] if len(cells)
                        else cells.reshape(0, 4))
    return rows


TETRAHEDRON_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]], dtype=np.int64)
"""The face opposite corner i of a positive tetrahedron, oriented outward (its normal by
the right-hand rule points away from corner i)."""


@attrs.frozen(eq=False)
class CellFaces:
    """Cells as their polygon faces, in CSR arrays (int64): cell c has the vertices
    ``vertices[vertex_offsets[c]:vertex_offsets[c + 1]]`` (each once) and the faces
    ``face_offsets[c]`` … ``face_offsets[c + 1] - 1``; face f is the outward cycle
    ``corners[corner_offsets[f]:corner_offsets[f + 1]]`` (counter-clockwise seen from
    outside).  ``kinds``: each cell's VTK type (:class:`CellKind`)."""

    kinds: np.ndarray
    vertices: np.ndarray
    vertex_offsets: np.ndarray
    corners: np.ndarray
    corner_offsets: np.ndarray
    face_offsets: np.ndarray

    @property
    def cell_count(self) -> int:
        return len(self.kinds)

    @property
    def face_count(self) -> int:
        return len(self.corner_offsets) - 1

    def owners(self) -> np.ndarray:
        """The cell of each face."""
        owners: np.ndarray = np.repeat(np.arange(self.cell_count),
                                       np.diff(self.face_offsets))
        return owners

    def face_sizes(self) -> np.ndarray:
        """The number of corners of each face."""
        sizes: np.ndarray = np.diff(self.corner_offsets)
        return sizes


def _offsets(sizes: list[int] | np.ndarray) -> np.ndarray:
    offsets = np.zeros(len(sizes) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    return offsets


def faces_of_tetrahedra(cells: np.ndarray) -> CellFaces:
    """The :class:`CellFaces` of tetrahedra (rows of 4 ids, positive): face f of cell c is
    row 4 c + f, opposite corner f (:data:`TETRAHEDRON_FACES`)."""
    count = len(cells)
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 4)
    return CellFaces(np.full(count, int(CellKind.TETRA), dtype=np.uint8), cells.reshape(-1),
                     np.arange(0, 4 * count + 1, 4, dtype=np.int64),
                     cells[:, TETRAHEDRON_FACES].reshape(-1),
                     np.arange(0, 12 * count + 1, 3, dtype=np.int64),
                     np.arange(0, 4 * count + 1, 4, dtype=np.int64))


def faces_of_cells(cells: list[Cell]) -> CellFaces:
    """The :class:`CellFaces` of mixed cells, in the given order, each cell's faces in its
    canonical (sorted) order."""
    faces = [face for cell in cells for face in cell.faces]
    return CellFaces(
        np.array([int(cell.kind) for cell in cells], dtype=np.uint8),
        np.fromiter(chain.from_iterable(cell.vertices for cell in cells), dtype=np.int64),
        _offsets([len(cell.vertices) for cell in cells]),
        np.fromiter(chain.from_iterable(faces), dtype=np.int64),
        _offsets([len(face) for face in faces]),
        _offsets([len(cell.faces) for cell in cells]))


def cell_faces(mesh: Mesh3D) -> CellFaces:
    """The cells of ``mesh`` as :class:`CellFaces`: a ``Mesh3``'s tetrahedra in
    ``mesh.tetrahedra()`` order, a ``MixedMesh3``'s cells in ``cell_list()`` order."""
    if isinstance(mesh, MixedMesh3):
        return faces_of_cells(mesh.cell_list())
    return faces_of_tetrahedra(_tetrahedron_rows(mesh))


def mesh_xyz(mesh: Mesh3D) -> np.ndarray:
    """The vertices as an n × 3 array of doubles (``Point3.fx/fy/fz``; ids as rows)."""
    return np.array([(p.fx, p.fy, p.fz) for p in (mesh.point(v)
                                                  for v in range(mesh.vertex_count))],
                    dtype=np.float64).reshape(-1, 3)


def kind_counts(kinds: np.ndarray) -> dict[str, int]:
    """How many of ``kinds`` (VTK types) are of each kind present, in :data:`KIND_ORDER`,
    by the kind's plural name (``{"hexahedra": 20, "wedges": 2}``)."""
    counts = {}
    for kind in KIND_ORDER:
        count = int(np.count_nonzero(kinds == int(kind)))
        if count:
            counts[KIND_PLURALS[kind]] = count
    return counts


def radius_ratios(xyz: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """3 × inradius / circumradius of each tetrahedron (rows of vertex ids into ``xyz``),
    in doubles: 1 for the regular tetrahedron, 0 when flat (display only, never a
    decision)."""
    if not len(cells):
        return np.zeros(0)
    a = xyz[cells[:, 0]]
    u, v, w = xyz[cells[:, 1]] - a, xyz[cells[:, 2]] - a, xyz[cells[:, 3]] - a
    vw, wu, uv = np.cross(v, w), np.cross(w, u), np.cross(u, v)
    det = np.einsum("ij,ij->i", u, vw)
    uu, vv, ww = (np.einsum("ij,ij->i", x, x) for x in (u, v, w))
    flat = det == 0.0
    safe = np.where(flat, 1.0, det)
    centre = (uu[:, None] * vw + vv[:, None] * wu + ww[:, None] * uv) / (2.0 * safe[:, None])
    circum = np.sqrt(np.einsum("ij,ij->i", centre, centre))
    fourth = np.cross(v - u, w - v)
    areas = (np.linalg.norm(vw, axis=1) + np.linalg.norm(wu, axis=1)
             + np.linalg.norm(uv, axis=1) + np.linalg.norm(fourth, axis=1)) / 2.0
    inradius = np.abs(det) / (2.0 * np.where(areas > 0, areas, 1.0))
    ratio = 3.0 * inradius / np.where(circum > 0, circum, 1.0)
    result: np.ndarray = np.where(flat | (areas == 0) | (circum == 0), 0.0, ratio)
    return result


def radius_ratio(a: Point3, b: Point3, c: Point3, d: Point3) -> float:
    """3 × inradius / circumradius of abcd in doubles (:func:`radius_ratios` of one
    tetrahedron): 1 for the regular tetrahedron, 0 when flat (display only)."""
    xyz = np.array([(p.fx, p.fy, p.fz) for p in (a, b, c, d)], dtype=np.float64)
    return float(radius_ratios(xyz, np.array([[0, 1, 2, 3]]))[0])


CLIP_AXES = ("x", "y", "z")


@attrs.frozen
class Clip:
    """A clip plane: ``axis`` (``"x"``, ``"y"`` or ``"z"``) = ``position`` (exact).  The
    cells whose centroid (the mean of their vertices) lies beyond it (coordinate >
    position) are removed from the drawing, whole; those on the plane stay."""

    axis: str
    position: Rational

    @property
    def index(self) -> int:
        return CLIP_AXES.index(self.axis)

    def text(self) -> str:
        return f"{self.axis} ≤ {format_rational(self.position)}"


def clip_plane(axis: str, position: object) -> Clip:
    """The :class:`Clip` at ``axis`` = ``position`` (an exact number or its text);
    ``ValueError`` for another axis or a position that is not a finite number."""
    if axis not in CLIP_AXES:
        raise ValueError(f"the clip axis must be one of x, y, z, not {axis!r}")
    return Clip(axis, to_rational(position))


def kept_by_clip(mesh: Mesh3D, cells: np.ndarray | CellFaces, clip: Clip | None
                 ) -> np.ndarray:
    """Which ``cells`` (rows of vertex ids of ``mesh``, or :class:`CellFaces`) the clip
    keeps (all without one): the centroid of the cell's vertices has its coordinate at
    most the position, compared exactly (the sum of the k exact coordinates against k
    times the position)."""
    if isinstance(cells, CellFaces):
        ids, offsets = cells.vertices, cells.vertex_offsets
    else:
        ids = np.asarray(cells, dtype=np.int64).reshape(-1)
        offsets = np.arange(0, len(ids) + 1, max(1, np.shape(cells)[-1]), dtype=np.int64)
    count = len(offsets) - 1
    if clip is None or not count:
        return np.ones(count, dtype=bool)
    index = clip.index
    exact = np.empty(mesh.vertex_count, dtype=object)
    exact[:] = [mesh.point(v)[index] for v in range(mesh.vertex_count)]
    sums = np.add.reduceat(exact[ids], offsets[:-1])
    kept: np.ndarray = (sums <= np.diff(offsets) * clip.position).astype(bool)
    return kept


def exact_volume(mesh: Mesh3D) -> Fraction:
    """The mesh's volume, exactly (the sum of its cells' signed volumes)."""
    if isinstance(mesh, MixedMesh3):
        total = mpq(mixed_volume(mesh))
        return Fraction(int(total.numerator), int(total.denominator))
    volume6 = mpq(0)
    for a, b, c, d in mesh.iter_tetrahedra():
        volume6 += signed_volume6(mesh.point(a), mesh.point(b), mesh.point(c), mesh.point(d))
    return Fraction(int(volume6.numerator), int(volume6.denominator)) / 6


def _cells_alive(mesh: Mesh3D) -> list[Any]:
    """The cells of one snapshot, sorted: tetrahedra (id tuples) or cells (:class:`Cell`)."""
    if isinstance(mesh, MixedMesh3):
        return mesh.cell_list()
    return mesh.tetrahedra()


def _cells_of(meshes: list[Any]) -> tuple[list[Any], np.ndarray, np.ndarray]:
    """Every cell that exists at some step, once, in order of birth (sorted within a
    step), with its birth and death steps."""
    steps = len(meshes) - 1
    if steps == 0:
        cells = _cells_alive(meshes[0])
        return (cells, np.zeros(len(cells), dtype=np.int32),
                np.ones(len(cells), dtype=np.int32))
    born: dict[Any, int] = {}
    order: list[Any] = []
    death: dict[Any, int] = {}
    alive: set[Any] = set()
    for index, current in enumerate(meshes):
        now = set(_cells_alive(current))
        for gone in alive - now:
            death[gone] = index
        for new in sorted(now - alive):
            born[new] = index
            order.append(new)
        alive = now
    return (order, np.array([born[t] for t in order], dtype=np.int32),
            np.array([death.get(t, steps + 1) for t in order], dtype=np.int32))


def _b64_array(values: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(values, dtype=dtype).tobytes()).decode(
        "ascii")


def payload3(mesh: Mesh3D, trace: Trace | None = None, *, title: str = "",
             colour: str | None = None, step: int | None = None,
             clip: Clip | None = None, materials: np.ndarray | Sequence[int] | None = None,
             material_names: Mapping[int, str] | None = None) -> dict[str, Any]:
    """The JSON payload of the 3D page.  With ``trace``, ``mesh`` is the trace's input: it
    is replayed once (every digest checked, :class:`~geomexact.errors.TraceError`
    otherwise) and the payload holds every step; the shown mesh is the last one.
    ``colour``: one of :data:`COLOUR_MODES` for a ``Mesh3`` (default ``"quality"``), of
    :data:`MIXED_COLOUR_MODES` for a ``MixedMesh3`` (default ``"kind"``), or
    ``"material"`` with ``materials``.  ``clip``: the clip plane the page starts with
    (None: none).  ``materials``: each cell's material id (``tetrahedra()`` or
    ``cell_list()`` order; no trace), named by ``material_names`` where it names them:
    the payload adds ``materials`` (each cell's index into ``material_ids``, the
    distinct ids as text, increasing), ``material_names`` and ``material_counts``."""
    from geomexact._version import __version__

    if not isinstance(mesh, Mesh3 | MixedMesh3):
        raise TypeError(f"the 3D viewer shows a Mesh3 or a MixedMesh3, not "
                        f"{type(mesh).__name__}")
    mixed = isinstance(mesh, MixedMesh3)
    modes: tuple[str, ...] = MIXED_COLOUR_MODES if mixed else COLOUR_MODES
    if materials is not None:
        if trace is not None:
            raise ValueError("materials are a mesh's cells': the page shows them without "
                             "a trace")
        modes = (*modes, "material")
    colour = modes[0] if colour is None else colour
    if colour not in modes:
        raise ValueError(f"colour must be one of {', '.join(modes)}, not {colour!r}")
    if clip is not None and not isinstance(clip, Clip):
        raise TypeError(f"clip must be a Clip, not {type(clip).__name__}")
    meshes: list[Any] = [mesh]
    labels = ["input"]
    if trace is not None:
        check_start(mesh, trace)
        meshes += list(replay_iter(mesh, trace))
        labels += [str(s) for s in trace.steps]
    steps = len(meshes) - 1
    if step is not None and not 0 <= step <= steps:
        raise ValueError(f"step {step} is outside 0..{steps}")
    final = meshes[-1]
    ops = ["input"] + ([s.op for s in trace.steps] if trace is not None else [])
    op_names = ["input", *sorted(set(ops) - {"input"})]
    cells, births, deaths = _cells_of(meshes)
    xyz = array("d")
    for vertex in range(final.vertex_count):
        p = final.point(vertex)
        xyz.extend((p.fx, p.fy, p.fz))
    points = np.frombuffer(xyz.tobytes(), dtype=np.float64).reshape(-1, 3)
    faces = faces_of_cells(cells) if mixed else faces_of_tetrahedra(
        np.array(cells, dtype=np.int64).reshape(-1, 4))
    tetrahedra = faces.kinds == int(CellKind.TETRA)
    ratios = np.zeros(faces.cell_count)
    corners_of_tetrahedra = np.repeat(tetrahedra, np.diff(faces.vertex_offsets))
    ratios[tetrahedra] = radius_ratios(points,
                                       faces.vertices[corners_of_tetrahedra].reshape(-1, 4))
    quality = np.rint(np.clip(ratios, 0.0, 1.0) * 255)
    creator_of_step = np.array([op_names.index(op) for op in ops], dtype=np.uint8)
    volume = exact_volume(final)
    data = {
        "format": PAYLOAD3_FORMAT,
        "version": PAYLOAD3_VERSION,
        "generator": f"geomexact {__version__}",
        "title": title,
        "vertex_count": final.vertex_count,
        "xyz": _b64(xyz),
        "cells": _b64_array(faces.vertices, "<u4"),
        "birth": _b64_array(births, "<i4"),
        "death": _b64_array(deaths, "<i4"),
        "quality": _b64_array(quality, "u1"),
        "creator": _b64_array(creator_of_step[births], "u1"),
        "ops": op_names,
        "steps": steps,
        "labels": labels,
        "vertex_counts": [m.vertex_count for m in meshes],
        "digests": [_digest.digest_text(m.digest) for m in meshes],
        "volume": str(volume),
        "options": {
            "colour": colour,
            "step": steps if step is None else step,
            "clip": None if clip is None else {
                "axis": clip.axis, "position": format_rational(clip.position),
                "value": float(clip.position)},
        },
    }
    if materials is not None:
        material_ids, ranks = material_ranks(materials)
        if len(ranks) != faces.cell_count:
            raise ValueError(f"materials has {len(ranks)} values for {faces.cell_count} "
                             "cells")
        named = material_names or {}
        data.update({
            "materials": _b64_array(ranks, "<u4"),
            "material_ids": [str(m) for m in material_ids],
            "material_names": [named.get(m, "") for m in material_ids],
            "material_counts": {str(m): int(n) for m, n in zip(
                material_ids, np.bincount(ranks, minlength=len(material_ids)), strict=True)},
        })
    if mixed:
        final_kinds = np.array([int(c.kind) for c in final.cell_list()], dtype=np.uint8)
        data.update({
            "kinds": _b64_array(faces.kinds, "u1"),
            "cell_offsets": _b64_array(faces.vertex_offsets, "<u4"),
            "faces": _b64_array(faces.corners, "<u4"),
            "face_offsets": _b64_array(faces.corner_offsets, "<u4"),
            "cell_face_offsets": _b64_array(faces.face_offsets, "<u4"),
            "kind_counts": kind_counts(final_kinds),
        })
    return data


def viewer_html_3d(mesh: Mesh3D, trace: Trace | None = None, *, title: str = "mesh",
                   colour: str | None = None, step: int | None = None,
                   clip: Clip | None = None,
                   materials: np.ndarray | Sequence[int] | None = None,
                   material_names: Mapping[int, str] | None = None) -> str:
    """The self-contained 3D viewer page of ``mesh``, a ``Mesh3`` or a ``MixedMesh3``
    (with ``trace``: ``mesh`` is its input and the page has a step slider over every
    intermediate mesh, ``step`` first shown, default the last).  ``colour``: for a
    ``Mesh3`` ``"quality"`` (radius ratio, the default), ``"step"`` (the operation that
    created each tetrahedron) or ``"plain"``; for a ``MixedMesh3`` ``"kind"`` (the
    default), ``"step"`` or ``"plain"``; with ``materials`` (each cell's material id, no
    trace: :func:`payload3`) also ``"material"``, a legend listing the ids (and the
    names ``material_names`` gives).  Faces are drawn as their polygons.  ``clip``:
    the clip plane the page starts with (the page moves it; it decides in doubles).  No
    network request at any time; byte-identical for equal inputs.  Time O(the sum over
    steps of the cells then alive): every step's snapshot is compared with the previous
    one; the page holds each cell once.  ``TypeError`` for any other value."""
    data = payload3(mesh, trace, title=title, colour=colour, step=step, clip=clip,
                    materials=materials, material_names=material_names)
    values = {
        "csp": VIEWER_CSP,
        "generator": data["generator"],
        "title": html.escape(title or "geomexact 3D viewer"),
        "css": page_css(),
        "js": page_script("viewer3d.js"),
        "data": payload_json(data),
    }
    return fill_page("viewer3d.html", values)


def write_viewer_3d(path: str | Path, mesh: Mesh3D, trace: Trace | None = None, *,
                    overwrite: bool = False, **options: Any) -> Path:
    """Write :func:`viewer_html_3d` to ``path`` atomically (refusing to replace a file
    unless ``overwrite``); return the path."""
    target = Path(path)
    write_text_atomic(target, viewer_html_3d(mesh, trace, **options), overwrite=overwrite)
    return target


__all__ = [
    "CLIP_AXES",
    "KIND_ORDER",
    "KIND_PLURALS",
    "MATERIAL_FILLS",
    "MIXED_COLOUR_MODES",
    "TETRAHEDRON_FACES",
    "CellFaces",
    "Clip",
    "Mesh3D",
    "TetrahedronArrays",
    "cell_faces",
    "clip_plane",
    "exact_volume",
    "faces_of_cells",
    "faces_of_tetrahedra",
    "kept_by_clip",
    "kind_counts",
    "material_label",
    "material_ranks",
    "mesh_xyz",
    "payload3",
    "radius_ratio",
    "radius_ratios",
    "tetrahedron_arrays",
    "viewer_html_3d",
    "write_viewer_3d",
]
