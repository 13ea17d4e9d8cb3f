"""The census of polyhedral Delaunay cells of 1-irregular cuboids (issue 23, item 3;
Contreras and Hitschfeld-Kahler, "Study on Delaunay tessellations of 1-irregular cuboids
for 3D mixed element meshes", arXiv 1312.1181).

Each pattern's partition is improved by Joe's flips with its boundary faces free, which
makes it the exact Delaunay tetrahedralization of the cuboid's points; its co-spherical
tetrahedra are grouped into cells (:func:`~geomexact.mesh3d.cospherical.
polyhedral_cells`).  A cell's *shape* is its vertex set in the cuboid's half-lattice
(coordinates 0, 1, 2 for low, middle, high), taken up to the cuboid's symmetries (the 48
of the cube; of a cuboid with unequal sides, those that only swap equal sides): the
smallest sorted tuple of lattice points over the symmetries."""

from __future__ import annotations

import itertools
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping

import attrs
import numpy as np
from numpy.typing import NDArray

from geomexact.kernel.vectors import cross3, dot3, sub3
from geomexact.mesh3d.cospherical import PolyhedralCell, polyhedral_cells
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.numbering import (
    BIT_COUNT,
    EDGE_BITS,
    FACE_EDGES,
    steiner_position2,
)
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3

__all__ = ["CellShape", "CellType", "PapersCount", "PolyhedralCensus", "cell_shape",
           "cell_type", "hull_faces", "lattice_cells", "lattice_census",
           "lattice_shape", "merged", "papers_count", "papers_patterns",
           "pattern_cells", "plane_cuts", "polyhedral_census", "uncut_parts"]

CellShape = tuple[tuple[int, int, int], ...]
"""A cell's vertices as sorted half-lattice points, the smallest over the symmetries."""

UNIT_CUBE = Box((0, 0, 0), (1, 1, 1))


@attrs.frozen
class PolyhedralCensus:
    """What the census found over ``patterns`` patterns of ``box``: how many cells of
    each shape (``shapes``), how many patterns have n cells (``cells_per_pattern``), and
    the tetrahedra before grouping (``tetrahedra``) against the cells after
    (``cells``)."""

    box: Box
    patterns: int
    shapes: dict[CellShape, int]
    cells_per_pattern: dict[int, int]
    tetrahedra: int
    cells: int

    def by_vertex_count(self) -> dict[int, tuple[int, int]]:
        """Vertices per cell -> (distinct shapes, cells)."""
        table: dict[int, list[int]] = {}
        for shape, count in self.shapes.items():
            entry = table.setdefault(len(shape), [0, 0])
            entry[0] += 1
            entry[1] += count
        return {size: (entry[0], entry[1]) for size, entry in sorted(table.items())}


def _symmetries(box: Box) -> list[tuple[tuple[int, int, int], tuple[bool, bool, bool]]]:
    """(axis permutation, reflections) of the box's symmetries: permutations only among
    equal sides."""
    extents = box.extents
    found = []
    for permutation in itertools.permutations(range(3)):
        if any(extents[permutation[axis]] != extents[axis] for axis in range(3)):
            continue
        for flips in itertools.product((False, True), repeat=3):
            found.append(((permutation[0], permutation[1], permutation[2]),
                          (flips[0], flips[1], flips[2])))
    return found


def cell_shape(mesh: Mesh3, cell: PolyhedralCell, box: Box = UNIT_CUBE) -> CellShape:
    """The canonical shape of ``cell`` (module docstring); every vertex of a pattern lies
    on the half-lattice of ``box``."""
    extents = box.extents
    lattice = []
    for vertex in cell.vertices:
        point = mesh.point(vertex)
        coordinates = [2 * (point[axis] - box.low[axis]) / extents[axis] for axis in range(3)]
        lattice.append(tuple(int(value) for value in coordinates))
    best: CellShape | None = None
    for permutation, flips in _symmetries(box):
        moved = tuple(sorted(
            tuple(2 - p[permutation[axis]] if flips[axis] else p[permutation[axis]]
                  for axis in range(3))
            for p in lattice))
        if best is None or moved < best:
            best = moved  # type: ignore[assignment]
    return best if best is not None else ()


