"""VTK files with polyhedron cells (``VTK_POLYHEDRON``, type 42) beside other cells, which
meshio 5.3 neither writes (its VTU writer refuses polyhedra mixed with other cells, its
legacy writer has none) nor reads (its VTU reader takes grids of polyhedra only, and
reorders them; its legacy readers none).  Spec: ``specs/formats/meshio.md``.

- :func:`vtu_text` and :func:`legacy_vtk_text`: an unstructured grid as VTU XML (ASCII
  arrays; each polyhedron also in the ``faces`` / ``faceoffsets`` arrays, ``-1`` for a
  cell that is not one) or as legacy VTK 4.2 ASCII (a polyhedron's cell entry is its face
  stream: face count, then each face's length and ids), doubles as their shortest exact
  text;
- :func:`polyhedra_readable`: while active, meshio's VTU and legacy VTK readers hand
  back every cell in the file's order, a polyhedron as a ``"polyhedron"`` block of face
  lists (VTU's ``faces``/``faceoffsets`` arrays, a legacy file's face streams).  Files
  without polyhedra go through meshio's own code."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from geomexact.io.vtu_grid import ascii_data_array, number_lines, vtu_document

__all__ = ["POLYHEDRON", "legacy_vtk_text", "polyhedra_readable", "vtu_text"]

POLYHEDRON = 42
"""VTK's cell type number of a polyhedron given by its faces."""

Entry = Sequence[int]
"""A cell's entry: its point ids, or for a polyhedron its face stream."""


def face_stream(faces: Sequence[Sequence[int]]) -> list[int]:
    """VTK's face stream of a polyhedron: the face count, then each face's length and
    ids."""
    stream = [len(faces)]
    for face in faces:
        stream += [len(face), *face]
    return stream


def vtu_text(points: Sequence[tuple[float, float, float]], types: Sequence[int],
             entries: Sequence[Entry], cell_data: Mapping[str, Sequence[int]]) -> str:
    """A VTU unstructured grid: ``points`` (doubles, written as their shortest exact
    text), one cell per ``types[i]`` whose ``entries[i]`` are its point ids, or for a
    polyhedron (type 42) its face stream (its point ids, sorted, go into
    ``connectivity``), and the int64 ``cell_data`` arrays."""
    connectivity: list[int] = []
    offsets: list[int] = []
    faces: list[int] = []
    faceoffsets: list[int] = []
    for kind, entry in zip(types, entries, strict=True):
        if kind == POLYHEDRON:
            at, ids = 1, set[int]()
            for _ in range(entry[0]):
                ids.update(entry[at + 1: at + 1 + entry[at]])
                at += 1 + entry[at]
            connectivity += sorted(ids)
            faces += entry
            faceoffsets.append(len(faces))
        else:
            connectivity += entry
            faceoffsets.append(-1)
        offsets.append(len(connectivity))
    coordinates = [repr(value) for point in points for value in point]
    cells = [ascii_data_array("connectivity", "Int64", connectivity),
             ascii_data_array("offsets", "Int64", offsets),
             ascii_data_array("types", "UInt8", list(types))]
    if faces:
        cells += [ascii_data_array("faces", "Int64", faces),
                  ascii_data_array("faceoffsets", "Int64", faceoffsets)]
    data = [ascii_data_array(name, "Int64", list(values)) for name, values in
            cell_data.items()]
    return vtu_document(len(points), len(types),
                        ascii_data_array("Points", "Float64", coordinates, 3, 3),
                        "".join(cells), "".join(data), compressed=False)


def legacy_vtk_text(points: Sequence[tuple[float, float, float]], types: Sequence[int],
                    entries: Sequence[Entry], cell_data: Mapping[str, Sequence[int]]) -> str:
    """The same grid as :func:`vtu_text` in legacy VTK 4.2 ASCII (``CELLS``: each cell's
    entry count and entry, a polyhedron's entry its face stream; ``cell_data`` as
    ``long`` scalars)."""
    size = sum(1 + len(entry) for entry in entries)
    parts = ["# vtk DataFile Version 4.2\nwritten by geomexact\nASCII\n"
             "DATASET UNSTRUCTURED_GRID\n", f"POINTS {len(points)} double\n"]
    parts += [f"{x!r} {y!r} {z!r}\n" for x, y, z in points]
    parts.append(f"CELLS {len(entries)} {size}\n")
    parts += [f"{len(entry)} {' '.join(map(str, entry))}\n" for entry in entries]
    parts.append(f"CELL_TYPES {len(types)}\n")
    parts += [f"{kind}\n" for kind in types]
    if cell_data:
        parts.append(f"CELL_DATA {len(types)}\n")
        for name, values in cell_data.items():
            parts.append(f"SCALARS {name} long 1\nLOOKUP_TABLE default\n")
            parts.append(number_lines(list(values), 12) + "\n")
    return "".join(parts)


