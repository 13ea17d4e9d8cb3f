"""Polylla: polygonal meshes from terminal-edge regions (exact).

S. Salinas-Fernández, N. Hitschfeld-Kahler, A. Ortiz-Bernardin, H. Si, *POLYLLA:
polygonal meshing algorithm based on terminal-edge regions*, Engineering with Computers 38
(2022), doi:10.1007/s00366-022-01643-4.

Given a triangulation, Polylla merges all triangles whose longest-edge propagation path
(Lepp, :mod:`geomexact.mesh2d.longest_edge`) ends at the same terminal edge into one polygon:

1. **Label phase** (exact): each triangle's longest edge by the edge order of
   :func:`geomexact.mesh2d.longest_edge.edge_order` (exact squared lengths; equal lengths: smaller
   ``(min id, max id)`` pair first).  An edge is *internal* when some triangle's Lepp
   crosses it, *frontier* otherwise (so every boundary edge, constrained segment and edge
   between triangles of different attributes is a frontier edge), and *terminal* when some
   triangle's Lepp ends at it.
2. **Traversal phase**: from one seed per terminal edge (the triangle whose Lepp ends
   there), the region's triangles are collected across internal edges and its boundary is
   walked along frontier edges: one counter-clockwise vertex cycle per region.
3. **Repair phase**: a region whose cycle goes along an edge and straight back (a
   *barrier edge*, both sides in the region) has a *barrier-edge tip*; the middle internal
   edge around the tip becomes a frontier edge, splitting the polygon.  A region whose
   cycle touches itself at a vertex (it wraps around other regions) is cut between the two
   visits.  Repeated until every polygon is simple.

The tie rules are written in ``specs/polylla.md``.  Everything runs on flat lists of
half-edges (``3 t + i`` is edge i of triangle t), O(n) apart from sorting; the label phase
runs on numpy arrays with the certified float filter of the exact length comparison, and
the exact comparison wherever the filter does not decide.

>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> square = mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> polylla(square).polygons
((0, 1, 2, 3),)
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import attrs
import numpy as np

from geomexact.errors import PolyllaError
from geomexact.kernel.array_filters import point_doubles, squared_length_signs
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.longest_edge import edge_order
from geomexact.mesh2d.polygonal.halfedge_table import HalfEdgeTable
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.snapshot import Edge, Mesh2

__all__ = [
    "EdgeLabels",
    "PolyllaRun",
    "label_edges",
    "polylla",
    "polylla_run",
]

_EQUAL = Comparison.EQUAL


# -----------------------------------------------------------------------------------------
# label phase
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class EdgeLabels:
    """The label phase's result, each a sorted tuple of ``(min, max)`` edges.

    ``internal`` and ``frontier`` partition the edges; ``terminal`` lists the edges where
    some Lepp ends: an interior terminal edge (a longest edge of both its triangles) is
    internal, a terminal edge on the boundary, on a constrained segment, or one that is the
    longest edge of one triangle but only tied-longest on the other side (whose own Lepp
    goes on), is a frontier edge."""

    internal: tuple[Edge, ...]
    frontier: tuple[Edge, ...]
    terminal: tuple[Edge, ...]


def _longest_edges(table: HalfEdgeTable, fx: Any, fy: Any, squares: Any) -> Any:
    """For each triangle t, the half-edge ``3 t + i`` of its longest edge in the edge order
    of :func:`geomexact.mesh2d.longest_edge.edge_order` (the float filter certifies a
    strictly longest edge, else ``edge_order`` decides)."""
    rows = np.arange(len(table.triangles))
    first = np.argmax(squares.reshape(-1, 3), axis=1)  # a guess: NaN and ties stay undecided
    longest = 3 * rows + first
    origin, target = table.origin_array, table.target_array
    certain = np.ones(len(rows), dtype=bool)
    for step in (1, 2):
        other = 3 * rows + (first + step) % 3
        certain &= squared_length_signs(fx, fy, origin[longest], target[longest],
                                        origin[other], target[other]) > 0
    points = table.points
    for t in np.flatnonzero(~certain).tolist():
        a, b, c = table.triangles[t]
        longest[t] = 3 * t + edge_order(points[a], points[b], points[c], a, b, c)[0]
    return longest


@np.errstate(over="ignore", invalid="ignore")
def _label(table: HalfEdgeTable, mesh: Mesh2) -> list[int]:
    """Set ``table.frontier``; return the seed half-edges (a terminal edge with its
    region on the left), one per terminal-edge region, in half-edge order."""
    size = len(table)
    if not size:
        return []
    points = table.points
    fx, fy = point_doubles(points)
    origin, target, twin = table.origin_array, table.target_array, table.twin_array
    ex = fx[target] - fx[origin]
    ey = fy[target] - fy[origin]
    longest = _longest_edges(table, fx, fy, ex * ex + ey * ey)
    halfedges = np.arange(size)
    is_longest = longest[halfedges // 3] == halfedges
    # constraint edges: boundary, constrained segment, different triangle attributes
    boundary = twin < 0
    partner = np.where(boundary, halfedges, twin)
    constraint = boundary.copy()
    if len(mesh.segments):
        low, high = np.minimum(origin, target), np.maximum(origin, target)
        packed = low * (len(points) + 1) + high
        segment_keys = np.array([u * (len(points) + 1) + v for u, v in mesh.segments],
                                dtype=np.int64)
        constraint |= np.isin(packed, segment_keys)
    if len(mesh.triangle_attributes):
        get = mesh.triangle_attributes.get
        ids: dict[object, int] = {}
        material = np.array([ids.setdefault(get(t), len(ids)) for t in table.triangles],
                            dtype=np.int64)
        constraint |= material[halfedges // 3] != material[partner // 3]
    on_partner = is_longest[partner] & ~boundary
    # an interior edge the longest of exactly one side: the Lepp crosses it unless it is
    # as long as the longest edge of the other side (then that Lepp ends here, one-sided)
    one_sided = ~constraint & (is_longest != on_partner)
    tied = np.zeros(size, dtype=bool)
    candidates = np.flatnonzero(one_sided & is_longest)  # the side whose Lepp would cross
    if len(candidates):
        other = longest[partner[candidates] // 3]
        unsure = squared_length_signs(fx, fy, origin[candidates], target[candidates],
                                      origin[other], target[other]) == 0
        for index in np.flatnonzero(unsure).tolist():
            h, g = int(candidates[index]), int(other[index])
            if compare_squared_lengths(points[table.origin[h]], points[table.target(h)],
                                       points[table.origin[g]], points[table.target(g)]) == _EQUAL:
                tied[h] = True
    tied_edge = tied | tied[partner]
    frontier = constraint | tied_edge | (~is_longest & ~on_partner)
    table.frontier[:] = frontier.astype(np.uint8).tobytes()
    # seeds: where a Lepp ends, with its region on the left; an interior terminal edge
    # (longest on both sides, same region) once, as the half-edge (min, max)
    ends = is_longest & (constraint | tied | on_partner)
    ends &= ~(on_partner & ~constraint & ~tied_edge & (origin > target))
    result: list[int] = np.flatnonzero(ends).tolist()
    return result


def label_edges(mesh: Mesh2) -> EdgeLabels:
    """The Polylla edge labels of ``mesh`` (exact; see :class:`EdgeLabels`).  O(n)."""
    table = HalfEdgeTable.from_mesh(mesh)
    return _labels_of(table, _label(table, mesh))


def _shorter(table: HalfEdgeTable, h: int, g: int) -> bool:
    """True when edge h is shorter than edge g, or as long with the smaller vertex pair."""
    points, origin = table.points, table.origin
    order = compare_squared_lengths(points[origin[h]], points[table.target(h)],
                                    points[origin[g]], points[table.target(g)])
    if order != _EQUAL:
        return order == Comparison.LESS
    return _undirected(table, h) < _undirected(table, g)


def _undirected(table: HalfEdgeTable, h: int) -> Edge:
    u, v = table.edge(h)
    return (u, v) if u < v else (v, u)


# -----------------------------------------------------------------------------------------
# traversal and repair phases
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class PolyllaRun:
    """A Polylla run: the polygon mesh and what each phase found.

    ``mesh``: the polygons (``sources``: the triangles of each), sorted by vertex tuple;
    ``terminal_edges``: the terminal edge of each terminal-edge region as a ``(u, v)``
    pair with the region on its left, sorted (one per region: an edge that ends Lepps on
    both sides and is frontier — boundary excepted — appears once per side);
    ``frontier_edges``: the number of frontier edges found by the label phase;
    ``barrier_tips``: the barrier-edge tips repaired, in repair order;
    ``repair_edges``: the internal edges made frontier edges by the repair (at barrier-edge
    tips and where a region touches itself at a vertex), sorted ``(min, max)`` pairs."""

    mesh: PolygonMesh
    terminal_edges: tuple[Edge, ...]
    frontier_edges: int
    barrier_tips: tuple[int, ...]
    repair_edges: tuple[Edge, ...]

    @property
    def regions(self) -> int:
        """The number of terminal-edge regions (polygons before the repair)."""
        return len(self.terminal_edges)


def polylla_run(mesh: Mesh2, /, *, repair: bool = True) -> PolyllaRun:
    """Polylla on the triangle mesh ``mesh`` (any valid :class:`Mesh2`: holes, several
    components and constrained segments are fine; isolated vertices are kept as unused
    vertices).  With ``repair=False`` the raw terminal-edge regions are returned, some of
    them possibly not simple (a cycle going along barrier edges and back, or touching
    itself at a vertex).

    Deterministic: results depend only on the mesh's content.  O(n) plus sorting.
    """
    with collector_paused():
        table = HalfEdgeTable.from_mesh(mesh)
        seeds = _label(table, mesh)
        frontier_count = _frontier_count(table)
        regions = _regions(table, seeds)
        groups: list[list[int]] = []
        cycles: list[list[int]] = []
        tips: list[int] = []
        added: list[Edge] = []
        for region in regions:
            for group, cycle in _repaired(table, region, repair, tips, added):
                groups.append(group)
                cycles.append(cycle)
        result = table.sealed(groups, cycles)
    terminal = tuple(sorted(table.edge(h) for h in seeds))
    return PolyllaRun(result, terminal, frontier_count, tuple(tips), tuple(sorted(added)))


def _frontier_count(table: HalfEdgeTable) -> int:
    twin, frontier = table.twin, table.frontier
    return sum(1 for h in range(len(twin)) if frontier[h] and (twin[h] < 0 or h < twin[h]))


def polylla(mesh: Mesh2, /) -> PolygonMesh:
    """The Polylla polygon mesh of ``mesh``: simple counter-clockwise polygons, each the
    union of the triangles listed in its ``sources`` (see :func:`polylla_run`)."""
    return polylla_run(mesh).mesh


def _labels_of(table: HalfEdgeTable, seeds: list[int]) -> EdgeLabels:
    internal: list[Edge] = []
    frontier: list[Edge] = []
    twin, flags = table.twin, table.frontier
    for h in range(len(table)):
        g = twin[h]
        if g < 0 or h < g:
            (frontier if flags[h] else internal).append(_undirected(table, h))
    terminal = sorted({_undirected(table, h) for h in seeds})
    return EdgeLabels(tuple(sorted(internal)), tuple(sorted(frontier)), tuple(terminal))


def _regions(table: HalfEdgeTable, seeds: list[int]) -> list[list[int]]:
    """The terminal-edge region of each seed: its triangles, collected across internal
    edges (each triangle exactly once)."""
    region_of = [-1] * len(table.triangles)
    regions: list[list[int]] = []

    def claim(u: int) -> bool:
        if region_of[u] < 0:
            region_of[u] = len(regions)
            return True
        if region_of[u] != len(regions):
            raise PolyllaError(f"triangle {table.triangles[u]} is reached from two "
                               "terminal edges")
        return False

    for seed in seeds:
        start = seed // 3
        if region_of[start] >= 0:
            raise PolyllaError(f"triangle {table.triangles[start]} is reached from two "
                               "terminal edges")
        region_of[start] = len(regions)
        regions.append(table.flood(start, claim))
    if -1 in region_of:
        t = region_of.index(-1)
        raise PolyllaError(f"triangle {table.triangles[t]} belongs to no terminal-edge region")
    return regions


def _repaired(
    table: HalfEdgeTable, region: list[int], repair: bool, tips: list[int], added: list[Edge]
) -> Iterator[tuple[list[int], list[int]]]:
    """(triangles, boundary cycle) of each simple polygon the region splits into (the
    region itself, unrepaired, when ``repair`` is false)."""
    pending = [region]
    while pending:
        group = pending.pop()
        cycle = table.boundary_cycle(group)
        if not repair:
            yield group, cycle
            continue
        split = _split_barrier_tips(table, cycle, tips, added)
        if not split:
            split = _split_pinch(table, group, cycle, added)
        if split:
            pending.extend(reversed(table.components(group)))
        else:
            yield group, cycle


def _split_barrier_tips(
    table: HalfEdgeTable, cycle: list[int], tips: list[int], added: list[Edge]
) -> bool:
    """Repair every barrier-edge tip of the cycle at once: the cycle arrives at a tip along
    h and leaves along twin(h); the k internal edges around the tip are numbered 1..k
    clockwise from h, and edge ⌈k/2⌉ (for even k the first of the two middle ones, as in
    the reference implementation) becomes a frontier edge.  All tips and their middle
    edges are found before any edge is changed.  Returns whether there was a tip."""
    twin, frontier = table.twin, table.frontier
    middles = []
    for h in cycle:
        if table.next_frontier(h) != twin[h]:
            continue
        fan = table.fan(h)
        if not fan:  # pragma: no cover - a full turn around a vertex has >= 2 triangles
            raise PolyllaError(f"barrier-edge tip {table.target(h)} has no internal edge")
        tips.append(table.target(h))
        middles.append(fan[(len(fan) + 1) // 2 - 1])
    for middle in middles:
        if not frontier[middle]:
            frontier[middle] = frontier[twin[middle]] = 1
            added.append(_undirected(table, middle))
    return bool(middles)


def _split_pinch(
    table: HalfEdgeTable, group: list[int], cycle: list[int], added: list[Edge]
) -> bool:
    """If the cycle visits a vertex twice without a barrier edge (the polygon touches
    itself at a vertex), cut the polygon between the two visits: the triangles around the
    vertex at its first two visits are joined through a unique path of internal edges (the
    region's triangles form a tree); the shortest edge of that path (exact; equal lengths:
    the smaller ``(min id, max id)`` pair) becomes a frontier edge.  The smallest such
    vertex is cut first.  Returns whether it cut."""
    twin, frontier = table.twin, table.frontier
    seen: dict[int, int] = {}
    repeated = None
    for position, h in enumerate(cycle):
        vertex = table.target(h)
        if vertex in seen:
            if repeated is None or vertex < repeated[0]:
                repeated = (vertex, seen[vertex], position)
        else:
            seen[vertex] = position
    if repeated is None:
        return False
    _, first, second = repeated

    def fan_triangles(h: int) -> set[int]:
        return {h // 3} | {twin[g] // 3 for g in table.fan(h)}

    start, goal = fan_triangles(cycle[first]), fan_triangles(cycle[second])
    inside = set(group)
    parent: dict[int, int] = {t: -1 for t in start}
    queue = sorted(start)
    reached = -1
    for t in queue:  # breadth first; the list grows while it is read
        if t in goal:
            reached = t
            break
        for h in (3 * t, 3 * t + 1, 3 * t + 2):
            if not frontier[h]:
                u = twin[h] // 3
                if u in inside and u not in parent:
                    parent[u] = h
                    queue.append(u)
    if reached < 0:  # pragma: no cover - the region is connected
        raise PolyllaError(f"cannot separate the visits of vertex {repeated[0]}")
    path = []
    t = reached
    while parent[t] >= 0:
        h = parent[t]
        path.append(h)
        t = h // 3
    if not path:  # pragma: no cover - the two visits have disjoint fans
        raise PolyllaError(f"the visits of vertex {repeated[0]} share a triangle")
    cut = path[0]
    for h in path[1:]:
        if _shorter(table, h, cut):
            cut = h
    frontier[cut] = frontier[twin[cut]] = 1
    added.append(_undirected(table, cut))
    return True