def pattern_cells(pattern: int,
                  box: Box = UNIT_CUBE) -> tuple[Mesh3, tuple[PolyhedralCell, ...]]:
    """The Delaunay tetrahedralization of ``pattern``'s points in ``box`` and its
    polyhedral cells."""
    mesh = partition_cuboid(pattern, box, improve=True, allow_boundary_flips=True).mesh
    return mesh, polyhedral_cells(mesh)


def merged(first: PolyhedralCensus, second: PolyhedralCensus) -> PolyhedralCensus:
    """The census of both parts (of one box)."""
    shapes: Counter[CellShape] = Counter(first.shapes)
    shapes.update(second.shapes)
    per_pattern: Counter[int] = Counter(first.cells_per_pattern)
    per_pattern.update(second.cells_per_pattern)
    return PolyhedralCensus(first.box, first.patterns + second.patterns,
                            dict(sorted(shapes.items())), dict(sorted(per_pattern.items())),
                            first.tetrahedra + second.tetrahedra, first.cells + second.cells)


def polyhedral_census(patterns: Iterable[int], box: Box = UNIT_CUBE) -> PolyhedralCensus:
    """The census over ``patterns`` (module docstring), in one process."""
    shapes: Counter[CellShape] = Counter()
    per_pattern: Counter[int] = Counter()
    tetrahedra = cells = count = 0
    for pattern in patterns:
        mesh, found = pattern_cells(pattern, box)
        count += 1
        per_pattern[len(found)] += 1
        cells += len(found)
        tetrahedra += sum(len(cell.tetrahedra) for cell in found)
        shapes.update(cell_shape(mesh, cell, box) for cell in found)
    return PolyhedralCensus(box, count, dict(sorted(shapes.items())),
                            dict(sorted(per_pattern.items())), tetrahedra, cells)


# --- The papers' counting (Contreras and Hitschfeld-Kahler 2013, 2014) -----------------

CellType = tuple[tuple[int, ...], ...]
"""A cell's combinatorial type: the smallest rotation-system code of its hull's vertex-edge
graph over every starting dart and both orientations (so mirror images are one type)."""

Lattice = tuple[int, int, int]


def papers_patterns() -> tuple[int, ...]:
    """The edge-midpoint patterns that the papers' counts are reproduced on: Steiner points
    on edges only (bits 0..11), and no face with all four of its edges split (a face whose
    four edges are split carries its centre too, which the papers' 1-irregular cuboids,
    "at most one Steiner point on their edges", do not have).  2,902 of the 4,096."""
    return tuple(
        pattern for pattern in range(1 << len(EDGE_BITS))
        if not any(all(pattern >> edge & 1 for edge in edges) for edges in FACE_EDGES))





def _planes(shape: CellShape) -> Iterator[tuple[Lattice, list[int]]]:
    """Every plane through three of ``shape``'s points: (normal, the side of each point:
    the sign-carrying dot product), each plane once per triple that spans it."""
    for i, j, k in itertools.combinations(range(len(shape)), 3):
        normal = cross3(sub3(shape[j], shape[i]), sub3(shape[k], shape[i]))
        if normal != (0, 0, 0):
            yield normal, [dot3(normal, sub3(point, shape[i])) for point in shape]


def hull_faces(shape: CellShape) -> tuple[tuple[int, ...], ...]:
    """The faces of the convex hull of ``shape`` (points in convex position, not coplanar),
    each as its vertex indices in counter-clockwise order seen from outside; exact."""
    faces: dict[frozenset[int], Lattice] = {}
    for normal, sides in _planes(shape):
        if all(side <= 0 for side in sides) or all(side >= 0 for side in sides):
            outward = normal if all(side <= 0 for side in sides) else (
                -normal[0], -normal[1], -normal[2])
            faces[frozenset(n for n, side in enumerate(sides) if side == 0)] = outward
    ordered = []
    for members, outward in faces.items():
        successor = {}
        for u, v in itertools.permutations(members, 2):
            # v follows u when every other vertex of the face lies to the left of u -> v
            if all(dot3(outward, cross3(sub3(shape[v], shape[u]),
                                        sub3(shape[w], shape[u]))) > 0
                   for w in members if w not in (u, v)):
                successor[u] = v
        start = min(members)
        cycle = [start]
        while successor[cycle[-1]] != start:
            cycle.append(successor[cycle[-1]])
        ordered.append(tuple(cycle))
    return tuple(sorted(ordered))


