"""The one mesh checker: :func:`validate` returns every violated invariant of a snapshot,
:func:`check` raises :class:`InvalidMeshError` carrying them.  Used by the tests, the ops'
property tests and ``geomexact check``.  Invariants: ``specs/snapshot.md``.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter
from typing import TYPE_CHECKING, Any

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.kernel.vectorising import worth_vectorising
from geomexact.mesh2d.segments import meeting_pairs, segments_meet_improperly
from geomexact.mesh2d.snapshot import Edge, Mesh2, canonical_triangle, full_digest

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from geomexact.mesh2d.mesh_arrays import MeshArrays

    IntArray = npt.NDArray[np.signedinteger[Any]]
    FloatArray = npt.NDArray[np.float64]
    BoolArray = npt.NDArray[np.bool_]


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
    if worth_vectorising(mesh.triangle_count, _VECTORISED_FROM):
        from geomexact.mesh2d.mesh_arrays import mesh_arrays

        arrays = mesh_arrays(mesh)
        if arrays is not None:
            return _validate_arrays(mesh, arrays, check_digest=check_digest,
                                    allow_isolated=allow_isolated)
    return scalar_validate(mesh, check_digest=check_digest, allow_isolated=allow_isolated)


def scalar_validate(
    mesh: Mesh2, *, check_digest: bool = True, allow_isolated: bool = True
) -> list[Violation]:
    """:func:`validate` element by element (the definition; :func:`validate` runs it on
    small meshes and on inconsistent tables, and checks the others on arrays with the same
    answers)."""
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
    found.extend(_table_violations(mesh))
    if not found:
        found.extend(_folded_vertices(mesh))
        found.extend(_boundary_crossings(mesh))
        if not found:
            found.extend(_stacked_components(mesh, triangles))
    if check_digest:
        found.extend(_digest_violations(mesh))
    return found


def _table_violations(mesh: Mesh2) -> list[Violation]:
    """Constrained segments that are not edges; markers and attributes of missing
    elements."""
    found: list[Violation] = []
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
            if vertex not in mesh.vertices:
                found.append(Violation("attribute", f"marker or attributes of missing "
                                       f"vertex {vertex}", (vertex,)))
    return found


def _digest_violations(mesh: Mesh2) -> list[Violation]:
    recomputed = full_digest(mesh)
    if recomputed != mesh.digest:
        return [Violation("digest", f"digest {mesh.digest:032x} differs from its "
                          f"recomputation {recomputed:032x}")]
    return []


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
    return [_fold_over(vertex) for vertex in sorted(mesh.outgoing) if _wraps(mesh, vertex)]


def _fold_over(vertex: int) -> Violation:
    return Violation("fold-over", f"the triangles around vertex {vertex} wrap around it "
                     "more than once", (vertex,))


def _wraps(mesh: Mesh2, vertex: int) -> bool:
    """Whether the triangles of the star of ``vertex`` (the fan its ``outgoing`` hint
    reaches) turn around it more than once (see :func:`_folded_vertices`)."""
    star = mesh.star(vertex)
    if not star:
        return False
    vertices = mesh.vertices
    p = vertices[vertex]
    directions = [(vertices[w].x - p.x, vertices[w].y - p.y) for _, w, _ in star]
    last = vertices[star[-1][2]]
    directions.append((last.x - p.x, last.y - p.y))
    quadrants = [_quadrant(dx, dy) for dx, dy in directions]
    turns = sum((b - a) % 4 for a, b in itertools.pairwise(quadrants))
    closed = star[-1][2] == star[0][1]
    if closed:
        return turns != 4
    (fx, fy), (lx, ly) = directions[0], directions[-1]
    return bool(turns > 4 or (turns == 4 and fx * ly - fy * lx >= 0))


def _boundary_crossings(mesh: Mesh2, boundary: list[Edge] | None = None) -> list[Violation]:
    """Pairs of boundary edges (``boundary``: :meth:`Mesh2.boundary_edges`) that meet
    anywhere but at a shared endpoint."""
    edges = mesh.boundary_edges() if boundary is None else boundary
    return [
        Violation("overlap", f"boundary edges {first} and {second} intersect", (*first, *second))
        for first, second in meeting_pairs(mesh.vertices, edges)
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


# -- the vectorised checker ---------------------------------------------------------------
_VECTORISED_FROM = 256
"""Meshes of this many triangles or more are checked on arrays (same answers)."""


def _validate_arrays(mesh: Mesh2, arrays: MeshArrays, *, check_digest: bool,
                     allow_isolated: bool) -> list[Violation]:
    """:func:`validate` of a mesh whose tables :func:`~geomexact.mesh2d.mesh_arrays.
    mesh_arrays` found consistent (vertex ids 0..n-1, every half-edge's vertices exist,
    the three half-edges of each triangle agree, the triangle count): the remaining checks
    on arrays, in the same order and with the same answers."""
    import numpy as np

    from geomexact.kernel.array_filters import orient2d_signs

    found: list[Violation] = []
    points = arrays.points
    n = len(points)
    tri = arrays.triangles
    tri = tri[np.lexsort((tri[:, 2], tri[:, 1], tri[:, 0]))]
    signs = orient2d_signs(arrays.fx, arrays.fy, tri[:, 0], tri[:, 1], tri[:, 2])
    for i in np.flatnonzero(signs <= 0).tolist():
        a, b, c = tri[i].tolist()
        orientation = (orient2d(points[a], points[b], points[c]) if signs[i] == 0
                       else Orientation.CLOCKWISE)
        if orientation != Orientation.COUNTERCLOCKWISE:
            what = "degenerate" if orientation == Orientation.COLLINEAR else "clockwise"
            found.append(Violation("orientation", f"triangle ({a}, {b}, {c}) is {what}",
                                   (a, b, c)))
    used = np.unique(tri)
    outgoing, halfedges = mesh.outgoing, mesh.halfedges
    for vertex in used.tolist():
        hint = outgoing.get(vertex)
        if hint is None or (vertex, hint) not in halfedges:
            found.append(Violation("outgoing", f"vertex {vertex} has no valid outgoing "
                                   "half-edge hint", (vertex,)))
    if len(tri) and not allow_isolated:
        for vertex in np.setdiff1d(np.arange(n), used).tolist():
            found.append(Violation("isolated-vertex", f"vertex {vertex} is in no triangle",
                                   (vertex,)))
    boundary = np.flatnonzero(arrays.twin < 0)
    out_degree = np.bincount(arrays.hu[boundary], minlength=n)
    in_degree = np.bincount(arrays.hv[boundary], minlength=n)
    for vertex in np.flatnonzero((out_degree != in_degree) | (out_degree > 1)).tolist():
        if out_degree[vertex] != in_degree[vertex]:
            found.append(Violation("boundary-loop", f"boundary edges do not form closed loops "
                                   f"at vertex {vertex}", (vertex,)))
        else:
            found.append(Violation("non-manifold-vertex", f"vertex {vertex} is on "
                                   f"{out_degree[vertex]} boundary loops", (vertex,)))
    found.extend(_table_violations(mesh))
    if not found:
        found.extend(_fold_over(v) for v in _folded_vertex_ids(mesh, arrays, used, out_degree))
        bu, bv = arrays.hu[boundary], arrays.hv[boundary]
        ordered = np.lexsort((bv, bu))
        edges = list(zip(bu[ordered].tolist(), bv[ordered].tolist(), strict=True))
        found.extend(
            Violation("overlap", f"boundary edges {first} and {second} intersect",
                      (*first, *second))
            for first, second in _meeting_pairs(points, edges))
        if not found and _component_count(arrays) > 1:
            found.extend(_stacked_components(mesh, [tuple(t) for t in tri.tolist()]))
    if check_digest:
        found.extend(_digest_violations(mesh))
    return found


def _difference_signs(values: FloatArray, exact: BoolArray, first: IntArray,
                      second: IntArray) -> tuple[IntArray, BoolArray]:
    """The sign of ``value[second] - value[first]`` (exact coordinates) where the doubles
    decide it, and where they do not.  Rounding to nearest is monotone, so different
    doubles order their rationals; equal doubles that are the exact values are equal."""
    import numpy as np

    a, b = values[first], values[second]
    with np.errstate(invalid="ignore"):
        sign = (b > a).astype(np.int64) - (b < a).astype(np.int64)
        decided = (sign != 0) | ((a == b) & exact[first] & exact[second])
    return sign, ~decided


def _quadrants(sx: IntArray, sy: IntArray) -> IntArray:
    """:func:`_quadrant` of directions given by the signs of their components."""
    import numpy as np

    quadrant = np.full(len(sx), 3, dtype=np.int64)
    quadrant[(sy <= 0) & (sx < 0)] = 2
    quadrant[(sx <= 0) & (sy > 0)] = 1
    quadrant[(sy >= 0) & (sx > 0)] = 0
    return quadrant


def _folded_vertex_ids(mesh: Mesh2, arrays: MeshArrays, used: IntArray,
                       boundary_out: IntArray) -> list[int]:
    """The vertices :func:`_folded_vertices` reports, sorted.  Each corner (p, w, x) of a
    triangle adds its quarter turns (quadrant of x - p minus quadrant of w - p, mod 4) to
    p; a vertex whose corners form one fan (one cycle, or one chain from its boundary
    half-edge: pointer jumping) with all quadrants decided by the doubles is judged here,
    any other (several fans, an undecided sign, an open fan of exactly four quarter turns)
    by :func:`_wraps` itself.  Called only when every vertex is on at most one boundary
    loop."""
    import numpy as np

    n = len(arrays.points)
    hu, hv, hw = arrays.hu, arrays.hv, arrays.hw
    if not len(hu):
        return []
    exact = arrays.exact
    first_x, unsure_a = _difference_signs(arrays.fx, exact, hu, hv)
    first_y, unsure_b = _difference_signs(arrays.fy, exact, hu, hv)
    second_x, unsure_c = _difference_signs(arrays.fx, exact, hu, hw)
    second_y, unsure_d = _difference_signs(arrays.fy, exact, hu, hw)
    unsure = unsure_a | unsure_b | unsure_c | unsure_d
    turn = (_quadrants(second_x, second_y) - _quadrants(first_x, first_y)) % 4
    turns = np.bincount(hu, weights=turn, minlength=n).astype(np.int64)
    corners = np.bincount(hu, minlength=n)
    doubtful = np.bincount(hu, weights=unsure, minlength=n) > 0
    # the next corner around p: (p, x, y), the half-edge (p, x), across (x, p)
    following = arrays.following
    after = arrays.twin[following[following]]
    count = len(hu)
    pointer = np.where(after >= 0, after, np.arange(count))
    label = np.arange(count)
    steps = (after >= 0).astype(np.int64)
    for _ in range(int(corners.max()).bit_length() + 1):
        label = np.minimum(label, label[pointer])
        steps = steps + steps[pointer]
        pointer = pointer[pointer]
    by_vertex = np.argsort(hu, kind="stable")
    starts = np.searchsorted(hu[by_vertex], used)
    lowest = np.minimum.reduceat(label[by_vertex], starts)
    highest = np.maximum.reduceat(label[by_vertex], starts)
    closed = boundary_out[used] == 0
    one_fan = np.where(closed, lowest == highest, False)
    gap = np.flatnonzero(arrays.twin < 0)  # each open vertex: its boundary half-edge
    chain = np.zeros(n, dtype=np.int64)
    chain[hu[gap]] = steps[gap] + 1
    one_fan |= ~closed & (chain[used] == corners[used])
    t = turns[used]
    wraps = np.where(closed, t != 4, t > 4)
    by_python = doubtful[used] | ~one_fan | (~closed & (t == 4))
    result = used[wraps & ~by_python].tolist()
    result += [vertex for vertex in used[by_python].tolist() if _wraps(mesh, vertex)]
    return sorted(result)


def _component_count(arrays: MeshArrays) -> int:
    """The number of edge-connected components of the triangles (union by minimum label
    with path halving, on arrays)."""
    import numpy as np

    from geomexact.kernel.components import component_labels

    hu, hv, hw = arrays.hu, arrays.hv, arrays.hw
    if not len(hu):
        return 0
    first = (hu < hv) & (hu < hw)
    index = np.cumsum(first) - 1
    following = arrays.following
    once, twice = following, following[following]
    triangle = np.where(first, index, np.where(first[once], index[once], index[twice]))
    twin = arrays.twin
    pairs = np.flatnonzero(twin > np.arange(len(twin)))
    a, b = triangle[pairs], triangle[twin[pairs]]
    parent = component_labels(int(first.sum()), a, b)
    return int(np.count_nonzero(parent == np.arange(len(parent))))


def _meeting_pairs(points: list[Point2], segments: list[Edge]) -> list[tuple[Edge, Edge]]:
    """:func:`~geomexact.mesh2d.segments.meeting_pairs` (the same pairs in the same order),
    skipping the pairs whose y-ranges the doubles prove disjoint (rounding is monotone, so
    doubles strictly apart order their rationals): segments on one vertical line are all
    active at once in the sweep over x."""
    ordered = sorted(
        (min(points[u].x, points[v].x), max(points[u].x, points[v].x), u, v) for u, v in segments
    )
    found: list[tuple[Edge, Edge]] = []
    active: list[tuple[object, float, float, int, int]] = []
    for low, high, u, v in ordered:
        active = [entry for entry in active if entry[0] >= low]  # type: ignore[operator]
        fu, fv = points[u].fy, points[v].fy
        if math.isnan(fu) or math.isnan(fv):  # beyond the doubles: no float range
            bottom, top = -math.inf, math.inf
        else:
            bottom, top = min(fu, fv), max(fu, fv)
        for _, lowest, highest, a, b in active:
            if highest < bottom or top < lowest:
                continue
            if segments_meet_improperly(points, (a, b), (u, v)):
                found.append(((a, b), (u, v)))
        active.append((high, bottom, top, u, v))
    return found
