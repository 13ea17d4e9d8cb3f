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
from collections.abc import Iterable

import attrs

from geomexact.mesh3d.cospherical import PolyhedralCell, polyhedral_cells
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3

__all__ = ["CellShape", "PolyhedralCensus", "cell_shape", "merged", "pattern_cells",
           "polyhedral_census"]

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
