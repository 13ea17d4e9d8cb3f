"""Geomview pictures of a tetrahedral mesh (write-only).
Spec: ``specs/formats/geomview3d.md``.

- ``geomview3d``: an OFF file of the tetrahedra's faces, four per tetrahedron (each
  outward from its tetrahedron), each face coloured by its tetrahedron (RGBA after the
  face's vertex list, one colour of a fixed palette per tetrahedron, by index);
- ``geomview3d-boundary``: an OFF file of the boundary faces only (outward), uncoloured;
- ``vect``: a Geomview VECT wireframe, one 2-vertex polyline per edge, one colour.

Coordinates are written with :class:`~geomexact.io.registry.NumberText` (lossless by
default, rounding counted).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from geomexact.io.registry import (
    NumberStyle,
    NumberText,
    Value,
    WriteReport,
    write_files,
    written_value,
)
from geomexact.mesh3d.snapshot import Mesh3

PALETTE = (
    "0.9 0.3 0.3 1",
    "0.3 0.7 0.3 1",
    "0.3 0.4 0.9 1",
    "0.9 0.8 0.2 1",
    "0.7 0.3 0.8 1",
    "0.2 0.8 0.8 1",
    "0.9 0.5 0.1 1",
    "0.6 0.6 0.6 1",
)
"""The RGBA colours of the tetrahedra, in turn."""

WIRE_COLOUR = "0 0 0 1"


def _vertex_rows(mesh: Mesh3, number: NumberText) -> list[str]:
    return [
        f"{number(p.x)} {number(p.y)} {number(p.z)}"
        for p in mesh.point_list()
    ]


def tetrahedra_off_text(mesh: Mesh3, number: NumberText) -> str:
    """OFF of the four outward faces of each tetrahedron (canonical order), coloured."""
    faces: list[str] = []
    for index, (a, b, c, d) in enumerate(mesh.tetrahedra()):
        colour = PALETTE[index % len(PALETTE)]
        # outward: the reversals of the faces seen counter-clockwise from inside
        for u, v, w in ((a, c, b), (a, d, c), (a, b, d), (b, c, d)):
            faces.append(f"3 {u} {v} {w} {colour}")
    rows = ["OFF", f"{mesh.vertex_count} {len(faces)} 0", *_vertex_rows(mesh, number), *faces]
    return "\n".join(rows) + "\n"


def boundary_off_text(mesh: Mesh3, number: NumberText) -> str:
    """OFF of the boundary faces, outward."""
    faces = [f"3 {a} {b} {c}" for a, b, c in mesh.boundary_faces()]
    rows = ["OFF", f"{mesh.vertex_count} {len(faces)} 0", *_vertex_rows(mesh, number), *faces]
    return "\n".join(rows) + "\n"


def vect_text(mesh: Mesh3, number: NumberText) -> str:
    """VECT of the edges: ``nlines nvertices ncolors``, the vertex count of each polyline
    (2), the colour count of each (1 for the first, 0 after: inherited), the vertices,
    the colour."""
    edges = mesh.edges()
    every = mesh.point_list()
    points = [every[v] for edge in edges for v in edge]
    rows = [
        "VECT",
        f"{len(edges)} {2 * len(edges)} {1 if edges else 0}",
        " ".join("2" for _ in edges),
        " ".join("1" if index == 0 else "0" for index in range(len(edges))),
        *(f"{number(p.x)} {number(p.y)} {number(p.z)}" for p in points),
    ]
    if edges:
        rows.append(WIRE_COLOUR)
    return "\n".join(rows) + "\n"


def write_tetrahedra_off(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A :class:`Mesh3` as a coloured OFF of its tetrahedra's faces."""
    return _write_text(path, value, overwrite, numbers, "geomview3d", tetrahedra_off_text)


def write_boundary_off(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A :class:`Mesh3` as an OFF of its boundary faces."""
    return _write_text(path, value, overwrite, numbers, "geomview3d-boundary",
                       boundary_off_text)


def write_vect(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A :class:`Mesh3` as a VECT wireframe of its edges."""
    return _write_text(path, value, overwrite, numbers, "vect", vect_text)


def _write_text(
    path: Path, value: Value, overwrite: bool, numbers: NumberStyle, format_name: str,
    text_of: Callable[[Mesh3, NumberText], str],
) -> WriteReport:
    """Write ``text_of`` the :class:`Mesh3` ``value`` (the format ``format_name``) to
    ``path``."""
    number = NumberText(numbers)
    text = text_of(written_value(value, Mesh3, format_name), number)
    return write_files([(path, text)], overwrite=overwrite, numbers=number)
