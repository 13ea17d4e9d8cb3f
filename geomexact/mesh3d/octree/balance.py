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

from geomexact.mesh3d.octree.tree import Cell, Octree

__all__ = ["NEIGHBOUR_OFFSETS", "balance_two_to_one", "irregular_leaves", "tiling_problems"]

NEIGHBOUR_OFFSETS: Final[tuple[tuple[int, int, int], ...]] = tuple(
    (x, y, z) for x, y, z in product((-1, 0, 1), repeat=3)
    if 1 <= abs(x) + abs(y) + abs(z) <= 2
)
"""The 6 face and 12 edge neighbours of a cell, as offsets on its own level."""


def _by_level(cells: Iterable[Cell]) -> dict[int, Any]:
    """The cells as one (m x 3) int64 array of (i, j, k) per level (in their order)."""
    array = np.array(list(cells), dtype=np.int64).reshape(-1, 4)
    array = array[np.argsort(array[:, 0], kind="stable")]
    levels, starts = np.unique(array[:, 0], return_index=True)
    bounds = [*starts.tolist(), len(array)]
    return {level: array[bounds[n]:bounds[n + 1], 1:]
            for n, level in enumerate(levels.tolist())}


def _level_keys(cells: Any, grid: tuple[int, int, int], level: int) -> Any:
    """One int64 per cell of ``level`` (rows of (i, j, k)), unique on that level."""
    ny, nz = grid[1] << level, grid[2] << level
    return (cells[:, 0] * ny + cells[:, 1]) * nz + cells[:, 2]


def _node_keys(by_level: dict[int, Any], grid: tuple[int, int, int], level: int) -> Any:
    """The sorted keys of the nodes of ``level``: the leaves there and every cell of that
    level above a finer leaf."""
    parts = [_level_keys(cells >> (finer - level), grid, level)
             for finer, cells in by_level.items() if finer >= level and len(cells)]
    return np.unique(np.concatenate(parts)) if parts else np.zeros(0, dtype=np.int64)


def _among(known: Any, keys: Any) -> Any:
    """Which of ``keys`` are in the sorted array ``known``."""
    if not len(known):
        return np.zeros(len(keys), dtype=bool)
    at = np.minimum(np.searchsorted(known, keys), len(known) - 1)
    return known[at] == keys


def _family_targets() -> Any:
    """For each set of a parent's children (bit b: octant b = x + 2y + 4z), the steps d
    from the parent to the level L-1 cells those children's 18 neighbours fall in, the
    parent itself left out (it is a node), each listed once and the list padded to 18 by
    repeating its first (256 x 18 x 3).  One child's: on each axis d is -1 or 0 where its
    octant bit is 0, 0 or 1 where it is 1 (-1 or 1 exactly when the neighbour steps out
    that way), and at most two axes step."""
    table = np.zeros((256, len(NEIGHBOUR_OFFSETS), 3), dtype=np.int64)
    for children in range(1, 256):
        steps = sorted({d for octant in range(8) if children >> octant & 1
                        for d in product(*((b - 1, b) for b in
                                           ((octant >> axis) & 1 for axis in range(3))))
                        if 1 <= sum(map(abs, d)) <= 2})
        table[children] = steps + steps[:1] * (len(NEIGHBOUR_OFFSETS) - len(steps))
    return table


FAMILY_TARGETS: Final = _family_targets()


def _uncovered_targets(by_level: dict[int, Any], grid: tuple[int, int, int],
                       level: int, *, families: bool = False) -> tuple[Any, Any]:
    """For the leaves of ``level`` >= 2: (rows, targets) of each level L-1 cell next to
    one of them across a face or an edge that is not a node (a coarser leaf covers it):
    ``rows[n]`` is the leaf's row in ``by_level[level]``, ``targets[n]`` the cell, once
    for each of the leaf's 18 neighbours that falls in it.

    With ``families`` the leaves are taken by parent: each parent once, with the steps of
    :data:`FAMILY_TARGETS` for the children that are leaves here -- the same cells (each
    perhaps more than once), found with a fraction of the work; ``rows`` is then the
    parent's first leaf's row."""
    cells = by_level[level]
    if families:
        parents = cells >> 1
        _, first, family = np.unique(_level_keys(parents, grid, level - 1),
                                     return_index=True, return_inverse=True)
        children = np.zeros(len(first), dtype=np.int64)
        octants = (cells[:, 0] & 1) + 2 * (cells[:, 1] & 1) + 4 * (cells[:, 2] & 1)
        np.bitwise_or.at(children, family.ravel(), np.left_shift(1, octants))
        steps = FAMILY_TARGETS[children]
        targets = (parents[first][:, None, :] + steps).reshape(-1, 3)
        bound = np.array(grid, dtype=np.int64) << (level - 1)
        inside = ((targets >= 0) & (targets < bound)).all(axis=1)
    else:
        steps = np.array(NEIGHBOUR_OFFSETS, dtype=np.int64)
        neighbours = (cells[:, None, :] + steps[None, :, :]).reshape(-1, 3)  # 18 a leaf
        bound = np.array(grid, dtype=np.int64) << level
        inside = ((neighbours >= 0) & (neighbours < bound)).all(axis=1)
        targets = neighbours >> 1
    known = _node_keys(by_level, grid, level - 1)
    missing = inside & ~_among(known, _level_keys(targets, grid, level - 1))
    rows = np.flatnonzero(missing) // len(NEIGHBOUR_OFFSETS)
    return (first[rows] if families else rows), targets[missing]


