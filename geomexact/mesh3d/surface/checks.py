"""Exact checks of a triangulated surface that is to bound a domain: :func:`surface_problems`
lists every problem (degenerate triangles, non-manifold edges and vertices, boundary
edges, inconsistent and inward orientation, self-intersections), :func:`check_surface`
refuses a surface with any, in words for a user, :func:`oriented_outward` turns an
inward closed surface outward, :func:`surfaces_intersect` finds the triangles of two
surfaces that meet.  Spec: ``specs/surfaces.md``.

Every decision is exact: the float filters used to discard candidates (bounding boxes of
the points' nearest doubles, which rounding to nearest keeps ordered, and the certified
orient3d / orient2d array filters of :mod:`geomexact.kernel.array_filters`) only ever
discard what the exact test would discard; the rest is decided in rational arithmetic.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from geomexact.errors import FormatError, Violation
from geomexact.kernel.array_filters import orient2d_signs, orient3d_signs, point_doubles3
from geomexact.kernel.numbers import Rational, format_rational
from geomexact.kernel.points import Point2, Point3, point2
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh3d.surface.value import TriangleSurface

__all__ = [
    "check_surface",
    "oriented_outward",
    "surface_problems",
    "surfaces_intersect",
]

IntArray = npt.NDArray[np.int64]

KINDS = (
    "degenerate-triangle",
    "non-manifold-edge",
    "non-manifold-vertex",
    "boundary-edge",
    "inconsistent-orientation",
    "self-intersection",
    "inward-orientation",
)
"""The kinds of :class:`Violation` :func:`surface_problems` reports, in its order."""

_PAIR_CHUNK = 1 << 22
"""The most candidate pairs the box sweep holds at once (bounded memory)."""


def surface_problems(surface: TriangleSurface) -> list[Violation]:
    """Every problem that keeps ``surface`` from bounding a domain, exactly, in the order
    of :data:`KINDS` (each kind sorted by ids); empty for a closed, 2-manifold, outward,
    consistently oriented surface of non-degenerate, non-intersecting triangles.

    ``elements`` of each :class:`Violation`: a triangle index for
    ``degenerate-triangle``; the edge's vertex ids for ``non-manifold-edge``,
    ``boundary-edge`` (as its triangle orders them) and ``inconsistent-orientation``;
    the vertex id for ``non-manifold-vertex``; the two triangle indices for
    ``self-intersection``; none for ``inward-orientation`` (closed surfaces only:
    ``enclosed_volume() < 0``).  Time O(n log n) plus the exact tests of triangles whose
    bounding boxes overlap."""
    triangles = surface.triangles
    found: list[Violation] = []
    repeated = _repeated_ids(triangles)
    collinear = _collinear(surface, ~repeated)
    for index in np.flatnonzero(repeated | collinear).tolist():
        ids = tuple(triangles[index].tolist())
        why = "a repeated vertex" if repeated[index] else "three collinear points"
        found.append(Violation("degenerate-triangle", f"triangle {index} {ids} has {why}",
                               (index,)))
    topology = _edge_problems(triangles, surface.vertex_count, ~repeated)
    found.extend(topology)
    usable = np.flatnonzero(~(repeated | collinear))
    for first, second in _intersecting_pairs(surface, usable):
        found.append(Violation(
            "self-intersection", f"triangles {first} {tuple(triangles[first].tolist())} and "
            f"{second} {tuple(triangles[second].tolist())} meet outside their shared "
            "vertices and edges", (first, second)))
    if not topology and len(triangles):
        volume = surface.enclosed_volume()
        if volume < 0:
            found.append(Violation("inward-orientation", "the triangles face inward: the "
                                   f"enclosed volume is {format_rational(volume)} < 0"))
    return found


def oriented_outward(surface: TriangleSurface) -> tuple[TriangleSurface, bool]:
    """``(surface, False)``, or ``(surface.reversed(), True)`` when ``surface`` is closed
    and consistently oriented (no boundary, non-manifold or inconsistent edge) and faces
    inward (``enclosed_volume() < 0``).  Any other surface is returned as it is: its
    problems are :func:`surface_problems`'."""
    triangles = surface.triangles
    if not len(triangles):
        return surface, False
    repeated = _repeated_ids(triangles)
    if repeated.any() or _edge_problems(triangles, surface.vertex_count, ~repeated):
        return surface, False
    if surface.enclosed_volume() < 0:
        return surface.reversed(), True
    return surface, False


