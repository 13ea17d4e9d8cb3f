"""The 3D viewer page: one self-contained HTML file showing a tetrahedral mesh
(:class:`~geomexact.mesh3d.snapshot.Mesh3`) with rotation, zoom, shrunk tetrahedra, a clip
plane, colour by quality or by creating step, and a step slider over a trace; and the
arrays both the page and the pictures (:mod:`geomexact.viz.pictures3d`) draw from:
:func:`tetrahedron_arrays`, :func:`radius_ratios`, :class:`Clip` and :func:`kept_by_clip`.

Payload (``"format": "geomexact-view3d"``, version 2): the final vertices as base64
little-endian ``Float64Array`` xyz (vertex ids are insertion order, so every earlier step
uses a prefix), and every tetrahedron that ever existed during the trace once
(``Uint32Array`` of 4 ids each) with its ``birth`` and ``death`` step (``Int32Array``:
alive at step s when ``birth <= s < death``), its radius ratio in 1/255ths (``Uint8Array``,
display only) and the operation that created it (an index into ``ops``: ``"input"`` first,
then the sorted operation names).  Exact statistics (volume as a rational's text, digests,
the clip position) travel as strings.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import base64
import html
import json
from array import array
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
from geomexact.mesh3d.snapshot import Mesh3, Tetrahedron, signed_volume6
from geomexact.trace.playback import check_start, replay_iter
from geomexact.trace.record import Trace
from geomexact.viz.scene import little_endian
from geomexact.viz.viewer import VIEWER_CSP, _check_inline, fill_page, page_asset, page_script

PAYLOAD3_FORMAT = "geomexact-view3d"
PAYLOAD3_VERSION = 2
COLOUR_MODES = ("quality", "step", "plain")
"""How the page colours tetrahedra: radius ratio, creating operation, one colour."""


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
    count = len(mesh.faces)
    faces = np.fromiter(chain.from_iterable(mesh.faces.keys()), dtype=np.int64,
                        count=3 * count).reshape(-1, 3)
    apices = np.fromiter(mesh.faces.values(), dtype=np.int64, count=count)
    # each tetrahedron once: the face opposite its smallest vertex (the face key starts at
    # its own smallest id a); (d, a, c, b) is the canonical tetrahedron (see
    # canonical_tetrahedron: d first, then the face (c, b, a) rotated to start at a)
    chosen = apices < faces[:, 0]
    cells = np.column_stack((apices[chosen], faces[chosen][:, [0, 2, 1]]))
    cells = cells[np.lexsort(cells.T[::-1])] if len(cells) else cells.reshape(0, 4)
    xyz = np.array([(p.fx, p.fy, p.fz) for p in (mesh.point(v)
                                                 for v in range(mesh.vertex_count))],
                   dtype=np.float64).reshape(-1, 3)
    return TetrahedronArrays(xyz, cells)


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
    tetrahedra whose centroid lies beyond it (coordinate > position) are removed from the
    drawing; those on the plane stay."""

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


def kept_by_clip(mesh: Mesh3, cells: np.ndarray, clip: Clip | None) -> np.ndarray:
    """Which of ``cells`` (rows of vertex ids of ``mesh``) the clip keeps (all without
    one): the centroid's coordinate is at most the position, compared exactly (the sum of
    the four exact coordinates against four times the position)."""
    if clip is None or not len(cells):
        return np.ones(len(cells), dtype=bool)
    index = clip.index
    exact = np.empty(mesh.vertex_count, dtype=object)
    exact[:] = [mesh.point(v)[index] for v in range(mesh.vertex_count)]
    sums = exact[cells].sum(axis=1)
    kept: np.ndarray = (sums <= 4 * clip.position).astype(bool)
    return kept


def exact_volume(mesh: Mesh3) -> Fraction:
    """The mesh's volume, exactly (the sum of its tetrahedra's signed volumes)."""
    total = mpq(0)
    for a, b, c, d in mesh.iter_tetrahedra():
        total += signed_volume6(mesh.point(a), mesh.point(b), mesh.point(c), mesh.point(d))
    return Fraction(int(total.numerator), int(total.denominator)) / 6


