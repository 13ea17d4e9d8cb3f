"""The cells of a mixed mesh: tetrahedra, pyramids, wedges, hexahedra (VTK's vertex
orderings) and general convex polyhedra given by their faces, each face an outward
vertex cycle (counter-clockwise seen from outside: its right-hand normal points out).

A :class:`Cell` is canonical: equal cells compare and hash equal whatever rotation,
symmetry or face order they were given in.  A cell given by its faces whose faces are
those of a standard kind *is* that kind (:func:`cell_of_faces`), so a polyhedron is a cell
that is none of the four.  Specification: ``specs/mixed.md``."""

from __future__ import annotations

import enum
import struct
from collections.abc import Iterable, Mapping, Sequence
from functools import cache
from hashlib import blake2b
from types import MappingProxyType
from typing import TypeAlias

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest

__all__ = [
    "KIND_FACES",
    "Cell",
    "CellKind",
    "Face",
    "cell_arguments",
    "cell_hash_of",
    "cell_of_arguments",
    "cell_of_faces",
    "polygon_key",
    "reversed_face",
    "rotated_face",
    "standard_cell",
]

Face: TypeAlias = tuple[int, ...]
"""A face polygon: its vertex ids in cyclic order (outward: counter-clockwise seen from
outside the cell)."""


class CellKind(enum.IntEnum):
    """The kinds of cells, valued by their VTK cell type numbers."""

    TETRA = 10
    HEXAHEDRON = 12
    WEDGE = 13
    PYRAMID = 14
    POLYHEDRON = 42


KIND_FACES: Mapping[CellKind, tuple[Face, ...]] = MappingProxyType({
    # (0, 1, 2)'s right-hand normal points to 3
    CellKind.TETRA: ((0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)),
    # base (0, 1, 2, 3)'s normal points to the apex 4
    CellKind.PYRAMID: ((0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)),
    # VTK's wedge differs: (0, 1, 2)'s normal points *away* from (3, 4, 5)
    CellKind.WEDGE: ((0, 1, 2), (3, 5, 4), (0, 3, 4, 1), (1, 4, 5, 2), (2, 5, 3, 0)),
    # bottom (0, 1, 2, 3)'s normal points to the top (4, 5, 6, 7); 0-4, 1-5, ... are edges
    CellKind.HEXAHEDRON: ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5),
                          (2, 3, 7, 6), (3, 0, 4, 7)),
})
"""Each standard kind's faces as outward cycles of positions in its VTK ordering (the
first face of each is the one the canonical search starts from)."""

KIND_SIZES: Mapping[CellKind, int] = MappingProxyType(
    {kind: 1 + max(max(face) for face in faces) for kind, faces in KIND_FACES.items()})
"""The number of vertices of each standard kind."""

_STANDARD_KINDS = (CellKind.TETRA, CellKind.PYRAMID, CellKind.WEDGE, CellKind.HEXAHEDRON)
"""The order in which :func:`cell_of_faces` tries the kinds (any order gives the same
answer: the face counts differ)."""


def rotated_face(face: Sequence[int]) -> Face:
    """The rotation of the cycle ``face`` that starts at its smallest id (orientation
    kept)."""
    start = min(range(len(face)), key=face.__getitem__)
    return (*face[start:], *face[:start])


def reversed_face(face: Sequence[int]) -> Face:
    """The same polygon with the other orientation, rotated to its smallest id."""
    return rotated_face(tuple(reversed(face)))


def polygon_key(face: Sequence[int]) -> Face:
    """The polygon ``face`` without its orientation: the smaller of its two rotated
    orientations (two cells share a face exactly when their faces have one key)."""
    return min(rotated_face(face), reversed_face(face))