def cell_type(shape: CellShape) -> CellType:
    """The combinatorial type of the cell with vertices ``shape`` (:data:`CellType`):
    Weinberg's canonical code, which a polyhedron's graph with its rotation system
    determines up to isomorphism."""
    turn: dict[tuple[int, int], int] = {}  # (v, w) -> the neighbour of v after w
    for face in hull_faces(shape):
        for index, vertex in enumerate(face):
            turn[(vertex, face[(index + 1) % len(face)])] = face[index - 1]
    best: CellType | None = None
    for mirrored in (False, True):
        rotation = turn if not mirrored else {(v, p): w for (v, w), p in turn.items()}
        for first_vertex, first_neighbour in rotation:
            label = {first_vertex: 0}
            order = [first_vertex]
            entry = {first_vertex: first_neighbour}
            code = []
            for vertex in order:  # grows while it is walked: breadth first
                row = []
                neighbour = entry[vertex]
                while True:
                    if neighbour not in label:
                        label[neighbour] = len(order)
                        order.append(neighbour)
                        entry[neighbour] = vertex
                    row.append(label[neighbour])
                    neighbour = rotation[(vertex, neighbour)]
                    if neighbour == entry[vertex]:
                        break
                code.append(tuple(row))
            found = tuple(code)
            if best is None or found < best:
                best = found
    assert best is not None
    return best


def plane_cuts(shape: CellShape) -> tuple[tuple[CellShape, CellShape], ...]:
    """The ways to cut the cell ``shape`` in two by inserting one internal face: a plane
    through three or more of its vertices with vertices strictly on both sides that
    crosses none of its faces (each face stays whole, so the cell's neighbours see no
    change); each once, as the two parts' sorted vertices (the smaller first), the
    plane's vertices in both."""
    faces = hull_faces(shape)
    found = set()
    for _, sides in _planes(shape):
        if not (min(sides) < 0 < max(sides)):
            continue
        if any(min(sides[v] for v in face) < 0 < max(sides[v] for v in face)
               for face in faces):
            continue
        above = tuple(sorted(p for p, side in zip(shape, sides, strict=True) if side >= 0))
        below = tuple(sorted(p for p, side in zip(shape, sides, strict=True) if side <= 0))
        found.add((above, below) if above < below else (below, above))
    return tuple(sorted(found))


def uncut_parts(shape: CellShape) -> frozenset[CellShape]:
    """The parts of five or more vertices that cannot be cut again (:func:`plane_cuts`)
    over every way of cutting ``shape`` repeatedly: ``{shape}`` when it has no cut;
    tetrahedra are left out (a co-spherical cell may always be cut into them)."""
    if len(shape) < 5:
        return frozenset()
    cuts = plane_cuts(shape)
    if not cuts:
        return frozenset([shape])
    return frozenset(part for pair in cuts for half in pair for part in uncut_parts(half))


@attrs.frozen
class PapersCount:
    """The papers' counts on one census: the distinct combinatorial types of the cells of
    five or more vertices (``types``, their shapes' numbers of cells summed), and what
    inserting internal faces leaves: ``uncuttable`` (types none of whose cells has a
    :func:`plane_cut <plane_cuts>`), ``reduced`` (the types of every uncut part: the
    fewest types that remain when every cell is cut as far as it goes)."""

    types: dict[CellType, int]
    uncuttable: frozenset[CellType]
    reduced: frozenset[CellType]


def papers_count(shapes: Mapping[CellShape, int]) -> PapersCount:
    """:class:`PapersCount` of a census's cells: how many of each shape (``shapes``)."""
    types: Counter[CellType] = Counter()
    cuttable: set[CellType] = set()
    reduced: set[CellType] = set()
    for shape, count in shapes.items():
        if len(shape) < 5:
            continue
        kind = cell_type(shape)
        types[kind] += count
        if plane_cuts(shape):
            cuttable.add(kind)
        reduced.update(cell_type(part) for part in uncut_parts(shape))
    return PapersCount(dict(sorted(types.items())), frozenset(set(types) - cuttable),
                       frozenset(reduced))


