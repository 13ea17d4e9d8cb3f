"""THE reference implementation of every mixed-mesh step: ``add_vertex``, ``add_cell``,
``remove_cell``, ``merge_cells`` (two cells across a face into their convex union) and
``split_cell`` (a cell cut by a plane through its vertices), with exact preconditions.

Each ``*_in`` function edits a :class:`~geomexact.mesh3d.mixed.transient.MixedTransient3`
and records its :class:`~geomexact.trace.step.Step`; the pure functions return a new
:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`.  Every step keeps a valid mesh valid
(``specs/mixed.md``, "Steps")."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from types import MappingProxyType

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, to_rational
from geomexact.kernel.points import point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.mixed.cell_geometry import cell_problems
from geomexact.mesh3d.mixed.cells import (
    Cell,
    Face,
    cell_arguments,
    cell_of_arguments,
    cell_of_faces,
    polygon_key,
    reversed_face,
    rotated_face,
)
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import MixedTransient3
from geomexact.trace.protocols import apply_from
from geomexact.trace.step import Step

__all__ = [
    "OPERATIONS",
    "add_cell",
    "add_cell_in",
    "add_vertex",
    "add_vertex_in",
    "apply",
    "apply_in",
    "merge_cells",
    "merge_cells_in",
    "remove_cell",
    "remove_cell_in",
    "split_cell",
    "split_cell_in",
]


def _check_cell(t: MixedTransient3, op: str, cell: Cell) -> None:
    """:class:`PreconditionError` unless ``cell`` passes every check of one cell."""
    problems = cell_problems(cell, t.points_of(cell))
    if problems:
        raise PreconditionError(op, f"{problems[0].message} ({problems[0].kind})")


def add_vertex_in(t: MixedTransient3, x: object, y: object, z: object) -> int:
    """Append the exact point (x, y, z) as vertex ``vertex_count`` (in no cell yet)."""
    point = point3(x, y, z)
    vertex = t.add_vertex(point)
    t.record(Step("add_vertex", (point.x, point.y, point.z)))
    return vertex


def add_cell_in(t: MixedTransient3, cell: Cell) -> None:
    """Add ``cell``.  Pre: its vertices exist; it passes every check of one cell (closed,
    planar convex faces, convex, positive volume); it is not in the mesh and none of its
    outward faces already has a cell on that side."""
    _check_cell(t, "add_cell", cell)
    if t.has_cell(cell):
        raise PreconditionError("add_cell", f"cell {cell} is already in the mesh")
    for face in cell.faces:
        if t.cells_with_face(face):
            raise PreconditionError("add_cell", f"face {face} of {cell} already has a cell "
                                    "on that side")
    t.insert_cell(cell)
    t.record(Step("add_cell", cell_arguments(cell)))


def remove_cell_in(t: MixedTransient3, cell: Cell) -> None:
    """Remove ``cell`` (pre: it is in the mesh).  The vertices stay."""
    if not t.has_cell(cell):
        raise PreconditionError("remove_cell", f"cell {cell} is not in the mesh")
    t.delete_cell(cell)
    t.record(Step("remove_cell", cell_arguments(cell)))


def merge_cells_in(t: MixedTransient3, face: Sequence[int]) -> Cell:
    """Replace the two cells across the polygon ``face`` (either orientation) by their
    union: the faces of both but the shared one, kept as they are (coplanar faces are not
    joined, so every neighbour still meets the same polygons).  Pre: exactly one cell on
    each side of the face, two different cells, and the union passes every check of one
    cell (in particular it is convex).  Returns the union."""
    key = polygon_key(_face_ids(face, "merge_cells"))
    one, other = t.cells_with_face(key), t.neighbours(key)
    if len(one) != 1 or len(other) != 1 or one[0] == other[0]:
        raise PreconditionError("merge_cells", f"face {key} is not shared by exactly two "
                                "cells, one on each side")
    first, second = one[0], other[0]
    shared = {rotated_face(key), reversed_face(key)}
    union = cell_of_faces([f for f in (*first.faces, *second.faces) if f not in shared])
    problems = cell_problems(union, t.points_of(union))
    if problems:
        raise PreconditionError("merge_cells", f"the union of {first} and {second} is not a "
                                f"valid cell: {problems[0].kind}")
    t.delete_cell(first)
    t.delete_cell(second)
    t.insert_cell(union)
    t.record(Step("merge_cells", key))
    return union


def split_cell_in(t: MixedTransient3, cell: Cell, plane: Sequence[int]) -> tuple[Cell, Cell]:
    """Cut ``cell`` by the plane through three of its vertices ``plane`` into two cells,
    the cut polygon (the cell's vertices on the plane) a face of both.  A face the plane
    crosses is split along its chord, in this cell and in the cell across it, whose
    shape does not change (it gets two coplanar faces for one), so the mesh stays
    conforming.  Pre: the cell is in the mesh; the three ids are distinct vertices of it,
    not collinear; the cell has vertices strictly on both sides; no edge crosses the plane
    between its ends.  Returns the pieces (the one on the plane's positive side first)."""
    if not t.has_cell(cell):
        raise PreconditionError("split_cell", f"cell {cell} is not in the mesh")
    p, q, r = _plane_ids(cell, plane)
    points = t.points_of(cell)
    side = {v: orient3d(points[p], points[q], points[r], points[v]) for v in cell.vertices}
    if Orientation.COUNTERCLOCKWISE not in side.values() or \
            Orientation.CLOCKWISE not in side.values():
        raise PreconditionError("split_cell", f"the plane of {(p, q, r)} does not cut {cell}: "
                                "it has no vertex strictly on one side")
    pieces: dict[int, list[Face]] = {1: [], -1: []}
    halves: dict[Face, tuple[Face, Face]] = {}
    for face in cell.faces:
        signs = [int(side[v]) for v in face]
        for i, s in enumerate(signs):
            if s * signs[(i + 1) % len(face)] < 0:
                raise PreconditionError(
                    "split_cell", f"the plane of {(p, q, r)} cuts edge "
                    f"{(face[i], face[(i + 1) % len(face)])} of {cell} between its ends")
        if 1 in signs and -1 in signs:
            plus, minus = _chord_halves(face, signs)
            halves[face] = (plus, minus)
            pieces[1].append(plus)
            pieces[-1].append(minus)
        else:
            pieces[1 if 1 in signs else -1].append(face)
    cut = _cut_face(pieces[1])
    if cut is None:
        raise PreconditionError("split_cell", f"the plane of {(p, q, r)} does not cut {cell} "
                                "in one polygon")
    upper = cell_of_faces([*pieces[1], cut])
    lower = cell_of_faces([*pieces[-1], reversed_face(cut)])
    renewed: dict[Cell, list[Face]] = {}
    for face, (plus, minus) in halves.items():
        for neighbour in t.neighbours(face):
            faces = renewed.setdefault(neighbour, list(neighbour.faces))
            faces.remove(reversed_face(face))
            faces += [reversed_face(plus), reversed_face(minus)]
    rebuilt = {neighbour: cell_of_faces(faces) for neighbour, faces in renewed.items()}
    for made in (upper, lower, *rebuilt.values()):
        _check_cell(t, "split_cell", made)
    t.delete_cell(cell)
    for neighbour in rebuilt:
        t.delete_cell(neighbour)
    for made in (upper, lower, *rebuilt.values()):
        t.insert_cell(made)
    t.record(Step("split_cell", (p, q, r, *cell_arguments(cell))))
    return upper, lower


def _plane_ids(cell: Cell, plane: Sequence[int]) -> tuple[int, int, int]:
    ids = sorted(_face_ids(plane, "split_cell"))
    if len(ids) != 3 or not set(ids) <= set(cell.vertices):
        raise PreconditionError("split_cell", f"the plane is given by three distinct "
                                f"vertices of the cell, not {tuple(plane)}")
    return ids[0], ids[1], ids[2]


def _chord_halves(face: Face, signs: list[int]) -> tuple[Face, Face]:
    """The two halves of a face whose vertices are on both sides of the plane, split at
    its two vertices on the plane: (the half on the positive side, the other)."""
    zeros = [i for i, s in enumerate(signs) if s == 0]
    if len(zeros) != 2:
        raise PreconditionError("split_cell", f"the plane meets face {face} in "
                                f"{len(zeros)} vertices, not a chord")
    size = len(face)
    first, second = zeros
    arc = [face[i % size] for i in range(first, second + 1)]
    rest = [face[i % size] for i in range(second, first + size + 1)]
    arc_sign = signs[(first + 1) % size]
    if any(signs[i % size] != arc_sign for i in range(first + 1, second)) or any(
            signs[i % size] != -arc_sign for i in range(second + 1, first + size)):
        raise PreconditionError("split_cell", f"the plane meets face {face} more than once")
    if arc_sign > 0:
        return rotated_face(arc), rotated_face(rest)
    return rotated_face(rest), rotated_face(arc)


def _cut_face(faces: list[Face]) -> Face | None:
    """The polygon that closes the open surface ``faces``: its free edges, reversed and
    chained into one cycle (None when they are not one cycle)."""
    directed = {(face[i], face[(i + 1) % len(face)]) for face in faces for i in range(len(face))}
    following = {v: u for u, v in directed if (v, u) not in directed}
    if len(following) < 3:
        return None
    start = min(following)
    cycle = [start]
    while (vertex := following[cycle[-1]]) != start:
        if vertex in cycle or vertex not in following:
            return None
        cycle.append(vertex)
    if len(cycle) != len(following):
        return None
    return rotated_face(cycle)


def _face_ids(face: Sequence[object], op: str) -> tuple[int, ...]:
    if len(face) < 3 or not all(isinstance(v, int) and not isinstance(v, bool)
                                for v in face) or len(set(face)) != len(face):
        raise PreconditionError(op, f"a polygon is three or more distinct vertex ids, not "
                                f"{tuple(face)}")
    return tuple(int(v) for v in face)  # type: ignore[call-overload]


# ---------------------------------------------------------------------------------------
# the step table
# ---------------------------------------------------------------------------------------
def _apply_add_vertex(t: MixedTransient3, step: Step) -> None:
    if len(step.args) != 3:
        raise PreconditionError("add_vertex", f"add_vertex takes x, y, z, not {step.args}")
    add_vertex_in(t, *step.args)


def _apply_add_cell(t: MixedTransient3, step: Step) -> None:
    add_cell_in(t, cell_of_arguments(step.args, "add_cell"))


def _apply_remove_cell(t: MixedTransient3, step: Step) -> None:
    remove_cell_in(t, cell_of_arguments(step.args, "remove_cell"))


def _apply_merge_cells(t: MixedTransient3, step: Step) -> None:
    merge_cells_in(t, step.args)  # type: ignore[arg-type]


def _apply_split_cell(t: MixedTransient3, step: Step) -> None:
    if len(step.args) < 4:
        raise PreconditionError("split_cell", f"split_cell takes three plane vertices and a "
                                f"cell, not {step.args}")
    plane = _face_ids(step.args[:3], "split_cell")
    split_cell_in(t, cell_of_arguments(step.args[3:], "split_cell"), plane)


OPERATIONS: Mapping[str, Callable[[MixedTransient3, Step], None]] = MappingProxyType({
    "add_vertex": _apply_add_vertex,
    "add_cell": _apply_add_cell,
    "remove_cell": _apply_remove_cell,
    "merge_cells": _apply_merge_cells,
    "split_cell": _apply_split_cell,
})
"""The mixed-mesh step table (:data:`geomexact.trace.protocols.OperationTable`)."""


def apply_in(t: MixedTransient3, step: Step) -> None:
    """Apply ``step`` to the transient (it records the step)."""
    apply_from(OPERATIONS, t, step)


# ---------------------------------------------------------------------------------------
# pure functions
# ---------------------------------------------------------------------------------------
def apply(mesh: MixedMesh3, step: Step, /) -> MixedMesh3:
    """The mesh after ``step``; ``mesh`` is unchanged."""
    t = MixedTransient3(mesh)
    apply_in(t, step)
    return t.seal()


def add_vertex(mesh: MixedMesh3, x: object, y: object, z: object, /) -> MixedMesh3:
    """The mesh with the exact point (x, y, z) appended as vertex ``mesh.vertex_count``."""
    coordinates: tuple[Rational, ...] = tuple(to_rational(c) for c in (x, y, z))
    return apply(mesh, Step("add_vertex", coordinates))


def add_cell(mesh: MixedMesh3, cell: Cell, /) -> MixedMesh3:
    """The mesh with ``cell`` added (see :func:`add_cell_in`)."""
    return apply(mesh, Step("add_cell", cell_arguments(cell)))


def remove_cell(mesh: MixedMesh3, cell: Cell, /) -> MixedMesh3:
    """The mesh without ``cell``."""
    return apply(mesh, Step("remove_cell", cell_arguments(cell)))


def merge_cells(mesh: MixedMesh3, face: Sequence[int], /) -> MixedMesh3:
    """The mesh with the two cells across ``face`` merged (see :func:`merge_cells_in`)."""
    return apply(mesh, Step("merge_cells", polygon_key(_face_ids(face, "merge_cells"))))


def split_cell(mesh: MixedMesh3, cell: Cell, plane: Sequence[int], /) -> MixedMesh3:
    """The mesh with ``cell`` cut by the plane through the three vertices ``plane`` (see
    :func:`split_cell_in`)."""
    return apply(mesh, Step("split_cell", (*sorted(plane), *cell_arguments(cell))))