@attrs.frozen(slots=True, order=True)
class Cell:
    """A canonical cell: its ``kind``; its ``vertices`` (a standard kind: in VTK's order,
    the least such ordering among the kind's orientation-preserving symmetries; a
    polyhedron: sorted); its ``faces``, outward cycles each rotated to its smallest id,
    sorted.  Made by :func:`standard_cell` and :func:`cell_of_faces` only."""

    kind: CellKind
    vertices: tuple[int, ...]
    faces: tuple[Face, ...]

    def __str__(self) -> str:
        if self.kind == CellKind.POLYHEDRON:
            return f"polyhedron{list(self.faces)}"
        return f"{self.kind.name.lower()}{self.vertices}"


def _faces_of_ordering(kind: CellKind, ordering: Sequence[int]) -> tuple[Face, ...]:
    return tuple(sorted(rotated_face([ordering[i] for i in face])
                        for face in KIND_FACES[kind]))


def _orderings(faces: Sequence[Face], kind: CellKind) -> list[tuple[int, ...]]:
    """Every ordering of the ids of ``faces`` that makes them exactly the faces of
    ``kind`` (orientation kept): found by mapping the kind's first face onto each face of
    the same size at each rotation and following the faces across their edges."""
    template = KIND_FACES[kind]
    size = KIND_SIZES[kind]
    wanted = sorted(rotated_face(face) for face in faces)
    if sorted(map(len, faces)) != sorted(map(len, template)) or len(set(wanted)) != len(wanted):
        return []
    owner: dict[tuple[int, int], Face] = {}
    for face in faces:
        for i, vertex in enumerate(face):
            owner[(vertex, face[(i + 1) % len(face)])] = face
    base = template[0]
    found = []
    for face in faces:
        if len(face) != len(base):
            continue
        for shift in range(len(face)):
            mapping = {base[i]: face[(shift + i) % len(face)] for i in range(len(base))}
            if not _follow(mapping, template, owner) or len(mapping) != size:
                continue
            ordering = tuple(mapping[i] for i in range(size))
            if len(set(ordering)) == size and sorted(
                    _faces_of_ordering(kind, ordering)) == wanted:
                found.append(ordering)
    return found


def _follow(mapping: dict[int, int], template: Sequence[Face],
            owner: Mapping[tuple[int, int], Face]) -> bool:
    """Extend ``mapping`` (template position -> id) across the faces until nothing
    changes; False when the faces do not fit the template."""
    changed = True
    while changed:
        changed = False
        for face in template:
            size = len(face)
            for i in range(size):
                x, y = mapping.get(face[i]), mapping.get(face[(i + 1) % size])
                if x is None or y is None:
                    continue
                image = owner.get((x, y))
                if image is None or len(image) != size:
                    return False
                at = image.index(x)
                for step in range(size):
                    position, vertex = face[(i + step) % size], image[(at + step) % size]
                    known = mapping.get(position)
                    if known is None:
                        mapping[position] = vertex
                        changed = True
                    elif known != vertex:
                        return False
                break
    return True


@cache
def symmetries(kind: CellKind) -> tuple[tuple[int, ...], ...]:
    """The orientation-preserving symmetries of ``kind`` as permutations of its positions
    (12 for a tetrahedron, 4 for a pyramid, 6 for a wedge, 24 for a hexahedron)."""
    return tuple(sorted(_orderings(KIND_FACES[kind], kind)))


def standard_cell(kind: CellKind, vertices: Sequence[int]) -> Cell:
    """The cell of a standard ``kind`` whose vertices, in VTK's order, are ``vertices``;
    :class:`PreconditionError` for a wrong count or a repeated id."""
    if kind == CellKind.POLYHEDRON:
        raise PreconditionError("cell", "a polyhedron is given by its faces (cell_of_faces)")
    ids = tuple(int(v) for v in vertices)
    if len(ids) != KIND_SIZES[kind] or len(set(ids)) != len(ids) or min(ids) < 0:
        raise PreconditionError("cell", f"a {kind.name.lower()} needs {KIND_SIZES[kind]} "
                                f"distinct vertex ids, not {ids}")
    ordering = min(tuple(ids[p] for p in permutation) for permutation in symmetries(kind))
    return Cell(kind, ordering, _faces_of_ordering(kind, ordering))


