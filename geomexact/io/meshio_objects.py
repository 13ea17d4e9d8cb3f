"""Meshes as meshio objects in memory (issue 26, item 2): :func:`to_meshio` and
:func:`from_meshio` for triangle meshes, tetrahedral meshes and mixed-cell meshes, without
files.  Spec: ``specs/formats/meshio.md`` ("In memory").

A triangle mesh keeps everything: its points (``n x 2``), a ``triangle`` block, its
segments as a ``line`` block, vertex markers and attributes as point data
(``vertex_markers``, ``vertex_attributes``), segment markers as the cell data ``marker``
(0 on triangles) and triangle attributes as the cell data ``triangle_attributes`` (NaN on
lines).  A tetrahedral mesh is its points and a ``tetra`` block; a mixed-cell mesh its
points, one block per run of one kind (meshio's vertex orders) and the cell data ``kind``
(each cell's VTK type); polyhedra are refused (meshio keeps no polyhedron beside other
cells; write ``.vtu``).  Numbers as :func:`geomexact.io.arrays.to_arrays` takes them:
``"double"`` (refused when a value is not exactly a double), ``"nearest"`` or ``"exact"``
(an object array of ``mpq``, for use in memory).

:func:`from_meshio` reads the same, and also Gmsh's ``gmsh:physical`` tags of line cells
as segment markers; each double is the rational it is exactly; every check a file gets
(orientation, overlaps, conformity) applies, its notes issued as warnings, its problems a
:class:`~geomexact.errors.FormatError` on ``<meshio>``."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from geomexact.errors import FormatError, PreconditionError, UnsupportedValueError
from geomexact.io.arrays import Numbers, from_arrays, number_array, to_arrays
from geomexact.io.meshio_bridge import (
    BOUNDARY_CELLS,
    IGNORED_CELLS,
    meshio_module,
    points3,
    tetrahedral_of_meshio,
)
from geomexact.io.mixed_meshio import cell_arrays, is_mixed_file, meshio_blocks, mixed_of_meshio
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.cells import CellKind
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

__all__ = ["from_meshio", "to_meshio"]

SOURCE = "<meshio>"
"""How errors name a meshio object."""

_SEGMENT_MARKERS = ("marker", "gmsh:physical")
"""Cell data read as segment markers, first found wins."""


def to_meshio(value: Mesh2 | Mesh3 | MixedMesh3, *, numbers: Numbers = "double") -> Any:
    """``value`` as a ``meshio.Mesh`` (module docstring); nothing is dropped or rounded
    unless ``numbers="nearest"`` asks."""
    meshio = meshio_module()
    if isinstance(value, MixedMesh3):
        if any(cell.kind == CellKind.POLYHEDRON for cell in value.cell_list()):
            raise UnsupportedValueError(
                "to_meshio: the mesh has polyhedron cells, which a meshio object does not "
                "keep beside other cells; write it as .vtu or .vtk instead")
        corners = map(value.point, range(value.vertex_count))
        points = number_array(((p.x, p.y, p.z) for p in corners), numbers).reshape(-1, 3)
        blocks = meshio_blocks(value)
        kinds = cell_arrays(value, {})["kind"]
        cells, kind_data, start = [], [], 0
        for name, rows in blocks:
            cells.append((name, np.array(rows, dtype=np.int64)))
            kind_data.append(np.array(kinds[start:start + len(rows)], dtype=np.int64))
            start += len(rows)
        return meshio.Mesh(points, cells, cell_data={"kind": kind_data})
    if isinstance(value, Mesh3):
        arrays = to_arrays(value, numbers=numbers)
        return meshio.Mesh(arrays["vertices"], [("tetra", arrays["tetrahedra"])])
    if not isinstance(value, Mesh2):
        raise UnsupportedValueError(f"to_meshio takes a Mesh2, Mesh3 or MixedMesh3, not a "
                                    f"{type(value).__name__}")
    arrays = to_arrays(value, numbers=numbers)
    triangles = arrays["triangles"]
    segments = arrays.get("segments", np.zeros((0, 2), dtype=np.int64))
    cells = [("triangle", triangles)]
    cell_data: dict[str, list[Any]] = {}
    if len(segments):
        cells.append(("line", segments))
        cell_data["marker"] = [np.zeros(len(triangles), dtype=np.int64),
                               arrays["segment_markers"]]
    if "triangle_attributes" in arrays:
        attributes = arrays["triangle_attributes"]
        cell_data["triangle_attributes"] = [attributes] + (
            [np.full((len(segments), attributes.shape[1]), np.nan,
                     dtype=attributes.dtype)] if len(segments) else [])
    point_data = {key: arrays[key] for key in ("vertex_markers", "vertex_attributes")
                  if key in arrays}
    return meshio.Mesh(arrays["vertices"], cells, point_data=point_data, cell_data=cell_data)


def from_meshio(mesh: Any) -> Mesh2 | Mesh3 | MixedMesh3:
    """The mesh a ``meshio.Mesh`` holds (module docstring): a :class:`MixedMesh3` when its
    solids include a hexahedron, wedge, pyramid or polyhedron, a :class:`Mesh3` when they
    are tetrahedra, else a :class:`Mesh2` of its triangles with the line cells as
    segments."""
    for attribute in ("points", "cells"):
        if not hasattr(mesh, attribute):
            raise UnsupportedValueError(f"from_meshio takes a meshio.Mesh; a "
                                        f"{type(mesh).__name__} has no {attribute!r}")
    notes: list[str] = []
    try:
        if is_mixed_file(mesh.cells):
            value: Mesh2 | Mesh3 | MixedMesh3 = mixed_of_meshio(
                SOURCE, points3(SOURCE, mesh), mesh.cells, BOUNDARY_CELLS, notes)
        elif any(block.type == "tetra" for block in mesh.cells):
            value = tetrahedral_of_meshio(SOURCE, mesh, notes)
        else:
            value = _triangles_of_meshio(mesh, notes)
    except PreconditionError as error:
        raise FormatError(SOURCE, None, str(error)) from error
    for note in notes:
        warnings.warn(f"from_meshio: {note}", stacklevel=2)
    return value


def _block_data(mesh: Any, names: Sequence[str], index: int) -> Any:
    for name in names:
        blocks = mesh.cell_data.get(name)
        if blocks is not None and index < len(blocks):
            return np.asarray(blocks[index])
    return None


def _triangles_of_meshio(mesh: Any, notes: list[str]) -> Mesh2:
    """A planar meshio object as the arrays of :func:`from_arrays`, then its mesh."""
    points = np.asarray(mesh.points)
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise FormatError(SOURCE, None, f"points have shape {points.shape}; expected n x 2|3")
    if points.shape[1] == 3:
        flat = [i for i, z in enumerate(points[:, 2].tolist()) if z != 0]
        if flat:
            raise FormatError(SOURCE, None, f"point {flat[0]} has z = {points[flat[0], 2]!r}; "
                              "only planar meshes (z = 0) are supported")
        points = points[:, :2]
    triangles, attributes, segments, markers = [], [], [], []
    for index, block in enumerate(mesh.cells):
        rows = np.asarray(block.data)
        if block.type == "triangle":
            triangles.append(rows.reshape(-1, 3))
            found = _block_data(mesh, ("triangle_attributes",), index)
            if found is not None:
                attributes.append(found.reshape(len(rows), -1))
        elif block.type == "line":
            segments.append(rows.reshape(-1, 2))
            found = _block_data(mesh, _SEGMENT_MARKERS, index)
            markers.append(found.reshape(-1) if found is not None
                           else np.ones(len(rows), dtype=np.int64))
        elif block.type in IGNORED_CELLS:
            notes.append(f"ignored {len(rows)} {block.type} cells")
        else:
            raise FormatError(SOURCE, None,
                              f"has {block.type} cells; only triangle meshes are supported")
    if not triangles:
        raise FormatError(SOURCE, None, "has no triangle, tetra or other solid cells")
    arrays: dict[str, Any] = {"vertices": points, "triangles": np.concatenate(triangles)}
    if attributes and len(attributes) == len(triangles):
        arrays["triangle_attributes"] = np.concatenate(attributes)
    if segments:
        arrays["segments"] = np.concatenate(segments)
        arrays["segment_markers"] = np.concatenate(markers)
    for key in ("vertex_markers", "vertex_attributes"):
        if key in mesh.point_data:
            arrays[key] = mesh.point_data[key]
    value = from_arrays(arrays)
    assert isinstance(value, Mesh2)  # triangles given: a Mesh2
    return value
