"""The octree value: a box domain, the grid of its level-0 cells and the leaves.

A cell is ``(level, i, j, k)``: at level L the domain's grid cell extents are divided by
2**L and (i, j, k) is the cell's integer position on that level's grid (``0 <= i <
nx * 2**L``).  Leaves are kept sorted, so an :class:`Octree` is a value whose equality and
iteration order never depend on how it was built.

The grid is equal boxes, or, with ``planes``, *rectilinear*: the grid lines of each axis
are given (exact, increasing, from the domain's low to its high side), so the grid cells
may differ in size and shape -- a device's layers of any rational thickness are whole
grid cells.  Everything topological (levels, balance, patterns, conformity) is the same;
only the points differ: inside a grid cell the map from lattice to space is a translation
and a positive scaling per axis.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Sequence
from itertools import pairwise
from typing import TypeAlias

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.mesh3d.cuboid.boxes import Box

__all__ = ["Cell", "Octree", "Planes", "cell_children", "cell_parent", "octree_of_grid",
           "octree_of_planes"]

Cell: TypeAlias = tuple[int, int, int, int]
"""(level, i, j, k)."""


def _grid(value: Iterable[int]) -> tuple[int, int, int]:
    nx, ny, nz = (int(v) for v in value)
    if min(nx, ny, nz) < 1:
        raise PreconditionError("octree", f"a grid has at least one cell per axis, not "
                                f"{(nx, ny, nz)}")
    return (nx, ny, nz)


def _sorted_cells(cells: Iterable[Cell]) -> tuple[Cell, ...]:
    return tuple(sorted(cells))


Planes: TypeAlias = tuple[tuple[Rational, ...], tuple[Rational, ...], tuple[Rational, ...]]


@attrs.frozen(slots=True)
class Octree:
    """The leaves (sorted cells) of an octree over ``domain`` with ``grid`` level-0 cells
    per axis.  The leaves tile the domain: :func:`~geomexact.mesh3d.octree.balance.
    tiling_problems` checks it."""

    domain: Box
    grid: tuple[int, int, int] = attrs.field(converter=_grid)
    leaves: tuple[Cell, ...] = attrs.field(converter=_sorted_cells)
    balanced: bool = attrs.field(default=False, eq=False)
    """True when made by the 2:1 balance (every leaf known 1-irregular): a fact about how
    the value was made, so not part of its equality."""
    planes: Planes | None = attrs.field(default=None, kw_only=True)
    """The grid lines of each axis (``grid[a] + 1`` of them) of a rectilinear grid, or
    None for equal grid cells."""

    def __attrs_post_init__(self) -> None:
        if self.planes is None:
            return
        for axis, lines in enumerate(self.planes):
            if (len(lines) != self.grid[axis] + 1 or lines[0] != self.domain.low[axis]
                    or lines[-1] != self.domain.high[axis]
                    or any(b <= a for a, b in pairwise(lines))):
                raise PreconditionError("octree", f"the grid lines of axis {axis} are "
                                        f"{self.grid[axis] + 1} increasing values from the "
                                        "domain's low side to its high side")

    @property
    def depth(self) -> int:
        """The deepest leaf level (0 for the grid itself)."""
        return max((cell[0] for cell in self.leaves), default=0)

    @property
    def leaf_count(self) -> int:
        return len(self.leaves)

    def cell_extents(self, level: int) -> tuple[Rational, Rational, Rational]:
        """The exact extents of a cell of ``level`` (equal grid cells only)."""
        if self.planes is not None:
            raise PreconditionError("octree", "the cells of a rectilinear grid differ in "
                                    "size: ask each one's box")
        scale = 1 << level
        x, y, z = (e / (n * scale) for e, n in zip(self.domain.extents, self.grid,
                                                    strict=True))
        return (x, y, z)

    def grid_cell_extents(self, cell: Cell) -> tuple[Rational, Rational, Rational]:
        """The exact extents of the grid cell that holds ``cell`` (its shape: the cell is
        that box scaled by 2**-level)."""
        if self.planes is None:
            return self.cell_extents(0)
        level, *position = cell
        extents = []
        for axis, value in enumerate(position):
            g = value >> level
            extents.append(self.planes[axis][g + 1] - self.planes[axis][g])
        return (extents[0], extents[1], extents[2])

    def cell_interval(self, level: int, axis: int, position: int) -> tuple[Rational, Rational]:
        """The exact [low, high] along ``axis`` of the cells of ``level`` at integer
        ``position`` on that axis (a box's side: the same for every cell in that slab)."""
        if self.planes is not None:
            scale = 1 << level
            g, r = divmod(position, scale)
            start, end = self.planes[axis][g], self.planes[axis][g + 1]
            step = (end - start) / scale
            return start + step * r, start + step * (r + 1)
        extent = (self.domain.high[axis] - self.domain.low[axis]) / (self.grid[axis] << level)
        low = self.domain.low[axis] + extent * position
        return low, low + extent

    def cell_box(self, cell: Cell) -> Box:
        """The exact box of ``cell``."""
        level, *position = cell
        sides = [self.cell_interval(level, axis, value) for axis, value in enumerate(position)]
        return Box(tuple(low for low, _ in sides), tuple(high for _, high in sides))

    def contains_cell(self, cell: Cell) -> bool:
        """True when ``cell``'s position is inside the domain's grid at its level."""
        level, i, j, k = cell
        nx, ny, nz = self.grid
        scale = 1 << level
        return 0 <= i < nx * scale and 0 <= j < ny * scale and 0 <= k < nz * scale

    def levels(self) -> Iterator[tuple[int, int]]:
        """(level, leaves at that level), by level."""
        counts: dict[int, int] = {}
        for cell in self.leaves:
            counts[cell[0]] = counts.get(cell[0], 0) + 1
        yield from sorted(counts.items())


def cell_children(cell: Cell) -> tuple[Cell, ...]:
    """The eight octants of ``cell`` (x fastest, then y, then z)."""
    level, i, j, k = cell
    return tuple((level + 1, 2 * i + (c & 1), 2 * j + (c >> 1 & 1), 2 * k + (c >> 2 & 1))
                 for c in range(8))


def cell_parent(cell: Cell) -> Cell:
    """The cell one level up that contains ``cell`` (level >= 1)."""
    level, i, j, k = cell
    if level < 1:
        raise PreconditionError("octree", f"cell {cell} is a grid cell: it has no parent")
    return (level - 1, i >> 1, j >> 1, k >> 1)


def octree_of_grid(domain: Box, grid: tuple[int, int, int] = (1, 1, 1)) -> Octree:
    """The octree whose leaves are the ``grid`` cells of ``domain`` (level 0)."""
    nx, ny, nz = _grid(grid)
    return Octree(domain, (nx, ny, nz),
                  [(0, i, j, k) for i in range(nx) for j in range(ny) for k in range(nz)])


def octree_of_planes(planes: Sequence[Sequence[Rational | int]]) -> Octree:
    """The octree whose leaves are the cells of the rectilinear grid with these grid
    lines per axis (exact, increasing; two or more per axis)."""
    lines = tuple(tuple(mpq(v) for v in axis) for axis in planes)
    if len(lines) != 3 or any(len(axis) < 2 for axis in lines):
        raise PreconditionError("octree", "a rectilinear grid has two or more grid lines on "
                                "each of three axes")
    domain = Box(tuple(axis[0] for axis in lines), tuple(axis[-1] for axis in lines))
    grid = (len(lines[0]) - 1, len(lines[1]) - 1, len(lines[2]) - 1)
    return Octree(domain, grid, [(0, i, j, k) for i in range(grid[0])
                                 for j in range(grid[1]) for k in range(grid[2])],
                  planes=(lines[0], lines[1], lines[2]))