def cell_of_faces(faces: Iterable[Sequence[int]]) -> Cell:
    """The cell bounded by ``faces`` (outward cycles): the standard kind whose faces they
    are, else a polyhedron.  :class:`PreconditionError` for fewer than four faces, a face
    of fewer than three ids or one repeating an id.  Closure and geometry are not checked
    here (``validate_mixed`` does)."""
    rotated = []
    for face in faces:
        ids = tuple(int(v) for v in face)
        if len(ids) < 3 or len(set(ids)) != len(ids) or min(ids) < 0:
            raise PreconditionError("cell", f"a face needs three or more distinct vertex "
                                    f"ids, not {ids}")
        rotated.append(rotated_face(ids))
    if len(rotated) < 4:
        raise PreconditionError("cell", f"a cell needs four or more faces, not {len(rotated)}")
    for kind in _STANDARD_KINDS:
        orderings = _orderings(rotated, kind)
        if orderings:
            ordering = min(orderings)
            return Cell(kind, ordering, _faces_of_ordering(kind, ordering))
    return Cell(CellKind.POLYHEDRON, tuple(sorted({v for face in rotated for v in face})),
                tuple(sorted(rotated)))


_CELL_HASHER = blake2b(digest_size=16, person=b"mixedcell")
_U64 = struct.Struct("<Q").pack


def cell_hash_of(cell: Cell) -> int:
    """The cell's 128-bit hash in the mesh digest: a tetrahedron's is the kernel's
    ``cell_hash`` of its vertices (so a tetrahedral mesh has one digest as a ``Mesh3``
    and as a mixed mesh); any other cell's is BLAKE2b-128 (personal ``mixedcell``) of
    :func:`cell_arguments`, each a little-endian u64."""
    if cell.kind == CellKind.TETRA:
        return _digest.cell_hash(cell.vertices)
    hasher = _CELL_HASHER.copy()
    hasher.update(b"".join(_U64(value) for value in cell_arguments(cell)))
    return int.from_bytes(hasher.digest(), "little")


def cell_arguments(cell: Cell) -> tuple[int, ...]:
    """The cell as step arguments (ints): ``kind, *vertices`` for a standard kind;
    ``42, face count, then each face's length and ids`` for a polyhedron."""
    if cell.kind != CellKind.POLYHEDRON:
        return (int(cell.kind), *cell.vertices)
    values = [int(cell.kind), len(cell.faces)]
    for face in cell.faces:
        values += [len(face), *face]
    return tuple(values)


def cell_of_arguments(arguments: Sequence[object], op: str = "cell") -> Cell:
    """The cell that :func:`cell_arguments` wrote (canonical, whatever order the ids were
    given in); :class:`PreconditionError` naming ``op`` for anything else."""
    values = list(arguments)
    if not values or not all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        raise PreconditionError(op, f"a cell is written as ints, not {tuple(values)}")
    ints = [int(v) for v in values]  # type: ignore[call-overload]
    try:
        kind = CellKind(ints[0])
    except ValueError:
        raise PreconditionError(op, f"unknown cell kind {ints[0]}") from None
    if kind != CellKind.POLYHEDRON:
        return standard_cell(kind, ints[1:])
    faces = []
    at = 2
    count = ints[1] if len(ints) > 1 else 0
    for _ in range(count):
        if at >= len(ints) or ints[at] < 0 or at + 1 + ints[at] > len(ints):
            break
        faces.append(ints[at + 1: at + 1 + ints[at]])
        at += 1 + ints[at]
    if at != len(ints) or len(faces) != count:
        raise PreconditionError(op, f"the polyhedron's faces are not written as "
                                f"count, then length and ids of each: {tuple(ints)}")
    return cell_of_faces(faces)