def _coarse_targets(octree: Octree, leaves: Iterable[Cell]) -> list[tuple[Cell, Cell]]:
    """(leaf, target): each level L-1 cell next to a leaf of level L >= 2 (across a face or
    an edge) that is covered by a leaf coarser than L-1."""
    by_level = _by_level(leaves)
    found: list[tuple[Cell, Cell]] = []
    for level in sorted(by_level):
        if level < 2:
            continue
        rows, targets = _uncovered_targets(by_level, octree.grid, level)
        cells = by_level[level]
        for row, (ti, tj, tk) in zip(rows.tolist(), targets.tolist(), strict=True):
            i, j, k = cells[row].tolist()
            found.append(((level, i, j, k), (level - 1, ti, tj, tk)))
    return found


def balance_two_to_one(octree: Octree) -> Octree:
    """The coarsest refinement of ``octree`` in which leaves sharing part of a face or an
    edge differ by at most one level.  Every split is forced, so the result does not
    depend on their order; they are made level by level from the finest (a leaf of
    level L only forces cells of level L-1 to be nodes, and the leaves a split makes are
    of level L-1 or coarser, checked when their level's turn comes)."""
    if octree.balanced:
        return octree
    grid = octree.grid
    by_level = _by_level(octree.leaves)
    for level in range(max(by_level, default=0), 1, -1):
        if level not in by_level or not len(by_level[level]):
            continue
        _, targets = _uncovered_targets(by_level, grid, level, families=True)
        if len(targets):
            _split_down_to(by_level, grid, np.unique(targets, axis=0), level - 1)
    rows = np.concatenate([np.zeros((0, 4), dtype=np.int64)] + [
        np.column_stack((np.full(len(cells), level, dtype=np.int64), cells))
        for level, cells in by_level.items()])
    return attrs.evolve(octree, leaves=list(map(tuple, rows.tolist())), balanced=True)


def _split_down_to(by_level: dict[int, Any], grid: tuple[int, int, int], targets: Any,
                   level: int) -> None:
    """Split the leaves covering the cells ``targets`` of ``level`` (none of them a node)
    and their descendants until every target is a node (a leaf)."""
    covering = np.full(len(targets), -1, dtype=np.int64)
    for coarse in range(level - 1, -1, -1):
        if coarse not in by_level or not len(by_level[coarse]):
            continue
        open_rows = covering < 0
        keys = _level_keys(targets >> (level - coarse), grid, coarse)
        leaf_keys = np.sort(_level_keys(by_level[coarse], grid, coarse))
        covering[open_rows & _among(leaf_keys, keys)] = coarse
    # the cells to split on each level: a covering leaf and the chain down to the target
    split: dict[int, Any] = {}
    for coarse in np.unique(covering).tolist():
        chosen = targets[covering == coarse]
        for depth in range(coarse, level):
            cells = chosen >> (level - depth)
            split[depth] = cells if depth not in split else np.concatenate((split[depth],
                                                                              cells))
    octants = np.array([(c & 1, c >> 1 & 1, c >> 2 & 1) for c in range(8)], dtype=np.int64)
    for depth in sorted(split):
        cells = np.unique(split[depth], axis=0)
        split_keys = _level_keys(cells, grid, depth)
        leaves = by_level.get(depth)
        if leaves is not None and len(leaves):  # the covering leaves stop being leaves
            keep = ~_among(np.sort(split_keys), _level_keys(leaves, grid, depth))
            by_level[depth] = leaves[keep]
        children = (2 * cells[:, None, :] + octants[None, :, :]).reshape(-1, 3)
        if depth + 1 in split:  # a child split further is a node, not a leaf
            further = np.unique(_level_keys(split[depth + 1], grid, depth + 1))
            children = children[~_among(further, _level_keys(children, grid, depth + 1))]
        below = by_level.get(depth + 1)
        by_level[depth + 1] = children if below is None else np.concatenate((below,
                                                                             children))


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