def surfaces_intersect(a: TriangleSurface, b: TriangleSurface) -> list[tuple[int, int]]:
    """The pairs (triangle of ``a``, triangle of ``b``) that share a point (touching
    counts), sorted; degenerate triangles (reported by :func:`surface_problems`) are
    left out."""
    offset = a.vertex_count
    points = a.points + b.points
    triangles = np.concatenate([a.triangles, b.triangles + offset])
    joined = TriangleSurface(points, triangles)
    repeated = _repeated_ids(triangles)
    usable = np.flatnonzero(~(repeated | _collinear(joined, ~repeated)))
    count = a.triangle_count
    return [(first, second - count)
            for first, second in _intersecting_pairs(joined, usable, split=count)]


def check_surface(surface: TriangleSurface, path: str) -> None:
    """Nothing when ``surface`` bounds a domain (:func:`surface_problems` finds none),
    else a :class:`FormatError` naming ``path`` and, for each kind of problem, how many
    and the first few, in words for a user."""
    problems = surface_problems(surface)
    if not problems:
        return
    by_kind: dict[str, list[Violation]] = {}
    for problem in problems:
        by_kind.setdefault(problem.kind, []).append(problem)
    parts = [_described(kind, found) for kind, found in by_kind.items()]
    raise FormatError(path, None, "; ".join(parts) + " (vertex ids and triangle numbers "
                      "count from 0 in file order)")


_SHOWN = 3


def _described(kind: str, found: list[Violation]) -> str:
    count = len(found)
    more = ", …" if count > _SHOWN else ""
    shown = found[:_SHOWN]
    edges = ", ".join(str(problem.elements) for problem in shown) + more
    if kind == "boundary-edge":
        noun = "boundary edge" if count == 1 else "boundary edges"
        return (f"the surface is not closed: {count} {noun}, e.g. {edges}; a domain needs "
                "a closed surface")
    if kind == "non-manifold-edge":
        return (f"the surface is not 2-manifold: {count} edge(s) in more than two "
                f"triangles, e.g. {edges}")
    if kind == "non-manifold-vertex":
        vertices = ", ".join(str(problem.elements[0]) for problem in shown) + more
        return (f"the surface is not 2-manifold at {count} vertex(es), where the "
                f"triangles around the vertex are not one fan: {vertices}")
    if kind == "inconsistent-orientation":
        return (f"the triangles are not consistently oriented: {count} edge(s) used twice "
                f"in the same direction, e.g. {edges}")
    if kind == "degenerate-triangle":
        described = "; ".join(problem.message for problem in shown) + more
        return f"{count} degenerate triangle(s) (no area): {described}"
    if kind == "self-intersection":
        pairs = ", ".join(f"{first} and {second}" for first, second in
                          (problem.elements for problem in shown)) + more
        return (f"the surface intersects itself: {count} pair(s) of triangles meet "
                f"outside their shared vertices and edges, e.g. triangles {pairs}")
    message = found[0].message
    return f"{message}; reverse every triangle (oriented_outward) to face outward"


# -----------------------------------------------------------------------------------------
# topology
# -----------------------------------------------------------------------------------------
def _repeated_ids(triangles: IntArray) -> npt.NDArray[np.bool_]:
    repeated: npt.NDArray[np.bool_] = (
        (triangles[:, 0] == triangles[:, 1]) | (triangles[:, 1] == triangles[:, 2])
        | (triangles[:, 0] == triangles[:, 2]))
    return repeated