# -----------------------------------------------------------------------------------------
# reading
# -----------------------------------------------------------------------------------------
def _faces_of_stream(stream: Sequence[int]) -> list[list[int]]:
    """The faces of a face stream; meshio's ``ReadError`` when the counts do not fit."""
    from meshio import ReadError

    if not len(stream) or stream[0] < 1:
        raise ReadError("a polyhedron's face stream is empty")
    faces, at = [], 1
    for _ in range(int(stream[0])):
        if at >= len(stream) or stream[at] < 1 or at + 1 + int(stream[at]) > len(stream):
            raise ReadError("a polyhedron's face stream ends inside its faces")
        faces.append([int(v) for v in stream[at + 1: at + 1 + int(stream[at])]])
        at += 1 + int(stream[at])
    if at != len(stream):
        raise ReadError("a polyhedron's face stream has values after its last face")
    return faces


def _blocks(types: Any, entry: Callable[[int], Any],
            faces: Callable[[int], list[list[int]]], cell_data_raw: Mapping[str, Any],
            ) -> tuple[list[Any], dict[str, list[Any]]]:
    """meshio's (cells, cell_data) of the cells in file order: one block per run of one
    type and size; polyhedra as ``"polyhedron"`` blocks of face lists; a wedge in
    meshio's order (VTK's with each triangle reversed, as meshio's own readers do)."""
    from meshio import CellBlock, ReadError
    from meshio._vtk_common import vtk_to_meshio_order, vtk_to_meshio_type

    runs: list[tuple[int, int, list[Any]]] = []  # (type, size or -1, cells)
    starts: list[int] = []
    for index, kind in enumerate(int(t) for t in types):
        cell: Any
        if kind == POLYHEDRON:
            cell, size = faces(index), -1
        else:
            if kind not in vtk_to_meshio_type:
                raise ReadError(f"cell {index} has the unknown VTK type {kind}")
            cell = np.asarray(entry(index), dtype=np.int64)
            order = vtk_to_meshio_order(kind)
            if order is not None and len(cell) == len(order):
                cell = cell[order]
            size = len(cell)
        if not runs or runs[-1][0] != kind or runs[-1][1] != size:
            runs.append((kind, size, []))
            starts.append(index)
        runs[-1][2].append(cell)
    cells = []
    for kind, _, members in runs:
        if kind == POLYHEDRON:
            cells.append(CellBlock("polyhedron", members))
        else:
            cells.append(CellBlock(vtk_to_meshio_type[kind], np.array(members)))
    cell_data = {
        name: [np.asarray(values)[start:start + len(run[2])]
               for start, run in zip(starts, runs, strict=True)]
        for name, values in cell_data_raw.items()}
    return cells, cell_data


def _ranges(ends: Any, count: int) -> Callable[[int], tuple[int, int]]:
    """(start, end) of item ``i`` from offsets that are the ends of ``count`` items (or
    ``count + 1`` offsets starting at 0)."""
    values = [int(v) for v in ends]
    if len(values) == count + 1:
        values = values[1:]
    return lambda i: (values[i - 1] if i else 0, values[i])


