"""Refinement of an octree: split leaves into octants while a criterion fails on a leaf that
a region meets, up to a maximum level (breadth first, so the result is the same whatever
the order)."""

from __future__ import annotations

from collections.abc import Callable

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.tree import Cell, Octree, cell_children

__all__ = ["MAX_LEVEL", "refine_octree"]

MAX_LEVEL = 16
"""The deepest level :func:`refine_octree` accepts (2**16 cells per axis per grid cell)."""


def refine_octree(octree: Octree, criterion: Callable[[Box], bool],
                  region: Callable[[Box], bool], max_level: int) -> Octree:
    """Split every leaf below ``max_level`` that ``region`` meets and ``criterion`` does not
    accept, then its octants likewise, until none is left."""
    if not 0 <= max_level <= MAX_LEVEL:
        raise PreconditionError("octree", f"the maximum level is 0..{MAX_LEVEL}, not "
                                f"{max_level}")
    leaves: list[Cell] = []
    pending = list(octree.leaves)
    while pending:
        following: list[Cell] = []
        for cell in pending:
            if cell[0] < max_level:
                box = octree.cell_box(cell)
                if region(box) and not criterion(box):
                    following.extend(cell_children(cell))
                    continue
            leaves.append(cell)
        pending = following
    return Octree(octree.domain, octree.grid, leaves)
