"""Mixed-cell meshes (:class:`~geomexact.mesh3d.mixed.MixedMesh3`) in meshio's terms: the
cells of a mesh as meshio blocks or VTK cell entries (writing), and a file's solid cells
read back as a mixed mesh, checked exactly (reading).  Spec: ``specs/formats/meshio.md``
("Mixed-cell meshes").

meshio's ``wedge`` is Gmsh's prism: VTK's wedge with each triangle reversed (meshio's VTK
readers and writers reorder it); every other kind has VTK's order in meshio."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from types import MappingProxyType
from typing import Any

from geomexact.errors import FormatError, PreconditionError, Violation
from geomexact.io.vtk_polyhedra import face_stream
from geomexact.kernel.points import Point3
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.cell_geometry import cell_volume, surface_problem
from geomexact.mesh3d.mixed.cells import Cell, CellKind, cell_of_faces, standard_cell
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed

__all__ = [
    "MESHIO_KINDS",
    "cell_arrays",
    "cell_entries",
    "is_mixed_file",
    "meshio_blocks",
    "mixed_of_meshio",
    "parts_of",
]

MESHIO_KINDS: Mapping[str, CellKind] = MappingProxyType({
    "tetra": CellKind.TETRA, "hexahedron": CellKind.HEXAHEDRON, "wedge": CellKind.WEDGE,
    "pyramid": CellKind.PYRAMID})
"""meshio's names of the standard kinds."""

_MESHIO_NAMES = {kind: name for name, kind in MESHIO_KINDS.items()}
_MESHIO_ORDER = {CellKind.WEDGE: (0, 2, 1, 3, 5, 4)}  # VTK <-> meshio, its own inverse
_MIXED_SOLIDS = ("hexahedron", "wedge", "pyramid")


def parts_of(value: MixedMesh3 | MixedMeshData) -> tuple[MixedMesh3, Mapping[str, tuple[int,
                                                                                       ...]]]:
    """(the mesh, its extra cell arrays: none for a bare mesh)."""
    if isinstance(value, MixedMeshData):
        return value.mesh, value.cell_data
    return value, MappingProxyType({})


def _file_order(cell: Cell) -> tuple[int, ...]:
    order = _MESHIO_ORDER.get(cell.kind)
    return cell.vertices if order is None else tuple(cell.vertices[i] for i in order)


def meshio_blocks(mesh: MixedMesh3) -> list[tuple[str, list[tuple[int, ...]]]]:
    """The cells, in ``cell_list()`` order, as meshio blocks (one per run of one kind, in
    meshio's vertex orders); :class:`PreconditionError` for a polyhedron (meshio writes
    no polyhedron beside other cells: :func:`cell_entries`)."""
    blocks: list[tuple[str, list[tuple[int, ...]]]] = []
    for cell in mesh.cell_list():
        if cell.kind == CellKind.POLYHEDRON:
            raise PreconditionError("meshio_blocks", f"{cell} is a polyhedron")
        name = _MESHIO_NAMES[cell.kind]
        if not blocks or blocks[-1][0] != name:
            blocks.append((name, []))
        blocks[-1][1].append(_file_order(cell))
    return blocks


def cell_entries(mesh: MixedMesh3) -> tuple[list[int], list[list[int]]]:
    """(VTK type, entry) of each cell in ``cell_list()`` order: a standard kind's vertices
    in VTK's order, a polyhedron's face stream (face count, then each face's length and
    ids, its faces outward)."""
    types, entries = [], []
    for cell in mesh.cell_list():
        types.append(int(cell.kind))
        if cell.kind == CellKind.POLYHEDRON:
            entries.append(face_stream(cell.faces))
        else:
            entries.append(list(cell.vertices))
    return types, entries


def is_mixed_file(blocks: Sequence[Any]) -> bool:
    """True when meshio's ``blocks`` hold a solid that is not a tetrahedron (a hexahedron,
    wedge, pyramid or polyhedron): the file is read as a mixed mesh."""
    return any(block.type in _MIXED_SOLIDS or block.type.startswith("polyhedron")
               for block in blocks)


def _ids(name: str, index: int, values: Sequence[Any], count: int) -> list[int]:
    ids = [int(v) for v in values]
    outside = [v for v in ids if not 0 <= v < count]
    if outside:
        raise FormatError(name, None, f"cell {index}: vertex {outside[0]} is out of range "
                          f"(there are {count} points)")
    return ids


