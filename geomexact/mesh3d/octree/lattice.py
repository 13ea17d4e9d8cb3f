"""The octree's integer lattice: every leaf corner and Steiner point as an integer point, the
vertex table (leaf corners, lexicographic), each leaf's Steiner pattern and template.

With D = depth + 1, a leaf of level L spans s = 2**(D - L) lattice units per axis, so its
edge midpoints and face centres are lattice points too.  Lattice point (X, Y, Z) is the
exact point ``low + extents * (X / (nx 2**D), Y / (ny 2**D), Z / (nz 2**D))``: a translation
and a positive scaling per axis, which keep orient3d signs and the lexicographic order of
points (so the conforming split order can be read on the lattice).  Vectorised with numpy
on int64 (exact: lattice coordinates are integers below 2**21 per axis here).
"""

from __future__ import annotations

from typing import Any, Final

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point3, nearest_double
from geomexact.mesh3d.cuboid.numbering import CORNER_POSITIONS, steiner_position2
from geomexact.mesh3d.octree.tree import Octree

__all__ = ["CODE_OFFSETS2", "MAX_LATTICE_POINTS", "OctreeLattice", "octree_lattice"]

CODE_OFFSETS2: Final = np.array(
    [tuple(2 * c for c in CORNER_POSITIONS[k]) for k in range(8)]
    + [steiner_position2(bit) for bit in range(18)], dtype=np.int64)
"""Point code (corner k: k; Steiner point of bit i: 8 + i) -> its position in half-units of
the leaf's edge (26 x 3)."""

MAX_LATTICE_POINTS: Final = 1 << 62
"""The lattice's point count must stay below this (one int64 key per point)."""