def _collinear(surface: TriangleSurface, candidates: npt.NDArray[np.bool_]
               ) -> npt.NDArray[np.bool_]:
    """Which ``candidates`` triangles have three collinear points: their projections on
    the three coordinate planes all have orientation 0 (the certified filter clears most,
    the exact cross product decides the rest)."""
    triangles = surface.triangles
    result = np.zeros(len(triangles), dtype=bool)
    rows = np.flatnonzero(candidates)
    if not len(rows):
        return result
    doubles = point_doubles3(surface.points)
    a, b, c = (triangles[rows, k] for k in range(3))
    undecided = np.ones(len(rows), dtype=bool)
    for first, second in ((0, 1), (1, 2), (2, 0)):
        undecided &= orient2d_signs(doubles[first], doubles[second], a, b, c) == 0
    for index in rows[undecided].tolist():
        p, q, r = surface.triangle(index)
        result[index] = not any(_cross(p, q, r))
    return result


def _cross(p: Point3, q: Point3, r: Point3) -> tuple[Rational, Rational, Rational]:
    """``(q - p) x (r - p)``, exactly."""
    ux, uy, uz = q.x - p.x, q.y - p.y, q.z - p.z
    vx, vy, vz = r.x - p.x, r.y - p.y, r.z - p.z
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