def _cells_of(meshes: list[Mesh3]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every tetrahedron that exists at some step, once, in order of birth (sorted within
    a step), with its birth and death steps."""
    steps = len(meshes) - 1
    if steps == 0:
        cells = tetrahedron_arrays(meshes[0]).cells
        return (cells, np.zeros(len(cells), dtype=np.int32),
                np.ones(len(cells), dtype=np.int32))
    born: dict[Tetrahedron, int] = {}
    order: list[Tetrahedron] = []
    death: dict[Tetrahedron, int] = {}
    alive: set[Tetrahedron] = set()
    for index, current in enumerate(meshes):
        now = set(current.iter_tetrahedra())
        for gone in alive - now:
            death[gone] = index
        for new in sorted(now - alive):
            born[new] = index
            order.append(new)
        alive = now
    return (np.array(order, dtype=np.int64).reshape(-1, 4),
            np.array([born[t] for t in order], dtype=np.int32),
            np.array([death.get(t, steps + 1) for t in order], dtype=np.int32))


def _b64_array(values: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(values, dtype=dtype).tobytes()).decode(
        "ascii")


def payload3(mesh: Mesh3, trace: Trace | None = None, *, title: str = "",
             colour: str = "quality", step: int | None = None,
             clip: Clip | None = None) -> dict[str, Any]:
    """The JSON payload of the 3D page.  With ``trace``, ``mesh`` is the trace's input: it
    is replayed once (every digest checked, :class:`~geomexact.errors.TraceError`
    otherwise) and the payload holds every step; the shown mesh is the last one.
    ``clip``: the clip plane the page starts with (None: none)."""
    from geomexact._version import __version__

    if not isinstance(mesh, Mesh3):
        raise TypeError(f"the 3D viewer shows a Mesh3, not {type(mesh).__name__}")
    if colour not in COLOUR_MODES:
        raise ValueError(f"colour must be one of {', '.join(COLOUR_MODES)}, not {colour!r}")
    if clip is not None and not isinstance(clip, Clip):
        raise TypeError(f"clip must be a Clip, not {type(clip).__name__}")
    meshes = [mesh]
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
    quality = np.rint(np.clip(radius_ratios(points, cells), 0.0, 1.0) * 255)
    creator_of_step = np.array([op_names.index(op) for op in ops], dtype=np.uint8)
    volume = exact_volume(final)
    return {
        "format": PAYLOAD3_FORMAT,
        "version": PAYLOAD3_VERSION,
        "generator": f"geomexact {__version__}",
        "title": title,
        "vertex_count": final.vertex_count,
        "xyz": _b64(xyz),
        "cells": _b64_array(cells, "<u4"),
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


def viewer_html_3d(mesh: Mesh3, trace: Trace | None = None, *, title: str = "mesh",
                   colour: str = "quality", step: int | None = None,
                   clip: Clip | None = None) -> str:
    """The self-contained 3D viewer page of ``mesh`` (with ``trace``: ``mesh`` is its input
    and the page has a step slider over every intermediate mesh, ``step`` first shown,
    default the last).  ``colour``: ``"quality"`` (radius ratio), ``"step"`` (the
    operation that created each tetrahedron) or ``"plain"``.  ``clip``: the clip plane
    the page starts with (the page moves it; it decides in doubles).  No network request
    at any time; byte-identical for equal inputs.  Time O(the sum over steps of the
    tetrahedra then alive): every step's snapshot is compared with the previous one; the
    page holds each tetrahedron once.  ``TypeError`` for anything but a ``Mesh3``."""
    data = payload3(mesh, trace, title=title, colour=colour, step=step, clip=clip)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    text = text.replace("<", "\\u003c")
    values = {
        "csp": VIEWER_CSP,
        "generator": data["generator"],
        "title": html.escape(title or "geomexact 3D viewer"),
        "css": _check_inline("viewer.css", page_asset("viewer.css")),
        "js": page_script("viewer3d.js"),
        "data": text,
    }
    return fill_page("viewer3d.html", values)


def write_viewer_3d(path: str | Path, mesh: Mesh3, trace: Trace | None = None, *,
                    overwrite: bool = False, **options: Any) -> Path:
    """Write :func:`viewer_html_3d` to ``path`` atomically (refusing to replace a file
    unless ``overwrite``); return the path."""
    target = Path(path)
    write_text_atomic(target, viewer_html_3d(mesh, trace, **options), overwrite=overwrite)
    return target


__all__ = [
    "CLIP_AXES",
    "Clip",
    "TetrahedronArrays",
    "clip_plane",
    "exact_volume",
    "kept_by_clip",
    "payload3",
    "radius_ratio",
    "radius_ratios",
    "tetrahedron_arrays",
    "viewer_html_3d",
    "write_viewer_3d",
]