@attrs.frozen(slots=True, eq=False)
class OctreeLattice:
    """The octree on its lattice (arrays are read only; rows follow ``octree.leaves``):

    - ``size``: lattice points per axis minus one (nx 2**D, ...);
    - ``vertices``: (V, 3) lattice points of the leaf corners, lexicographic (vertex id =
      row);
    - ``codes``: (leaves, 26) vertex id of each leaf's corners and present Steiner points
      (-1 for an absent one), by point code;
    - ``patterns``: each leaf's Steiner pattern (bit i: the midpoint of its edge i or the
      centre of its face i is a vertex);
    - ``templates``: each leaf's 5-tetrahedron template, the parity of i + j + k at its own
      level."""

    octree: Octree
    depth: int
    size: tuple[int, int, int]
    vertices: Any
    codes: Any
    patterns: Any
    templates: Any

    @property
    def vertex_count(self) -> int:
        return int(self.vertices.shape[0])

    def unit(self, axis: int) -> Rational:
        """The exact length of one lattice unit along ``axis`` (equal grid cells only)."""
        if self.octree.planes is not None:
            raise PreconditionError("octree", "a rectilinear grid's lattice units differ")
        return self.octree.domain.extents[axis] / self.size[axis]  # type: ignore[no-any-return]

    def coordinate(self, axis: int, value: Rational | int) -> Rational:
        """The exact coordinate along ``axis`` of the lattice coordinate ``value`` (an
        integer, or a rational strictly inside a grid cell)."""
        octree = self.octree
        if octree.planes is None:
            return octree.domain.low[axis] + octree.domain.extents[axis] * mpq(  # type: ignore[no-any-return]
                value) / self.size[axis]
        per = 1 << self.depth
        cell = min(int(mpq(value) // per), octree.grid[axis] - 1)
        start, end = octree.planes[axis][cell], octree.planes[axis][cell + 1]
        return start + (end - start) * (mpq(value) - cell * per) / per  # type: ignore[no-any-return]

    def exact_points(self) -> list[Point3]:
        """The vertices' exact coordinates, by id."""
        return self.exact_points_of(self.vertices)

    def exact_points_of(self, lattice_points: Any) -> list[Point3]:
        """The exact coordinates of ``lattice_points`` ((n, 3) integers; each distinct
        lattice coordinate is converted once: a lattice has few of them per axis)."""
        columns = []
        for axis, column in enumerate(np.asarray(lattice_points).reshape(-1, 3).T.tolist()):
            exact = {value: self.coordinate(axis, value) for value in set(column)}
            doubles = {value: nearest_double(q) for value, q in exact.items()}
            columns.append(([exact[v] for v in column], [doubles[v] for v in column]))
        (xs, fxs), (ys, fys), (zs, fzs) = columns
        return [Point3(*values) for values in zip(xs, ys, zs, fxs, fys, fzs, strict=True)]


def _keys(points: Any, size: tuple[int, int, int]) -> Any:
    """One int64 per lattice point, increasing with its lexicographic (x, y, z) order."""
    _, ny, nz = size
    return (points[..., 0] * (ny + 1) + points[..., 1]) * (nz + 1) + points[..., 2]


DENSE_POINTS_PER_KEY: Final = 8
""":func:`_vertex_table` numbers the vertices through a table of every lattice point when
the lattice has at most this many points per looked-up key (else by sorting the keys)."""


def _vertex_table(keys: Any, low: Any, half: Any,
                  size: tuple[int, int, int]) -> tuple[Any, Any]:
    """The vertices (the distinct leaf corners, ``keys[:, :8]``, lexicographic: V x 3) and,
    for every key, its vertex id or -1 when it is not a corner's.  When every leaf lies in
    the lattice (its keys then name its points one to one) and the lattice is small, by a
    table of every lattice point (a scatter and a gather; the vertices read off their
    keys), else by a sort and a binary search (the vertices at their first corner): the
    same arrays."""
    points = (size[0] + 1) * (size[1] + 1) * (size[2] + 1)
    corners = keys[:, :8].ravel()
    inside = bool(((low >= 0) & (low + 2 * half[:, None] <= np.array(size))).all())
    if inside and points <= DENSE_POINTS_PER_KEY * max(keys.size, 1):
        table = np.zeros(points, dtype=np.int64)
        table[corners] = 1
        vertex_keys = np.flatnonzero(table)
        table -= 1
        table[vertex_keys] = np.arange(len(vertex_keys), dtype=np.int64)
        _, ny, nz = size
        rest, z = np.divmod(vertex_keys, nz + 1)
        x, y = np.divmod(rest, ny + 1)
        return np.stack((x, y, z), axis=1), table[keys]
    vertex_keys, first = np.unique(corners, return_index=True)
    positions = low[:, None, :] + half[:, None, None] * CODE_OFFSETS2[None, :8, :]
    found = np.minimum(np.searchsorted(vertex_keys, keys), len(vertex_keys) - 1)
    return (positions.reshape(-1, 3)[first],
            np.where(vertex_keys[found] == keys, found, -1))


def octree_lattice(octree: Octree) -> OctreeLattice:
    """The lattice, vertices, patterns and templates of ``octree`` (whose leaves must tile
    its domain; the patterns are only meaningful when every leaf is 1-irregular)."""
    depth = octree.depth + 1
    size = (octree.grid[0] << depth, octree.grid[1] << depth, octree.grid[2] << depth)
    if (size[0] + 1) * (size[1] + 1) * (size[2] + 1) >= MAX_LATTICE_POINTS:
        raise PreconditionError("octree", f"the lattice {size} is too fine: lower the level "
                                "or the grid")
    cells = np.array(octree.leaves, dtype=np.int64).reshape(-1, 4)
    levels = cells[:, 0]
    half = np.left_shift(np.int64(1), depth - levels - 1)  # half a leaf edge, >= 1
    low = cells[:, 1:] * (2 * half)[:, None]
    # a key is linear in its point: a leaf's keys are its low corner's plus its half edge
    # times the keys of the code offsets (integers, exact)
    keys = _keys(low, size)[:, None] + half[:, None] * _keys(CODE_OFFSETS2, size)[None, :]
    vertices, codes = _vertex_table(keys, low, half, size)
    present = codes >= 0
    weights = np.left_shift(np.int64(1), np.arange(18, dtype=np.int64))
    patterns = (present[:, 8:] * weights).sum(axis=1)
    templates = (cells[:, 1] + cells[:, 2] + cells[:, 3]) & 1
    for array in (vertices, codes, patterns, templates):
        array.setflags(write=False)
    return OctreeLattice(octree, depth, size, vertices, codes, patterns, templates)