def lattice_cells(pattern: int, squares: tuple[int, int, int] = (1, 1, 1)
                  ) -> tuple[CellShape, ...]:
    """The Delaunay cells of ``pattern``'s points in a cuboid whose squared extents are in
    the ratios ``squares`` (positive integers), each as its sorted half-lattice points;
    exact, by brute force over every four points.  Only the squared extents enter the
    insphere test (scaling an axis by e scales the orientation by e and the lifted
    coordinate by e**2), so a 1 x 1 x sqrt 2 cuboid is ``squares=(1, 1, 2)`` though
    sqrt 2 is not rational.  Agrees with :func:`pattern_cells` on rational boxes."""
    points = [(2 * (k & 1), 2 * (k >> 1 & 1), 2 * (k >> 2 & 1)) for k in range(8)]
    points += [steiner_position2(bit) for bit in range(BIT_COUNT)
               if pattern >> bit & 1]
    lattice = np.array(points, dtype=np.int64)
    weights = np.array(squares, dtype=np.int64)
    quads = np.array(list(itertools.combinations(range(len(points)), 4)), dtype=np.int64)
    base = lattice[quads[:, 0]]
    edges = lattice[quads[:, 1:]] - base[:, None, :]  # (q, 3, 3)
    orientation = _det3(edges)
    quads, orientation = quads[orientation != 0], orientation[orientation != 0]
    # rows p - e, |p - e|^2 for p in the quadruple and e every point: (q, n, 4, 4)
    offsets = lattice[quads][:, None, :, :] - lattice[None, :, None, :]
    lifted = (offsets * offsets * weights).sum(axis=3)
    matrix = np.concatenate([offsets, lifted[..., None]], axis=3)
    location = -_det4(matrix) * np.sign(orientation)[:, None]  # > 0: e inside the sphere
    empty = (location <= 0).all(axis=1)
    cells = {tuple(sorted(points[n] for n in np.flatnonzero(row == 0)))
             for row in location[empty]}
    return tuple(sorted(cells))


def _det3(m: NDArray[np.int64]) -> NDArray[np.int64]:
    result: NDArray[np.int64] = (
        m[..., 0, 0] * (m[..., 1, 1] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 1])
        - m[..., 0, 1] * (m[..., 1, 0] * m[..., 2, 2] - m[..., 1, 2] * m[..., 2, 0])
        + m[..., 0, 2] * (m[..., 1, 0] * m[..., 2, 1] - m[..., 1, 1] * m[..., 2, 0]))
    return result


def _det4(m: NDArray[np.int64]) -> NDArray[np.int64]:
    total = np.zeros(m.shape[:-2], dtype=np.int64)
    for column in range(4):
        minor = np.delete(np.delete(m, 0, axis=-2), column, axis=-1)
        total += (-1) ** column * m[..., 0, column] * _det3(minor)
    return total


def lattice_shape(points: CellShape, squares: tuple[int, int, int] = (1, 1, 1)
                  ) -> CellShape:
    """:func:`cell_shape` of a cell given by its half-lattice ``points`` in a cuboid of
    squared extents ``squares``: the smallest over the symmetries that exchange only
    equal sides."""
    best: CellShape | None = None
    for permutation in itertools.permutations(range(3)):
        if any(squares[permutation[axis]] != squares[axis] for axis in range(3)):
            continue
        for flips in itertools.product((False, True), repeat=3):
            moved = tuple(sorted(
                (_axis(p, permutation[0], flips[0]), _axis(p, permutation[1], flips[1]),
                 _axis(p, permutation[2], flips[2])) for p in points))
            if best is None or moved < best:
                best = moved
    assert best is not None
    return best


def _axis(point: tuple[int, int, int], axis: int, flip: bool) -> int:
    return 2 - point[axis] if flip else point[axis]


def lattice_census(patterns: Iterable[int], squares: tuple[int, int, int] = (1, 1, 1)
                   ) -> Counter[CellShape]:
    """How many cells of each shape :func:`lattice_cells` finds over ``patterns``."""
    shapes: Counter[CellShape] = Counter()
    for pattern in patterns:
        shapes.update(lattice_shape(cell, squares) for cell in lattice_cells(pattern, squares))
    return shapes