def _vtu_piece(piece: Mapping[str, Any], offset: int, data: Mapping[str, Any]
               ) -> tuple[list[Any], dict[str, list[Any]]]:
    """The blocks of one VTU piece with polyhedra (ids shifted by the piece's first
    point, ``offset``)."""
    types = np.asarray(piece["types"]).ravel()
    count = len(types)
    connectivity = np.asarray(piece["connectivity"]).ravel() + offset
    cell_range = _ranges(np.asarray(piece["offsets"]).ravel(), count)

    def entry(i: int) -> Any:
        start, end = cell_range(i)
        return connectivity[start:end]

    if "faces" not in piece or "faceoffsets" not in piece:
        from meshio import ReadError

        raise ReadError("its polyhedra have no 'faces' and 'faceoffsets' arrays (VTK 9.4's "
                        "face_connectivity layout is not read yet)")
    stream = [int(v) for v in np.asarray(piece["faces"]).ravel()]
    ends = [int(v) for v in np.asarray(piece["faceoffsets"]).ravel()]
    if len(ends) != count:
        from meshio import ReadError

        raise ReadError(f"faceoffsets has {len(ends)} values for {count} cells")
    starts = []  # each cell's start: the end of the last polyhedron before it
    last = 0
    for end in ends:
        starts.append(last)
        if end >= 0:
            last = end

    def faces(i: int) -> list[list[int]]:
        found = _faces_of_stream(stream[starts[i]:ends[i]])
        return [[v + offset for v in face] for face in found]

    return _blocks(types, entry, faces, data)


def _vtu_organized(original: Callable[..., Any]) -> Callable[..., Any]:
    def organize(point_offsets: Any, cells: Any, cell_data_raw: Any) -> Any:
        if not any(np.any(np.asarray(piece["types"]) == POLYHEDRON) for piece in cells):
            return original(point_offsets, cells, cell_data_raw)
        blocks: list[Any] = []
        cell_data: dict[str, list[Any]] = {}
        for piece, offset, data in zip(cells, point_offsets, cell_data_raw, strict=True):
            piece_blocks, piece_data = _vtu_piece(piece, int(offset), data)
            blocks += piece_blocks
            for name, values in piece_data.items():
                cell_data.setdefault(name, []).extend(values)
        return blocks, cell_data
    return organize


def _legacy_51(original: Callable[..., Any]) -> Callable[..., Any]:
    def cells_from_data(connectivity: Any, offsets: Any, types: Any, cell_data_raw: Any
                        ) -> Any:
        if not np.any(np.asarray(types) == POLYHEDRON):
            return original(connectivity, offsets, types, cell_data_raw)
        cell_range = _ranges(np.asarray(offsets).ravel(), len(types))

        def entry(i: int) -> Any:
            start, end = cell_range(i)
            return connectivity[start:end]

        return _blocks(types, entry, lambda i: _faces_of_stream(entry(i).tolist()),
                       cell_data_raw)
    return cells_from_data


def _legacy_42(original: Callable[..., Any]) -> Callable[..., Any]:
    def translate(connectivity: Any, types: Any, cell_data_raw: Any) -> Any:
        from meshio import ReadError

        if not np.any(np.asarray(types) == POLYHEDRON):
            return original(connectivity, types, cell_data_raw)
        values = np.asarray(connectivity).ravel()
        starts, at = [], 0
        for _ in range(len(types)):
            if at >= len(values) or values[at] < 0 or at + 1 + values[at] > len(values):
                raise ReadError("the CELLS section ends inside a cell")
            starts.append(at)
            at += 1 + int(values[at])

        def entry(i: int) -> Any:
            return values[starts[i] + 1: starts[i] + 1 + int(values[starts[i]])]

        return _blocks(types, entry, lambda i: _faces_of_stream(entry(i).tolist()),
                       cell_data_raw)
    return translate


@contextlib.contextmanager
def polyhedra_readable() -> Iterator[None]:
    """While active, meshio's VTU and legacy VTK readers read polyhedra among other cells
    (their functions that arrange cells replaced, restored afterwards; not thread-safe,
    like meshio's own module state)."""
    import meshio.vtk._vtk_42 as legacy_42
    import meshio.vtk._vtk_51 as legacy_51
    import meshio.vtu._vtu as vtu

    replaced = [(vtu, "_organize_cells", _vtu_organized),
                (legacy_51, "vtk_cells_from_data", _legacy_51),
                (legacy_42, "translate_cells", _legacy_42)]
    originals = [(module, name, getattr(module, name)) for module, name, _ in replaced]
    for (module, name, wrap), (_, _, original) in zip(replaced, originals, strict=True):
        setattr(module, name, wrap(original))
    try:
        yield
    finally:
        for module, name, original in originals:
            setattr(module, name, original)
