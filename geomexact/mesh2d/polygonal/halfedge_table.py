"""Triangles as flat half-edge arrays (numpy), the structure Polylla and the convex
decomposition walk: twins, frontier flags, and the polygons traced along frontier
half-edges."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from geomexact.errors import PolyllaError
from geomexact.kernel.points import Point2
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.snapshot import Edge, Mesh2, Triangle


class HalfEdgeTable:
    """Counter-clockwise triangles as flat half-edge lists, with a frontier flag per
    half-edge.  Half-edge ``h = 3 t + i`` goes from ``origin[h]`` (vertex i of triangle t)
    to the next vertex of t; ``twin[h]`` is the reverse half-edge, -1 on the boundary.

    Owned by the function that builds it (mutable, like a transient); shared by
    :mod:`geomexact.mesh2d.polygonal.polylla_meshing` and :mod:`geomexact.mesh2d.polygonal.convex`.
    """

    __slots__ = ("frontier", "key_order", "origin", "origin_array", "points", "sorted_keys",
                 "target_array", "triangles", "twin", "twin_array")

    def __init__(self, points: Sequence[Point2], triangles: Sequence[Triangle]) -> None:
        self.points = list(points)
        self.triangles = list(triangles)
        corners = np.array(self.triangles, dtype=np.int64).reshape(-1, 3)
        origin = corners.reshape(-1)
        target = corners[:, [1, 2, 0]].reshape(-1)
        size = len(self.points) + 1
        if size * size >= 2**62:  # pragma: no cover - beyond memory long before
            raise PolyllaError(f"{size - 1} vertices are too many for packed edge keys")
        keys = origin * size + target  # the half-edge (u, v) as one integer
        order = np.argsort(keys, kind="stable")
        ordered = keys[order]
        if len(ordered) > 1 and bool((ordered[1:] == ordered[:-1]).any()):
            raise PolyllaError("two triangles share a directed edge: the triangles overlap")
        reverse = target * size + origin
        found = np.searchsorted(ordered, reverse)
        found[found == len(ordered)] = 0
        twin = np.where(ordered[found] == reverse, order[found], -1) if len(ordered) else found
        self.origin_array = origin
        self.target_array = target
        self.twin_array = twin
        self.sorted_keys = ordered
        self.key_order = order
        self.origin: list[int] = origin.tolist()
        self.twin: list[int] = twin.tolist()
        self.frontier = bytearray(len(self.origin))

    def find(self, origins: Any, targets: Any) -> Any:
        """The half-edges (origin, target) for arrays of origins and targets; -1 where
        there is none."""
        size = len(self.points) + 1
        keys = np.asarray(origins, dtype=np.int64) * size + np.asarray(targets, dtype=np.int64)
        ordered = self.sorted_keys
        if not len(ordered):
            return np.full(len(keys), -1, dtype=np.int64)
        found = np.searchsorted(ordered, keys)
        found[found == len(ordered)] = 0
        return np.where(ordered[found] == keys, self.key_order[found], -1)

    @classmethod
    def from_mesh(cls, mesh: Mesh2) -> HalfEdgeTable:
        """The table of ``mesh``'s triangles in sorted canonical order."""
        vertices = mesh.vertices
        return cls([vertices[i] for i in range(len(vertices))], mesh.triangles())

    def __len__(self) -> int:
        return len(self.origin)

    def target(self, h: int) -> int:
        """The vertex half-edge ``h`` points to."""
        return self.origin[h + 1 if h % 3 != 2 else h - 2]

    def edge(self, h: int) -> Edge:
        """Half-edge ``h`` as the pair (origin, target)."""
        return self.origin[h], self.target(h)

    def next_frontier(self, h: int) -> int:
        """The frontier half-edge that follows frontier half-edge ``h`` on the boundary of
        its polygon (turning clockwise around the target of ``h`` across internal
        edges)."""
        frontier, twin = self.frontier, self.twin
        g = h + 1 if h % 3 != 2 else h - 2
        while not frontier[g]:
            g = twin[g]
            g = g + 1 if g % 3 != 2 else g - 2
        return g

    def fan(self, h: int) -> list[int]:
        """The internal half-edges leaving the target of frontier half-edge ``h``, in
        clockwise order, up to the next frontier half-edge."""
        frontier, twin = self.frontier, self.twin
        found = []
        g = h + 1 if h % 3 != 2 else h - 2
        while not frontier[g]:
            found.append(g)
            g = twin[g]
            g = g + 1 if g % 3 != 2 else g - 2
        return found

    def flood(self, start: int, claim: Callable[[int], bool]) -> list[int]:
        """The triangles reached from triangle ``start`` across internal (non-frontier)
        edges, sorted.  ``claim(u)`` is called for each neighbour u reached and says
        whether u joins now (it marks u taken, so it answers False the next time; it may
        raise for a neighbour that belongs elsewhere).  ``start`` is already claimed."""
        frontier, twin = self.frontier, self.twin
        group = [start]
        stack = [start]
        while stack:
            t = stack.pop()
            for h in (3 * t, 3 * t + 1, 3 * t + 2):
                if not frontier[h]:
                    u = twin[h] // 3
                    if claim(u):
                        group.append(u)
                        stack.append(u)
        group.sort()
        return group

    def components(self, triangles: Sequence[int]) -> list[list[int]]:
        """The given triangles (ids) grouped into classes connected across internal
        (non-frontier) edges, each sorted; classes ordered by their smallest triangle."""
        wanted = set(triangles)

        def claim(u: int) -> bool:
            if u in wanted:
                wanted.discard(u)
                return True
            return False

        result = []
        for start in sorted(wanted):
            if start in wanted:
                wanted.discard(start)
                result.append(self.flood(start, claim))
        return result

    def boundary_cycle(self, triangles: Sequence[int]) -> list[int]:
        """The frontier half-edges of a class of triangles connected across internal edges,
        in boundary order starting from the smallest; :class:`PolyllaError` when they do
        not form one closed walk (the class would not be a disk)."""
        frontier = self.frontier
        count = 0
        first = -1
        for t in triangles:
            for h in (3 * t, 3 * t + 1, 3 * t + 2):
                if frontier[h]:
                    count += 1
                    if first < 0 or h < first:
                        first = h
        if first < 0:
            raise PolyllaError(f"triangles {self.triangles[triangles[0]]}… have no frontier "
                               "edge around them")
        twin = self.twin
        cycle = [first]
        h = first
        while True:  # next_frontier, inlined
            h = h + 1 if h % 3 != 2 else h - 2
            while not frontier[h]:
                h = twin[h]
                h = h + 1 if h % 3 != 2 else h - 2
            if h == first or len(cycle) > count:
                break
            cycle.append(h)
        if len(cycle) != count:
            raise PolyllaError(
                f"the boundary of the polygon with triangle {self.triangles[first // 3]} is "
                f"not one closed walk ({len(cycle)} of {count} frontier half-edges)"
            )
        return cycle

    def all_polygons(self) -> tuple[list[list[int]], list[list[int]]]:
        """(triangles, boundary cycle) of every class of triangles connected across
        internal edges, classes ordered by their smallest triangle; :class:`PolyllaError`
        when a class's frontier half-edges do not form exactly one closed walk.  O(n)."""
        frontier, twin = self.frontier, self.twin
        count = len(self.triangles)
        label = [-1] * count
        groups: list[list[int]] = []

        def claim(u: int) -> bool:
            if label[u] < 0:
                label[u] = len(groups)
                return True
            return False

        for start in range(count):
            if label[start] < 0:
                label[start] = len(groups)
                groups.append(self.flood(start, claim))
        cycles: list[list[int] | None] = [None] * len(groups)
        seen = bytearray(len(frontier))
        for first in range(len(frontier)):
            if not frontier[first] or seen[first]:
                continue
            cycle = [first]
            seen[first] = 1
            h = first
            while True:  # next_frontier, inlined
                h = h + 1 if h % 3 != 2 else h - 2
                while not frontier[h]:
                    h = twin[h]
                    h = h + 1 if h % 3 != 2 else h - 2
                if seen[h]:
                    break
                seen[h] = 1
                cycle.append(h)
            number = label[first // 3]
            if h != first or cycles[number] is not None:
                raise PolyllaError(f"the boundary of the polygon with triangle "
                                   f"{self.triangles[first // 3]} is not one closed walk")
            cycles[number] = cycle
        done = [cycle for cycle in cycles if cycle is not None]
        if len(done) != len(groups):
            raise PolyllaError("a class of triangles has no frontier edge around it")
        return groups, done

    def polygon(self, cycle: Sequence[int]) -> tuple[int, ...]:
        """The vertex cycle of a boundary cycle, rotated to start at its smallest vertex."""
        origin = self.origin
        vertices = [origin[h] for h in cycle]
        start = vertices.index(min(vertices))
        return tuple(vertices[start:] + vertices[:start])

    def sealed(
        self, groups: Sequence[Sequence[int]], cycles: Sequence[Sequence[int]]
    ) -> PolygonMesh:
        """A polygon mesh of the given triangle classes and their boundary cycles, polygons
        sorted by their vertex tuples."""
        triangles = self.triangles
        rows = sorted(
            (self.polygon(cycle), tuple(triangles[t] for t in group))
            for group, cycle in zip(groups, cycles, strict=True)
        )
        return PolygonMesh(
            vertices=self.points,
            polygons=[row[0] for row in rows],
            sources=[row[1] for row in rows],
        )
