"""The one mesh checker: :func:`validate` returns every violated invariant of a snapshot,
:func:`check` raises :class:`InvalidMeshError` carrying them.  Used by the tests, the ops'
property tests and ``geomexact check``.  Invariants: ``specs/snapshot.md``.
"""

from __future__ import annotations

import itertools
from collections import Counter

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.segments import meeting_pairs
from geomexact.mesh2d.snapshot import Mesh2, canonical_triangle, full_digest


def validate(
    mesh: Mesh2, *, check_digest: bool = True, allow_isolated: bool = True
) -> list[Violation]:
    """Every violation of the snapshot invariants, in a deterministic order (empty when
    the mesh is valid).  O(n) (plus the O(n) digest recomputation when ``check_digest``).

    Checked: vertices referenced exist; each triangle's three half-edges agree; every
    triangle is strictly counter-clockwise (exact); the triangle count; each vertex of a
    triangle has a valid ``outgoing`` hint; boundary edges form closed loops through
    manifold vertices; every constrained segment is an edge; attributes and markers refer
    to existing elements; the triangles around each vertex turn exactly once (interior
    vertex) or less than once (boundary vertex) — no fold-over; boundary edges meet only
    at shared endpoints and no connected component lies on another (no overlap); the
    digest equals its recomputation.  Vertices in no triangle
    (Triangle keeps unused duplicates and vertices inside holes) are reported as
    ``isolated-vertex`` only when ``allow_isolated`` is false.
    """
    found: list[Violation] = []
    vertices, halfedges = mesh.vertices, mesh.halfedges
    n = len(vertices)
    if sorted(vertices) != list(range(n)):
        found.append(Violation("vertex-ids", "vertex ids are not 0..n-1"))
    triangles = []
    for key in sorted(halfedges):
        u, v = key
        w = halfedges[key]
        if not (u in vertices and v in vertices and w in vertices):
            found.append(
                Violation("missing-vertex", f"half-edge ({u}, {v}) -> {w} refers to a missing "
                          "vertex", (u, v, w))
            )
            continue
        if halfedges.get((v, w)) != u or halfedges.get((w, u)) != v:
            found.append(
                Violation("adjacency", f"half-edges of triangle ({u}, {v}, {w}) disagree",
                          (u, v, w))
            )
            continue
        if u < v and u < w:
            triangles.append((u, v, w))
    for a, b, c in triangles:
        orientation = orient2d(vertices[a], vertices[b], vertices[c])
        if orientation != Orientation.COUNTERCLOCKWISE:
            what = "degenerate" if orientation == Orientation.COLLINEAR else "clockwise"
            found.append(Violation("orientation", f"triangle ({a}, {b}, {c}) is {what}",
                                   (a, b, c)))
    if len(triangles) != mesh.triangle_count:
        found.append(Violation("triangle-count", f"triangle_count is {mesh.triangle_count} "
                               f"but there are {len(triangles)} triangles"))
    used = {vertex for triangle in triangles for vertex in triangle}
    for vertex in sorted(used):
        hint = mesh.outgoing.get(vertex)
        if hint is None or (vertex, hint) not in halfedges:
            found.append(Violation("outgoing", f"vertex {vertex} has no valid outgoing "
                                   "half-edge hint", (vertex,)))
    if triangles and not allow_isolated:
        for vertex in sorted(set(vertices) - used):
            found.append(Violation("isolated-vertex", f"vertex {vertex} is in no triangle",
                                   (vertex,)))
    out_degree: Counter[int] = Counter()
    in_degree: Counter[int] = Counter()
    for key in halfedges:
        u, v = key
        if (v, u) not in halfedges:
            out_degree[u] += 1
            in_degree[v] += 1
    for vertex in sorted(set(out_degree) | set(in_degree)):
        if out_degree[vertex] != in_degree[vertex]:
            found.append(Violation("boundary-loop", f"boundary edges do not form closed loops "
                                   f"at vertex {vertex}", (vertex,)))
        elif out_degree[vertex] > 1:
            found.append(Violation("non-manifold-vertex", f"vertex {vertex} is on "
                                   f"{out_degree[vertex]} boundary loops", (vertex,)))
    for key in sorted(mesh.segments):
        u, v = key
        if not mesh.is_edge(u, v):
            found.append(Violation("segment", f"constrained segment ({u}, {v}) is not an edge",
                                   (u, v)))
    for triangle in sorted(mesh.triangle_attributes):
        if not mesh.has_triangle(triangle):
            found.append(Violation("attribute", f"attributes of missing triangle {triangle}",
                                   triangle))
    for table in (mesh.vertex_markers, mesh.vertex_attributes):
        for vertex in sorted(table):
            if vertex not in vertices:
                found.append(Violation("attribute", f"marker or attributes of missing "
                                       f"vertex {vertex}", (vertex,)))
    if not found:
        found.extend(_folded_vertices(mesh))
        found.extend(_boundary_crossings(mesh))
        if not found:
            found.extend(_stacked_components(mesh, triangles))
    if check_digest:
        recomputed = full_digest(mesh)
        if recomputed != mesh.digest:
            found.append(Violation("digest", f"digest {mesh.digest:032x} differs from its "
                                   f"recomputation {recomputed:032x}"))
    return found


