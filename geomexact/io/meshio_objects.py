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
from typing import Any

import numpy as np

from geomexact.errors import FormatError, PreconditionError, UnsupportedValueError
from geomexact.io.arrays import Numbers, number_array, to_arrays
from geomexact.io.meshio_bridge import (
    BOUNDARY_CELLS,
    mesh2_meshio,
    mesh2_of_meshio,
    meshio_module,
    points3,
    tetrahedral_of_meshio,
)
from geomexact.io.mixed_meshio import cell_arrays, is_mixed_file, meshio_blocks, mixed_of_meshio
from geomexact.kernel.numbers import mpq
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
    converted, rounded, dropped = mesh2_meshio(
        SOURCE, value, numbers="exact" if numbers == "exact" else "nearest")
    if dropped:
        raise UnsupportedValueError(f"to_meshio: a meshio object cannot hold the "
                                    f"{' and '.join(dropped)} of this mesh")
    if numbers == "double":
        inexact = rounded + sum((mpq(point.fx) != point.x) + (mpq(point.fy) != point.y)
                                for point in value.point_list())
        if inexact:
            raise PreconditionError(
                "to_meshio", f"{inexact} number{'s are' if inexact != 1 else ' is'} not "
                "exactly a double: give numbers='exact' (rationals) or numbers='nearest' "
                "(rounded on purpose)")
    return converted


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
            value = mesh2_of_meshio(SOURCE, mesh, notes)
    except PreconditionError as error:
        raise FormatError(SOURCE, None, str(error)) from error
    for note in notes:
        warnings.warn(f"from_meshio: {note}", stacklevel=2)
    return value