def _edge_problems(triangles: IntArray, vertex_count: int,
                   included: npt.NDArray[np.bool_]) -> list[Violation]:
    """Non-manifold edges, non-manifold vertices, boundary edges and edges used twice in
    one direction, among the ``included`` triangles."""
    rows = np.flatnonzero(included)
    if not len(rows):
        return []
    chosen = triangles[rows]
    tails = chosen.reshape(-1)
    heads = chosen[:, [1, 2, 0]].reshape(-1)
    low, high = np.minimum(tails, heads), np.maximum(tails, heads)
    keys = low * vertex_count + high
    _, first, inverse, counts = np.unique(keys, return_index=True,
                                               return_inverse=True, return_counts=True)
    inverse = inverse.reshape(-1)
    owner = rows[np.arange(len(tails)) // 3]
    order = np.argsort(inverse, kind="stable")
    starts = np.concatenate([[0], np.cumsum(counts)])
    found: list[Violation] = []
    for edge in np.flatnonzero(counts > 2).tolist():
        uses = order[starts[edge]: starts[edge + 1]]
        ends = (int(low[uses[0]]), int(high[uses[0]]))
        found.append(Violation("non-manifold-edge", f"edge {ends} is in "
                               f"{len(uses)} triangles {owner[uses].tolist()}", ends))
    found.extend(_non_manifold_vertices(chosen, tails, heads, low, first[inverse]))
    for edge in np.flatnonzero(counts == 1).tolist():
        use = first[edge]
        ends = (int(tails[use]), int(heads[use]))
        found.append(Violation("boundary-edge", f"edge {ends} of triangle {owner[use]} "
                               "is in no other triangle", ends))
    twice = np.flatnonzero(counts == 2)
    one, other = order[starts[twice]], order[starts[twice] + 1]
    same = tails[one] == tails[other]
    for use, again in zip(one[same].tolist(), other[same].tolist(), strict=True):
        ends = (int(tails[use]), int(heads[use]))
        found.append(Violation("inconsistent-orientation", f"edge {ends} is used in this "
                               f"direction by triangles {owner[use]} and {owner[again]}",
                               ends))
    return found


def _non_manifold_vertices(chosen: IntArray, tails: IntArray, heads: IntArray,
                           low: IntArray, first_use: IntArray) -> list[Violation]:
    """The vertices whose triangles are more than one fan: the corners of a vertex are
    joined across each edge they share (every use of an edge joined with its first use),
    and a vertex with corners in two groups is non-manifold."""
    corner_count = len(tails)
    position = np.arange(corner_count)
    tail_corner = position
    head_corner = (position // 3) * 3 + (position % 3 + 1) % 3
    low_corner = np.where(tails == low, tail_corner, head_corner)
    high_corner = np.where(tails == low, head_corner, tail_corner)
    left = np.concatenate([low_corner, high_corner])
    right = np.concatenate([low_corner[first_use], high_corner[first_use]])
    labels = _components(corner_count, left, right)
    vertex_of_corner = chosen.reshape(-1)
    groups = np.unique(np.stack([vertex_of_corner, labels], axis=1), axis=0)
    vertices, fans = np.unique(groups[:, 0], return_counts=True)
    return [Violation("non-manifold-vertex", f"the triangles around vertex {vertex} form "
                      f"{count} fans, not one", (vertex,))
            for vertex, count in zip(vertices.tolist(), fans.tolist(), strict=True)
            if count > 1]


def _components(count: int, left: IntArray, right: IntArray) -> IntArray:
    """A label per node of the graph with edges ``left[i] - right[i]``, equal exactly
    within a connected component (minimum-label propagation with pointer jumping)."""
    labels = np.arange(count)
    while True:
        smaller = np.minimum(labels[left], labels[right])
        updated = labels.copy()
        np.minimum.at(updated, left, smaller)
        np.minimum.at(updated, right, smaller)
        updated = updated[updated]
        if np.array_equal(updated, labels):
            return labels
        labels = updated


# -----------------------------------------------------------------------------------------
# intersections
# -----------------------------------------------------------------------------------------
def _intersecting_pairs(surface: TriangleSurface, usable: IntArray,
                        split: int | None = None) -> list[tuple[int, int]]:
    """The pairs (i < j) of ``usable`` triangles that meet outside their shared vertices
    and edges; with ``split``, only pairs with i < split <= j."""
    if len(usable) < 2:
        return []
    triangles = surface.triangles
    doubles = point_doubles3(surface.points)
    low, high = _boxes(doubles, triangles[usable])
    found: list[tuple[int, int]] = []
    for first, second in _overlapping_boxes(low, high):
        i, j = usable[first], usable[second]
        if split is not None:
            keep = (np.minimum(i, j) < split) & (np.maximum(i, j) >= split)
            i, j = i[keep], j[keep]
        i, j = np.minimum(i, j), np.maximum(i, j)
        undecided = _not_separated(doubles, triangles[i], triangles[j])
        for one, two in zip(i[undecided].tolist(), j[undecided].tolist(), strict=True):
            if _meet(surface, one, two):
                found.append((one, two))
    return sorted(found)


def _boxes(doubles: tuple[Any, Any, Any], rows: IntArray) -> tuple[Any, Any]:
    """The bounding boxes (low, high: (n, 3)) of the triangles ``rows`` in the points'
    nearest doubles (rounding to nearest keeps x <= y as fl(x) <= fl(y), so boxes that
    overlap exactly overlap here); a point beyond the doubles' range gives an infinite
    box."""
    low = np.empty((len(rows), 3))
    high = np.empty((len(rows), 3))
    for axis in range(3):
        values = doubles[axis][rows]
        unknown = np.isnan(values)
        low[:, axis] = np.where(unknown, -np.inf, values).min(axis=1)
        high[:, axis] = np.where(unknown, np.inf, values).max(axis=1)
    return low, high


def _overlapping_boxes(low: Any, high: Any) -> Any:
    """The pairs (i, j) of boxes that overlap (closed), in chunks of arrays: sort and
    sweep along the axis of largest extent, then the other two axes."""
    finite_low = np.where(np.isfinite(low), low, 0.0)
    finite_high = np.where(np.isfinite(high), high, 0.0)
    axis = int(np.argmax(finite_high.max(axis=0) - finite_low.min(axis=0)))
    order = np.argsort(low[:, axis], kind="stable")
    starts = low[order, axis]
    ends = np.searchsorted(starts, high[order, axis], side="right")
    position = np.arange(len(order))
    counts = np.maximum(ends - position - 1, 0)
    begin = 0
    while begin < len(order):
        total = np.cumsum(counts[begin:])
        stop = begin + max(1, int(np.searchsorted(total, _PAIR_CHUNK, side="right")))
        chunk = counts[begin:stop]
        size = int(chunk.sum())
        begin_here = begin
        begin = stop
        if not size:
            continue
        first = np.repeat(position[begin_here:stop], chunk)
        offsets = np.arange(size) - np.repeat(np.cumsum(chunk) - chunk, chunk)
        second = first + 1 + offsets
        i, j = order[first], order[second]
        overlap = np.ones(size, dtype=bool)
        for other in range(3):
            if other != axis:
                overlap &= (low[i, other] <= high[j, other]) & (low[j, other] <= high[i, other])
        yield i[overlap], j[overlap]


def _not_separated(doubles: tuple[Any, Any, Any], one: IntArray,
                   two: IntArray) -> npt.NDArray[np.bool_]:
    """False where the certified orient3d filter proves that triangles ``one`` and
    ``two`` (rows of ids) meet at most in their shared vertices: the vertices of one that
    the other does not have lie strictly on one side of the other's plane."""
    shared = one[:, :, None] == two[:, None, :]
    own_one = ~shared.any(axis=2)
    own_two = ~shared.any(axis=1)
    fx, fy, fz = doubles
    distinct = shared.sum(axis=(1, 2)) < 3
    cleared = np.zeros(len(one), dtype=bool)
    for plane, others, own in ((one, two, own_two), (two, one, own_one)):
        signs = np.stack([orient3d_signs(fx, fy, fz, plane[:, 0], plane[:, 1], plane[:, 2],
                                         others[:, k]) for k in range(3)], axis=1)
        positive = np.where(own, signs > 0, True).all(axis=1)
        negative = np.where(own, signs < 0, True).all(axis=1)
        cleared |= positive | negative
    undecided: npt.NDArray[np.bool_] = ~(cleared & distinct)
    return undecided


def _meet(surface: TriangleSurface, one: int, two: int) -> bool:
    """True when the non-degenerate triangles ``one`` and ``two`` share a point outside
    the vertices and edge they share by id, exactly."""
    first = surface.triangles[one].tolist()
    second = surface.triangles[two].tolist()
    shared = [vertex for vertex in first if vertex in second]
    if len(shared) == 3:
        return True
    # put the shared vertices first in both, keeping each triangle's cyclic order
    first = _rotated(first, shared)
    second = _rotated(second, shared)
    p = [surface.points[v] for v in first]
    q = [surface.points[v] for v in second]
    normal = _cross(p[0], p[1], p[2])
    heights = [_dot(normal, _minus(point, p[0])) for point in q]
    if not any(heights):
        return _meet_in_plane(p, q, len(shared), normal)
    if len(shared) == 2:
        return False  # the planes meet in the line of the shared edge only
    if all(h > 0 for h in heights) or all(h < 0 for h in heights):
        return False
    other_normal = _cross(q[0], q[1], q[2])
    other_heights = [_dot(other_normal, _minus(point, q[0])) for point in p]
    if all(h > 0 for h in other_heights) or all(h < 0 for h in other_heights):
        return False
    line = _cross_vectors(normal, other_normal)
    axis = max(range(3), key=lambda k: abs(line[k]))
    low_one, high_one = _span(p, other_heights, axis)
    low_two, high_two = _span(q, heights, axis)
    low, high = max(low_one, low_two), min(high_one, high_two)
    if len(shared) == 1:
        return bool(low < high)  # both contain the shared vertex: more than it?
    return bool(low <= high)


def _rotated(ids: list[int], shared: list[int]) -> list[int]:
    """``ids`` rotated so that the shared ids come first (for two: in a cyclic order
    where they are the first two)."""
    for start in range(3):
        rotated = ids[start:] + ids[:start]
        if all(vertex in shared for vertex in rotated[: len(shared)]):
            return rotated
    return ids


def _minus(p: Point3, q: Point3) -> tuple[Rational, Rational, Rational]:
    return p.x - q.x, p.y - q.y, p.z - q.z


def _dot(u: Sequence[Rational], v: Sequence[Rational]) -> Rational:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _cross_vectors(u: Sequence[Rational], v: Sequence[Rational]
                   ) -> tuple[Rational, Rational, Rational]:
    return u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]


def _span(points: list[Point3], heights: list[Rational], axis: int
          ) -> tuple[Rational, Rational]:
    """The extent, along coordinate ``axis``, of the triangle ``points`` cut by the plane
    where ``heights`` (of its vertices) vanish: the vertices on it and the crossings of
    its edges."""
    values = [point[axis] for point, height in zip(points, heights, strict=True)
              if height == 0]
    for k in range(3):
        a, b = k, (k + 1) % 3
        if heights[a] * heights[b] < 0:
            ha, hb = heights[a], heights[b]
            values.append((hb * points[a][axis] - ha * points[b][axis]) / (hb - ha))
    return min(values), max(values)


def _meet_in_plane(p: list[Point3], q: list[Point3], shared: int,
                   normal: tuple[Rational, Rational, Rational]) -> bool:
    """:func:`_meet` for two triangles in one plane, projected along the normal's
    largest coordinate (an affine bijection of the plane: orientations keep or all
    flip)."""
    drop = max(range(3), key=lambda k: abs(normal[k]))
    keep = [k for k in range(3) if k != drop]
    one = [point2(point[keep[0]], point[keep[1]]) for point in p]
    two = [point2(point[keep[0]], point[keep[1]]) for point in q]
    if shared == 2:
        return int(orient2d(one[0], one[1], one[2])) == int(orient2d(one[0], one[1], two[2]))
    if shared == 1:
        apex = one[0]
        return (any(_in_cone(apex, two[1], two[2], w) for w in one[1:])
                or any(_in_cone(apex, one[1], one[2], w) for w in two[1:]))
    for k in range(3):
        for m in range(3):
            if _segments_meet(one[k], one[(k + 1) % 3], two[m], two[(m + 1) % 3]):
                return True
    return _in_triangle(one, two[0]) or _in_triangle(two, one[0])


def _in_cone(apex: Point2, u: Point2, v: Point2, w: Point2) -> bool:
    """``w`` in the closed cone at ``apex`` spanned by ``u`` and ``v`` (an angle below
    180 degrees)."""
    turn = int(orient2d(apex, u, v))
    return (int(orient2d(apex, u, w)) * turn >= 0
            and int(orient2d(apex, w, v)) * turn >= 0)


def _in_triangle(triangle: list[Point2], point: Point2) -> bool:
    turn = int(orient2d(*triangle))
    return all(int(orient2d(triangle[k], triangle[(k + 1) % 3], point)) * turn >= 0
               for k in range(3))


def _segments_meet(a: Point2, b: Point2, c: Point2, d: Point2) -> bool:
    """The closed segments ab and cd share a point."""
    o1, o2 = int(orient2d(a, b, c)), int(orient2d(a, b, d))
    o3, o4 = int(orient2d(c, d, a)), int(orient2d(c, d, b))
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return ((o1 == 0 and _on_segment(a, b, c)) or (o2 == 0 and _on_segment(a, b, d))
            or (o3 == 0 and _on_segment(c, d, a)) or (o4 == 0 and _on_segment(c, d, b)))


def _on_segment(a: Point2, b: Point2, p: Point2) -> bool:
    """``p``, collinear with ``a`` and ``b``, lies on the closed segment ab."""
    return bool(min(a.x, b.x) <= p.x <= max(a.x, b.x)
                and min(a.y, b.y) <= p.y <= max(a.y, b.y))