def check(mesh: Mesh2) -> Mesh2:
    """Return ``mesh`` if it is valid, else raise :class:`InvalidMeshError` listing every
    violation."""
    violations = validate(mesh)
    if violations:
        raise InvalidMeshError(violations)
    return mesh


def _quadrant(dx: object, dy: object) -> int:
    """Quadrant of a non-zero direction: 0 for angles in [0°, 90°), 1 for [90°, 180°),
    2 for [180°, 270°), 3 for [270°, 360°)."""
    if dy >= 0 and dx > 0:  # type: ignore[operator]
        return 0
    if dx <= 0 and dy > 0:  # type: ignore[operator]
        return 1
    if dy <= 0 and dx < 0:  # type: ignore[operator]
        return 2
    return 3


def _folded_vertices(mesh: Mesh2) -> list[Violation]:
    """Vertices whose triangles turn around them more than once (interior: exactly once
    required; boundary: less than once).  Exact: each triangle's angle at the vertex is
    below 180° (orientation is already checked), so summing quadrant changes along the star
    counts quarter turns; an interior star must make exactly 4.  O(n)."""
    found: list[Violation] = []
    vertices = mesh.vertices
    for vertex in sorted(mesh.outgoing):
        star = mesh.star(vertex)
        if not star:
            continue
        p = vertices[vertex]
        directions = [(vertices[w].x - p.x, vertices[w].y - p.y) for _, w, _ in star]
        last = vertices[star[-1][2]]
        directions.append((last.x - p.x, last.y - p.y))
        quadrants = [_quadrant(dx, dy) for dx, dy in directions]
        turns = sum((b - a) % 4 for a, b in itertools.pairwise(quadrants))
        closed = star[-1][2] == star[0][1]
        if closed:
            wraps = turns != 4
        else:
            (fx, fy), (lx, ly) = directions[0], directions[-1]
            wraps = turns > 4 or (turns == 4 and fx * ly - fy * lx >= 0)
        if wraps:
            found.append(Violation("fold-over", f"the triangles around vertex {vertex} wrap "
                                   "around it more than once", (vertex,)))
    return found


def _boundary_crossings(mesh: Mesh2) -> list[Violation]:
    """Pairs of boundary edges that meet anywhere but at a shared endpoint."""
    return [
        Violation("overlap", f"boundary edges {first} and {second} intersect", (*first, *second))
        for first, second in meeting_pairs(mesh.vertices, mesh.boundary_edges())
    ]


def _stacked_components(mesh: Mesh2, triangles: list[tuple[int, int, int]]) -> list[Violation]:
    """Connected components lying inside one another (their boundaries do not cross, so
    one vertex of each component decides).  O(n · components); skipped for one component.
    """
    component: dict[tuple[int, int, int], int] = {}
    count = 0
    halfedges = mesh.halfedges
    for triangle in triangles:
        if triangle in component:
            continue
        stack = [triangle]
        component[triangle] = count
        while stack:
            a, b, c = stack.pop()
            for u, v in ((a, b), (b, c), (c, a)):
                w = halfedges.get((v, u))
                if w is not None:
                    neighbour = canonical_triangle(v, u, w)
                    if neighbour not in component:
                        component[neighbour] = count
                        stack.append(neighbour)
        count += 1
    if count < 2:
        return []
    first_vertex: dict[int, int] = {}
    for triangle in triangles:
        index = component[triangle]
        first_vertex[index] = min(first_vertex.get(index, triangle[0]), *triangle)
    found: list[Violation] = []
    vertices = mesh.vertices
    for index, vertex in sorted(first_vertex.items()):
        p = vertices[vertex]
        for a, b, c in triangles:
            if component[(a, b, c)] == index or vertex in (a, b, c):
                continue
            pa, pb, pc = vertices[a], vertices[b], vertices[c]
            if (orient2d(pa, pb, p) != Orientation.CLOCKWISE
                    and orient2d(pb, pc, p) != Orientation.CLOCKWISE
                    and orient2d(pc, pa, p) != Orientation.CLOCKWISE):
                found.append(Violation(
                    "overlap", f"vertex {vertex} of one connected component lies in triangle "
                    f"({a}, {b}, {c}) of another", (vertex, a, b, c)))
                break
    return found
