"""Refinement of an octree: split leaves into octants while a criterion fails on a leaf that
a region meets, up to a maximum level (breadth first, so the result is the same whatever
the order); and derefinement: merge eight sibling leaves back into their parent where the
parent is acceptable (the seed's "refine, improve and derefine")."""

from __future__ import annotations

from collections.abc import Callable

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.regions import answers_on_boxes
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
        below = [cell for cell in pending if cell[0] < max_level]
        leaves.extend(cell for cell in pending if cell[0] >= max_level)
        following: list[Cell] = []
        for cell, split in zip(below, _splits(octree, below, criterion, region), strict=True):
            if split:
                following.extend(cell_children(cell))
            else:
                leaves.append(cell)
        pending = following
    return attrs.evolve(octree, leaves=leaves, balanced=False)


def _splits(octree: Octree, cells: list[Cell], criterion: Callable[[Box], bool],
            region: Callable[[Box], bool]) -> list[bool]:
    """Whether each of ``cells`` is split: ``region`` meets its box and ``criterion`` does
    not accept it.  Both are asked level by level about all the cells at once
    (:func:`~geomexact.mesh3d.octree.regions.answers_on_boxes`: each distinct side of a box
    made once), the criterion only about the boxes the region meets."""
    split = [False] * len(cells)
    by_level: dict[int, list[int]] = {}
    for n, cell in enumerate(cells):
        by_level.setdefault(cell[0], []).append(n)
    for level, at in by_level.items():
        sides: list[list[tuple[Rational, Rational]]] = []
        columns = []
        for axis in range(3):
            index: dict[int, int] = {}
            columns.append([index.setdefault(cells[n][axis + 1], len(index)) for n in at])
            sides.append([octree.cell_interval(level, axis, p) for p in index])
        rows = np.array(columns, dtype=np.int64).T.reshape(-1, 3)
        met = np.flatnonzero(answers_on_boxes(region, sides, rows))
        accepted = answers_on_boxes(criterion, sides, rows[met])
        for n in met[~accepted].tolist():
            split[at[n]] = True
    return split


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
