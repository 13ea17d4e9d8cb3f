"""The 3D viewer page: one self-contained HTML file showing a tetrahedral mesh
(:class:`~geomexact.mesh3d.snapshot.Mesh3`) with rotation, zoom, shrunk tetrahedra,
colour by quality or by creating step, and a step slider over a trace.

Payload (``"format": "geomexact-view3d"``, version 1): the final vertices as base64
little-endian ``Float64Array`` xyz (vertex ids are insertion order, so every earlier step
uses a prefix), and every tetrahedron that ever existed during the trace once
(``Uint32Array`` of 4 ids each) with its ``birth`` and ``death`` step (``Int32Array``:
alive at step s when ``birth <= s < death``), its radius ratio in doubles (display only)
and the operation that created it (an index into ``ops``: ``"input"`` first, then the
sorted operation names).  Exact statistics (volume as a rational's text,
digests) travel as strings.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import base64
import html
import json
import math
from array import array
from fractions import Fraction
from pathlib import Path
from typing import Any

from geomexact.io.files import write_text_atomic
from geomexact.kernel import digest as _digest
from geomexact.kernel.points import Point3
from geomexact.mesh3d.snapshot import Mesh3, Tetrahedron, signed_volume6
from geomexact.trace.playback import check_start, replay_iter
from geomexact.trace.record import Trace
from geomexact.viz.scene import little_endian
from geomexact.viz.viewer import _PLACEHOLDER, VIEWER_CSP, _asset, _check_inline

PAYLOAD3_FORMAT = "geomexact-view3d"
PAYLOAD3_VERSION = 1
COLOUR_MODES = ("quality", "step", "plain")
"""How the page colours tetrahedra: radius ratio, creating operation, one colour."""


def _b64(values: array[Any]) -> str:
    return base64.b64encode(little_endian(values)).decode("ascii")


def radius_ratio(a: Point3, b: Point3, c: Point3, d: Point3) -> float:
    """3 × inradius / circumradius in doubles: 1 for the regular tetrahedron, 0 when flat
    (display only, never a decision)."""
    ax, ay, az = a.fx, a.fy, a.fz
    u = (b.fx - ax, b.fy - ay, b.fz - az)
    v = (c.fx - ax, c.fy - ay, c.fz - az)
    w = (d.fx - ax, d.fy - ay, d.fz - az)

    def cross(p: tuple[float, ...], q: tuple[float, ...]) -> tuple[float, float, float]:
        return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2],
                p[0] * q[1] - p[1] * q[0])

    def dot(p: tuple[float, ...], q: tuple[float, ...]) -> float:
        return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]

    vw, wu, uv = cross(v, w), cross(w, u), cross(u, v)
    det = dot(u, vw)
    if det == 0.0:
        return 0.0
    uu, vv, ww = dot(u, u), dot(v, v), dot(w, w)
    centre = tuple((uu * vw[i] + vv * wu[i] + ww * uv[i]) / (2.0 * det) for i in range(3))
    circum = math.sqrt(dot(centre, centre))
    vu = (v[0] - u[0], v[1] - u[1], v[2] - u[2])
    wv = (w[0] - v[0], w[1] - v[1], w[2] - v[2])
    areas = (math.sqrt(dot(vw, vw)) + math.sqrt(dot(wu, wu)) + math.sqrt(dot(uv, uv))
             + math.sqrt(dot(cross(vu, wv), cross(vu, wv)))) / 2.0
    inradius = abs(det) / (2.0 * areas) if areas else 0.0
    return 3.0 * inradius / circum if circum else 0.0


def exact_volume(mesh: Mesh3) -> Fraction:
    """The mesh's volume, exactly (the sum of its tetrahedra's signed volumes)."""
    total = Fraction(0)
    for a, b, c, d in mesh.iter_tetrahedra():
        total += Fraction(signed_volume6(mesh.point(a), mesh.point(b), mesh.point(c),
                                         mesh.point(d)))
    return total / 6


def payload3(mesh: Mesh3, trace: Trace | None = None, *, title: str = "",
             colour: str = "quality", step: int | None = None) -> dict[str, Any]:
    """The JSON payload of the 3D page.  With ``trace``, ``mesh`` is the trace's input: it
    is replayed once (every digest checked, :class:`~geomexact.errors.TraceError`
    otherwise) and the payload holds every step; the shown mesh is the last one."""
    from geomexact._version import __version__

    if not isinstance(mesh, Mesh3):
        raise TypeError(f"the 3D viewer shows a Mesh3, not {type(mesh).__name__}")
    if colour not in COLOUR_MODES:
        raise ValueError(f"colour must be one of {', '.join(COLOUR_MODES)}, not {colour!r}")
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
    cells, births, deaths, ratios, creators = (array("I"), array("i"), array("i"),
                                               array("d"), array("B"))
    for tetrahedron in order:
        cells.extend(tetrahedron)
        births.append(born[tetrahedron])
        deaths.append(death.get(tetrahedron, steps + 1))
        ratios.append(radius_ratio(*(final.point(v) for v in tetrahedron)))
        creators.append(op_names.index(ops[born[tetrahedron]]))
    xyz = array("d")
    for vertex in range(final.vertex_count):
        p = final.point(vertex)
        xyz.extend((p.fx, p.fy, p.fz))
    volume = exact_volume(final)
    return {
        "format": PAYLOAD3_FORMAT,
        "version": PAYLOAD3_VERSION,
        "generator": f"geomexact {__version__}",
        "title": title,
        "vertex_count": final.vertex_count,
        "xyz": _b64(xyz),
        "cells": _b64(cells),
        "birth": _b64(births),
        "death": _b64(deaths),
        "quality": _b64(ratios),
        "creator": _b64(creators),
        "ops": op_names,
        "steps": steps,
        "labels": labels,
        "vertex_counts": [m.vertex_count for m in meshes],
        "digests": [_digest.digest_text(m.digest) for m in meshes],
        "volume": str(volume),
        "options": {"colour": colour, "step": steps if step is None else step},
    }


def viewer_html_3d(mesh: Mesh3, trace: Trace | None = None, *, title: str = "mesh",
                   colour: str = "quality", step: int | None = None) -> str:
    """The self-contained 3D viewer page of ``mesh`` (with ``trace``: ``mesh`` is its input
    and the page has a step slider over every intermediate mesh, ``step`` first shown,
    default the last).  ``colour``: ``"quality"`` (radius ratio), ``"step"`` (the
    operation that created each tetrahedron) or ``"plain"``.  No network request at any
    time; byte-identical for equal inputs.  Time O(the sum over steps of the tetrahedra
then alive): every step's snapshot is compared with the previous one; the page holds
each tetrahedron once.  ``TypeError`` for anything but a ``Mesh3``."""
    data = payload3(mesh, trace, title=title, colour=colour, step=step)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    text = text.replace("<", "\\u003c")
    values = {
        "csp": VIEWER_CSP,
        "generator": data["generator"],
        "title": html.escape(title or "geomexact 3D viewer"),
        "css": _check_inline("viewer.css", _asset("viewer.css")),
        "js": _check_inline("viewer3d.js", _asset("viewer3d.js")),
        "data": text,
    }
    return _PLACEHOLDER.sub(lambda match: values[match.group(1)], _asset("viewer3d.html"))


def write_viewer_3d(path: str | Path, mesh: Mesh3, trace: Trace | None = None, *,
                    overwrite: bool = False, **options: Any) -> Path:
    """Write :func:`viewer_html_3d` to ``path`` atomically (refusing to replace a file
    unless ``overwrite``); return the path."""
    target = Path(path)
    write_text_atomic(target, viewer_html_3d(mesh, trace, **options), overwrite=overwrite)
    return target


__all__ = ["exact_volume", "payload3", "radius_ratio", "viewer_html_3d", "write_viewer_3d"]
