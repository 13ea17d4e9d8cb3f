"""Integer cell data of a 3D meshio file (``.vtu``, ``.vtk``, ``.msh``, …) read back,
aligned with the cells of the mesh :func:`geomexact.io.read` gives for the same file: a
:class:`~geomexact.mesh3d.snapshot.Mesh3`'s ``tetrahedra()`` order, a
:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`'s ``cell_list()`` order.  The readers
canonicalise, reorient and sort the cells, so each file cell is matched to its mesh cell
by its vertex set (vertex ids are the file's).  Spec: ``specs/formats/meshio.md`` ("Cell
data read back").

:data:`MATERIAL_ARRAYS` are the names of the array that says each cell's material."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from geomexact import io
from geomexact.errors import FormatError
from geomexact.io.meshio_bridge import _meshio_read
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

__all__ = ["MATERIAL_ARRAYS", "material_array", "read_cell_arrays"]

MATERIAL_ARRAYS = ("material", "materials", "region", "gmsh:physical")
"""The cell arrays that hold materials, the first present one chosen: geomexact's own
(``material``), common spellings, and Gmsh's physical group tags."""

_SOLIDS = ("tetra", "hexahedron", "wedge", "pyramid")
_DOUBLE_INTEGERS = 1 << 53
"""Gmsh keeps cell data as doubles: integral values below this are exact integers."""


def _is_solid(block_type: str) -> bool:
    return block_type in _SOLIDS or block_type.startswith("polyhedron")


def _vertex_set(block_type: str, row: Any) -> tuple[int, ...]:
    """A file cell's vertex ids, sorted: a standard cell's row, or a polyhedron's faces."""
    if block_type.startswith("polyhedron"):
        return tuple(sorted({int(vertex) for face in row for vertex in face}))
    return tuple(sorted(int(vertex) for vertex in row))


def _integers(values: np.ndarray, doubles_allowed: bool) -> np.ndarray | None:
    """``values`` (one number per cell) as int64, or None when they are not integers (a
    double array counts only where the format keeps integers as doubles, all integral)."""
    if values.ndim == 2 and values.shape[1] == 1:  # legacy VTK's SCALARS of one component
        values = values[:, 0]
    if values.ndim != 1:
        return None
    if values.dtype.kind in "iu" or values.dtype == np.bool_:
        return values.astype(np.int64)
    if values.dtype.kind == "O":
        if all(isinstance(v, int | np.integer) for v in values):
            return np.array([int(v) for v in values], dtype=np.int64)
        values = values.astype(np.float64)
    if doubles_allowed and values.dtype.kind == "f":
        finite = np.isfinite(values).all()
        if finite and (values == np.rint(values)).all() and (
                np.abs(values) < _DOUBLE_INTEGERS).all():
            return values.astype(np.int64)
    return None


def _mesh_cells(mesh: Mesh3 | MixedMesh3) -> list[tuple[int, ...]]:
    """The vertex set (sorted ids) of each cell, in the mesh's order."""
    if isinstance(mesh, MixedMesh3):
        return [tuple(sorted(cell.vertices)) for cell in mesh.cell_list()]
    return [tuple(sorted(tetrahedron)) for tetrahedron in mesh.tetrahedra()]


def read_cell_arrays(path: str | Path, *, format: str | None = None,
                     mesh: Mesh3 | MixedMesh3 | None = None) -> dict[str, np.ndarray]:
    """Each integer cell-data array of the 3D mesh file ``path`` (one value per cell) as an
    int64 array aligned with the cells of ``io.read(path, format=format)`` (``mesh``: that
    mesh when already read).  A Gmsh file's integral double arrays count (Gmsh stores
    cell data as doubles); multi-component and fractional arrays are left out; a file of a
    format without cell data (anything but meshio's) gives ``{}``.  The mesh's cells get
    the values of the file's solid cells (tetrahedra, pyramids, wedges, hexahedra,
    polyhedra), matched by vertex set; boundary cells are skipped.
    :class:`~geomexact.errors.FormatError` when the file is not a 3D mesh or a mesh cell
    has no file cell."""
    name = str(path)
    chosen = format if format is not None else io.detect_format(path)
    if chosen != "meshio":
        return {}
    if mesh is None:
        read = io.read(path, format=chosen)
        if not isinstance(read, Mesh3 | MixedMesh3):
            raise FormatError(name, None, f"is a {type(read).__name__}: cell arrays are read "
                              "back for tetrahedral and mixed-cell meshes")
        mesh = read
    data = _meshio_read(Path(path), [])
    doubles_allowed = Path(path).suffix.lower() == ".msh"
    position: dict[tuple[int, ...], int] = {}  # vertex set -> index among the solid cells
    solid_blocks: list[int] = []
    for index, block in enumerate(data.cells):
        if not _is_solid(block.type):
            continue
        solid_blocks.append(index)
        for row in block.data:
            cell = _vertex_set(block.type, row)
            if cell in position:  # the readers refuse such a file; a changed file is not it
                raise FormatError(name, None, f"two solid cells have the vertices {cell}")
            position[cell] = len(position)
    cells = _mesh_cells(mesh)
    try:
        order = np.fromiter((position[cell] for cell in cells), dtype=np.int64,
                            count=len(cells))
    except KeyError as error:
        raise FormatError(name, None, f"the mesh's cell with vertices {error.args[0]} is no "
                          "solid cell of the file") from None
    arrays: dict[str, np.ndarray] = {}
    for array_name, per_block in data.cell_data.items():
        chunks = [np.asarray(per_block[index]) for index in solid_blocks]
        if not chunks:
            continue
        values = _integers(np.concatenate(chunks), doubles_allowed)
        if values is not None and len(values) == len(position):
            arrays[array_name] = values[order]
    return arrays


def material_array(arrays: Mapping[str, np.ndarray]) -> tuple[str, np.ndarray] | None:
    """The first of :data:`MATERIAL_ARRAYS` among ``arrays``: (its name, its values), or
    None.  A ``gmsh:physical`` of zeros only is none: meshio fills it with zeros for a
    file without physical groups, and Gmsh's tags start at 1."""
    for array_name in MATERIAL_ARRAYS:
        values = arrays.get(array_name)
        if values is None or (array_name == "gmsh:physical" and not values.any()):
            continue
        return array_name, values
    return None