def _read_cells(name: str, blocks: Sequence[Any], count: int, ignored: Sequence[str],
                notes: list[str]) -> list[tuple[int, Cell]]:
    """(index among the file's cells, canonical cell) of each solid cell; lower-dimensional
    blocks in ``ignored`` noted; anything else refused."""
    cells: list[tuple[int, Cell]] = []
    index = 0
    for block in blocks:
        kind = MESHIO_KINDS.get(block.type)
        if kind is None and not block.type.startswith("polyhedron"):
            if block.type not in ignored:
                raise FormatError(name, None, f"has {len(block.data)} {block.type} cell(s) "
                                  f"(from cell {index}): a mixed mesh is read from tetra, "
                                  "pyramid, wedge, hexahedron and polyhedron cells (a "
                                  "boundary's faces, edges and points are ignored); nothing "
                                  "was read rather than drop them")
            notes.append(f"ignored {len(block.data)} {block.type} cells")
            index += len(block.data)
            continue
        for row in block.data:
            try:
                if kind is None:
                    cell = cell_of_faces([_ids(name, index, face, count) for face in row])
                else:
                    ids = _ids(name, index, row, count)
                    order = _MESHIO_ORDER.get(kind)
                    cell = standard_cell(kind, ids if order is None else [ids[i] for i in order])
            except PreconditionError as error:
                raise FormatError(name, None, f"cell {index} ({block.type}): "
                                  f"{error.problem}") from error
            cells.append((index, cell))
            index += 1
    return cells


def _mirrored(cell: Cell) -> Cell:
    """The cell with every face reversed (its mirror image's orientation)."""
    return cell_of_faces([tuple(reversed(face)) for face in cell.faces])


def _oriented(name: str, cells: list[tuple[int, Cell]], points: Mapping[int, Point3],
              notes: list[str]) -> list[tuple[int, Cell]]:
    """The rule of the tetrahedral readers for every cell: all positive kept; all negative
    (a file of the other handedness) each mirrored, with a note; a mix refused naming one
    of each.  Cells whose faces do not close, or of zero volume, are left to the cell
    checks."""
    negative, positive = [], []
    for index, cell in cells:
        if surface_problem(cell) is None:
            volume = cell_volume(cell, points)
            if volume < 0:
                negative.append((index, cell))
            elif volume > 0:
                positive.append((index, cell))
    if not negative:
        return cells
    if positive:
        (bad, one), (good, other) = negative[0], positive[0]
        raise FormatError(name, None, f"cells have mixed orientations: cell {bad}, {one}, is "
                          f"inverted (negative volume: its faces point inwards) but cell "
                          f"{good}, {other}, is positive")
    notes.append(f"all {len(negative)} cells were inverted (negative volume); mirrored "
                 "each (its faces reversed)" if len(negative) > 1 else
                 "the only cell was inverted (negative volume); mirrored it")
    return [(index, _mirrored(cell)) for index, cell in cells]


def _culprit(violation: Violation, cells: Sequence[tuple[int, Cell]]) -> int | None:
    """The first cell of the file (its index) that the violation's elements belong to."""
    wanted = set(violation.elements)
    for index, cell in cells:
        if wanted and (wanted == set(cell.vertices) or wanted <= set(cell.vertices)):
            return index
    return None


def mixed_of_meshio(name: str, points: Sequence[Point3], blocks: Sequence[Any],
                    ignored: Sequence[str], notes: list[str]) -> MixedMesh3:
    """The solid cells of meshio's ``blocks`` over the exact ``points`` as a valid
    :class:`MixedMesh3`: oriented by :func:`_oriented`, then checked by
    :func:`~geomexact.mesh3d.mixed.validate_mixed` (without a domain volume).  Every
    problem is a :class:`FormatError` on ``name`` naming the cell (its index among the
    file's cells, from 0) and the problem; ``ignored`` are the block types skipped with a
    note."""
    cells = _read_cells(name, blocks, len(points), ignored, notes)
    table = dict(enumerate(points))
    cells = _oriented(name, cells, table, notes)
    first: dict[Cell, int] = {}
    for index, cell in cells:
        if cell in first:
            raise FormatError(name, None, f"cell {index} repeats cell {first[cell]} ({cell})")
        first[cell] = index
    mesh = mixed_mesh_from_cells(points, [cell for _, cell in cells])
    violations = validate_mixed(mesh, check_digest=False)
    if violations:
        violation = violations[0]
        culprit = _culprit(violation, cells)
        where = f"cell {culprit}: " if culprit is not None else ""
        more = f" (and {len(violations) - 1} more problem(s))" if len(violations) > 1 else ""
        raise FormatError(name, None, f"{where}{violation.kind}: {violation.message}{more}")
    return mesh


def cell_arrays(mesh: MixedMesh3, extra: Mapping[str, Sequence[int]],
                check: Callable[[str, Sequence[int]], None] | None = None
                ) -> dict[str, list[int]]:
    """``kind`` (each cell's VTK type, ``cell_list()`` order) and the ``extra`` arrays, as
    lists; ``check(name, values)`` may refuse an array."""
    arrays = {"kind": [int(cell.kind) for cell in mesh.cell_list()]}
    arrays.update((name, list(values)) for name, values in extra.items())
    if check is not None:
        for array_name, values in arrays.items():
            check(array_name, values)
    return arrays
