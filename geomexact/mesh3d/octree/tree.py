"""The octree value: a box domain, the grid of its level-0 cells and the leaves.

A cell is ``(level, i, j, k)``: at level L the domain's grid cell extents are divided by
2**L and (i, j, k) is the cell's integer position on that level's grid (``0 <= i <
nx * 2**L``).  Leaves are kept sorted, so an :class:`Octree` is a value whose equality and
iteration order never depend on how it was built.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import TypeAlias

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational
from geomexact.mesh3d.cuboid.boxes import Box

__all__ = ["Cell", "Octree", "cell_children", "cell_parent", "octree_of_grid"]

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

    @property
    def depth(self) -> int:
        """The deepest leaf level (0 for the grid itself)."""
        return max((cell[0] for cell in self.leaves), default=0)

    @property
    def leaf_count(self) -> int:
        return len(self.leaves)

    def cell_extents(self, level: int) -> tuple[Rational, Rational, Rational]:
        """The exact extents of a cell of ``level``."""
        scale = 1 << level
        x, y, z = (e / (n * scale) for e, n in zip(self.domain.extents, self.grid,
                                                    strict=True))
        return (x, y, z)

    def cell_box(self, cell: Cell) -> Box:
        """The exact box of ``cell``."""
        level, *position = cell
        extents = self.cell_extents(level)
        low = tuple(lo + e * p for lo, e, p in zip(self.domain.low, extents, position,
                                                    strict=True))
        high = tuple(lo + e for lo, e in zip(low, extents, strict=True))
        return Box(low, high)

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

