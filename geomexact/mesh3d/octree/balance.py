"""2:1 balance across faces and edges: after :func:`balance_two_to_one`, two leaves that
share part of a face or of an edge differ by at most one level, so every leaf is
*1-irregular* (its edges and faces carry at most their midpoints and centres as other
leaves' corners) and has a cuboid Steiner pattern.  ``specs/octree.md`` argues why edges
are needed as well as faces, and why corners are not."""

from __future__ import annotations

from collections.abc import Iterable
from itertools import product
from typing import Any, Final

import attrs
import numpy as np

from geomexact.mesh3d.octree.tree import Cell, Octree, cell_children

__all__ = ["NEIGHBOUR_OFFSETS", "balance_two_to_one", "irregular_leaves", "tiling_problems"]

NEIGHBOUR_OFFSETS: Final[tuple[tuple[int, int, int], ...]] = tuple(
    (x, y, z) for x, y, z in product((-1, 0, 1), repeat=3)
    if 1 <= abs(x) + abs(y) + abs(z) <= 2
)
"""The 6 face and 12 edge neighbours of a cell, as offsets on its own level."""


def _ancestors(leaves: Iterable[Cell]) -> set[Cell]:
    """Every leaf and every cell above one."""
    nodes: set[Cell] = set()
    for cell in leaves:
        while cell not in nodes:
            nodes.add(cell)
            level, i, j, k = cell
            if level == 0:
                break
            cell = (level - 1, i >> 1, j >> 1, k >> 1)
    return nodes


def _level_keys(cells: Any, grid: tuple[int, int, int], level: int) -> Any:
    """One int64 per cell of ``level`` (rows of (i, j, k)), unique on that level."""
    ny, nz = grid[1] << level, grid[2] << level
    return (cells[:, 0] * ny + cells[:, 1]) * nz + cells[:, 2]


def _coarse_targets(octree: Octree, leaves: Iterable[Cell]) -> list[tuple[Cell, Cell]]:
    """(leaf, target): each level L-1 cell next to a leaf of level L >= 2 (across a face or
    an edge) that is covered by a leaf coarser than L-1 (vectorised by level)."""
    nodes = _ancestors(leaves)
    by_level: dict[int, list[Cell]] = {}
    for cell in nodes:
        by_level.setdefault(cell[0], []).append(cell)
    offsets = np.array(NEIGHBOUR_OFFSETS, dtype=np.int64)
    found: list[tuple[Cell, Cell]] = []
    leaf_set = set(leaves)
    for level in sorted(by_level):
        if level < 2:
            continue
        cells = np.array(sorted(c for c in by_level[level] if c in leaf_set),
                         dtype=np.int64).reshape(-1, 4)[:, 1:]
        if not len(cells):
            continue
        neighbours = cells[:, None, :] + offsets[None, :, :]  # n x 18 x 3
        bound = np.array(octree.grid, dtype=np.int64) << level
        inside = ((neighbours >= 0) & (neighbours < bound)).all(axis=2)
        targets = neighbours >> 1
        upper = np.array(sorted(by_level.get(level - 1, [])), dtype=np.int64).reshape(-1, 4)
        known = np.sort(_level_keys(upper[:, 1:], octree.grid, level - 1))
        keys = _level_keys(targets.reshape(-1, 3), octree.grid, level - 1)
        at = np.minimum(np.searchsorted(known, keys), max(len(known) - 1, 0))
        present = (known[at] == keys) if len(known) else np.zeros(len(keys), dtype=bool)
        missing = inside.ravel() & ~present
        for row in np.flatnonzero(missing).tolist():
            i, j, k = cells[row // 18].tolist()
            ti, tj, tk = targets.reshape(-1, 3)[row].tolist()
            found.append(((level, i, j, k), (level - 1, ti, tj, tk)))
    return found


def balance_two_to_one(octree: Octree) -> Octree:
    """The coarsest refinement of ``octree`` in which leaves sharing part of a face or an
    edge differ by at most one level: rounds of forced splits (each split is forced, so
    the result does not depend on the order) until none is needed."""
    if octree.balanced:
        return octree
    leaves = set(octree.leaves)
    while True:
        pending = _coarse_targets(octree, leaves)
        if not pending:
            return attrs.evolve(octree, leaves=leaves, balanced=True)
        nodes = _ancestors(leaves)
        for _, target in sorted(pending):
            _split_down_to(target, leaves, nodes)


def _split_down_to(target: Cell, leaves: set[Cell], nodes: set[Cell]) -> None:
    """Split the leaf covering ``target`` and its descendants until ``target`` is a node."""
    chain = [target]
    while chain[-1] not in nodes:
        level, i, j, k = chain[-1]
        chain.append((level - 1, i >> 1, j >> 1, k >> 1))
    for cell in reversed(chain[:-1]):
        parent = (cell[0] - 1, cell[1] >> 1, cell[2] >> 1, cell[3] >> 1)
        leaves.discard(parent)
        for child in cell_children(parent):
            leaves.add(child)
            nodes.add(child)


def irregular_leaves(octree: Octree) -> list[tuple[Cell, Cell]]:
    """(leaf, coarse cell) pairs where a leaf of level L touches, across a face or an
    edge, a leaf coarser than L - 1 (``coarse cell`` is the level L-1 cell it touches);
    empty when every leaf is 1-irregular."""
    return sorted(_coarse_targets(octree, octree.leaves))


def tiling_problems(octree: Octree) -> list[str]:
    """Why the leaves do not tile the domain exactly once (empty when they do): a leaf
    outside the grid, a leaf inside another, or leaves whose volumes do not add up."""
    problems = [f"leaf {cell} is outside the {octree.grid} grid"
                for cell in octree.leaves if not octree.contains_cell(cell)]
    leaves = set(octree.leaves)
    for cell in octree.leaves:
        level, i, j, k = cell
        for up in range(1, level + 1):
            ancestor = (level - up, i >> up, j >> up, k >> up)
            if ancestor in leaves:
                problems.append(f"leaf {cell} lies inside leaf {ancestor}")
                break
    depth = octree.depth
    nx, ny, nz = octree.grid
    covered = sum(8 ** (depth - cell[0]) for cell in leaves)
    if not problems and covered != nx * ny * nz * 8 ** depth:
        problems.append(f"the leaves cover {covered} of {nx * ny * nz * 8 ** depth} cells "
                        f"of level {depth}")
    return problems
