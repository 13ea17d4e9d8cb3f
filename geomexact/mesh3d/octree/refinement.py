"""Refinement of an octree: split leaves into octants while a criterion fails on a leaf that
a region meets, up to a maximum level (breadth first, so the result is the same whatever
the order); and derefinement: merge eight sibling leaves back into their parent where the
parent is acceptable (the seed's "refine, improve and derefine")."""

from __future__ import annotations

from collections.abc import Callable

import attrs

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.tree import Cell, Octree, cell_children, cell_parent

__all__ = ["MAX_LEVEL", "derefine_octree", "refine_octree"]

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
    return attrs.evolve(octree, leaves=leaves, balanced=False)


def derefine_octree(octree: Octree, accepts: Callable[[Box], bool],
                    min_level: int = 0) -> Octree:
    """Merge the eight leaves of a parent into it where ``accepts(parent box)`` holds and
    the parent's level is at least ``min_level``; again on the merged leaves, deepest
    level first, until no merge is left (the result does not depend on the leaves'
    order).  The result may need the 2:1 balance again."""
    if min_level < 0:
        raise PreconditionError("octree", f"the minimum level is not negative, not "
                                f"{min_level}")
    leaves = set(octree.leaves)
    for level in range(octree.depth, min_level, -1):
        siblings: dict[Cell, list[Cell]] = {}
        for cell in leaves:
            if cell[0] == level:
                siblings.setdefault(cell_parent(cell), []).append(cell)
        for parent, children in sorted(siblings.items()):
            if len(children) == 8 and accepts(octree.cell_box(parent)):
                leaves.difference_update(children)
                leaves.add(parent)
    return attrs.evolve(octree, leaves=leaves, balanced=False)
