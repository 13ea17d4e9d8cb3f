"""Longest-edge propagation paths (Lepp, Rivara 1997), exact.

Definitions (``specs/lepp.md``):

* **Edge order** of a triangle: its three edges sorted by exact squared length, longest
  first; edges of equal length are ordered by their vertex pair ``(min id, max id)``,
  smaller pair first.  The *longest edge* is the first, the *second-longest* the second.
* **Constraint edge**: a boundary edge (a triangle on one side only), a constrained
  segment, or an edge between two triangles with different attributes.  No step flips a
  constraint edge or inserts a centroid across it.
* **Lepp(t0)**: triangles t0, t1, …, tk where t(i+1) is the neighbour of ti across the
  longest edge e(i) of ti.  The path stops at e(k) — the **terminal edge** — when e(k) is a
  constraint edge, or when e(k) is *a* longest edge of the neighbour too (at least as long
  as each of its edges).  Then ``|e(i)|`` strictly increases along the path, so it never
  revisits a triangle and ends after at most as many triangles as there are edge lengths.

The functions take a :class:`~geomexact.mesh2d.snapshot.Mesh2` or an open
:class:`~geomexact.mesh2d.transient.Transient2`; directed edges ``(u, v)`` are returned with the
triangle they belong to on their left.

>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> path = lepp(square, (0, 1, 2))
>>> path.terminal_edge, path.terminal_triangles, path.kind
((2, 0), ((0, 1, 2), (0, 2, 3)), 'interior')
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal, TypeAlias

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.snapshot import Edge, Mesh2, Triangle, canonical_triangle
from geomexact.mesh2d.transient import Transient2

__all__ = [
    "Lepp",
    "TerminalKind",
    "comes_first",
    "edge_order",
    "edges_by_length",
    "is_constraint_edge",
    "lepp",
    "longest_edge",
    "longest_first",
    "second_longest_edge",
]

TerminalKind: TypeAlias = Literal["interior", "boundary", "constrained"]
MeshLike: TypeAlias = Mesh2 | Transient2

_LESS = Comparison.LESS


def comes_first(order: int, u: int, v: int, x: int, y: int) -> bool:
    """True when edge {u, v} comes before edge {x, y} in the edge order, given ``order``,
    the sign (-1, 0, 1 or a :class:`Comparison`) of ``|uv|² - |xy|²``: longer, or as long
    with the smaller (min id, max id) pair."""
    if order > 0:
        return True
    if order < 0:
        return False
    return (min(u, v), max(u, v)) < (min(x, y), max(x, y))


def _before(p: Point2, q: Point2, u: int, v: int, r: Point2, s: Point2, x: int, y: int) -> bool:
    """True when edge {u, v} (points p, q) comes before edge {x, y} (points r, s) in the
    edge order."""
    return comes_first(compare_squared_lengths(p, q, r, s), u, v, x, y)


def longest_first(
    pa: Point2, pb: Point2, pc: Point2, a: int, b: int, c: int,
    compare: Callable[[Point2, Point2, Point2, Point2], int] = compare_squared_lengths,
) -> Triangle:
    """The rotation (u, v, w) of the triangle (a, b, c), at pa, pb, pc, whose edge {u, v}
    is its longest in the edge order.  Two comparisons by ``compare``: the exact
    :func:`~geomexact.kernel.comparisons.compare_squared_lengths`, or one equal to it on
    the points given (the batch engine's float comparison on the dyadic grid)."""
    if comes_first(compare(pa, pb, pb, pc), a, b, b, c):
        return (a, b, c) if comes_first(compare(pa, pb, pc, pa), a, b, c, a) else (c, a, b)
    return (b, c, a) if comes_first(compare(pb, pc, pc, pa), b, c, c, a) else (c, a, b)


def edge_order(
    pa: Point2, pb: Point2, pc: Point2, a: int, b: int, c: int
) -> tuple[int, int, int]:
    """The edge order of the triangle with vertices a, b, c at pa, pb, pc, as indices of
    its edges: 0 for {a, b}, 1 for {b, c}, 2 for {c, a}; longest first (tie rule in the
    module docstring).  At most three exact comparisons."""
    first01 = _before(pa, pb, a, b, pb, pc, b, c)
    first12 = _before(pb, pc, b, c, pc, pa, c, a)
    first20 = _before(pc, pa, c, a, pa, pb, a, b)
    if first01:
        if first12:
            return (0, 1, 2)
        return (2, 0, 1) if first20 else (0, 2, 1)
    if first12:
        return (1, 2, 0) if first20 else (1, 0, 2)
    return (2, 1, 0)


def _points(mesh: MeshLike, triangle: Triangle) -> tuple[Point2, Point2, Point2]:
    a, b, c = triangle
    if mesh.apex(a, b) != c:
        raise PreconditionError(
            "lepp", f"{triangle} is not a counter-clockwise triangle of the mesh",
            triangle=triangle,
        )
    return mesh.point(a), mesh.point(b), mesh.point(c)


def edges_by_length(mesh: MeshLike, triangle: Triangle) -> tuple[Edge, Edge, Edge]:
    """The edges of a counter-clockwise ``triangle`` of ``mesh`` as directed edges (the
    triangle on their left), in edge order: longest first."""
    a, b, c = triangle
    pa, pb, pc = _points(mesh, triangle)
    edges = ((a, b), (b, c), (c, a))
    i, j, k = edge_order(pa, pb, pc, a, b, c)
    return edges[i], edges[j], edges[k]


def longest_edge(mesh: MeshLike, triangle: Triangle) -> Edge:
    """The longest edge of ``triangle`` (tie rule: smaller vertex pair), directed with the
    triangle on its left."""
    u, v, _ = longest_first(*_points(mesh, triangle), *triangle)
    return u, v


def second_longest_edge(mesh: MeshLike, triangle: Triangle) -> Edge:
    """The second edge of ``triangle`` in edge order, directed with the triangle on its
    left."""
    return edges_by_length(mesh, triangle)[1]


def _attributes(mesh: MeshLike, triangle: Triangle) -> object:
    if isinstance(mesh, Mesh2):
        if not len(mesh.triangle_attributes):
            return None
        return mesh.triangle_attributes.get(canonical_triangle(*triangle))
    return mesh.triangle_attributes(triangle)


def _segment(mesh: MeshLike, u: int, v: int) -> bool:
    if isinstance(mesh, Mesh2):
        return mesh.is_constrained(u, v)
    return mesh.segment_marker(u, v) is not None


def is_constraint_edge(mesh: MeshLike, u: int, v: int) -> bool:
    """True when edge {u, v} is a boundary edge, a constrained segment, or lies between
    triangles with different attributes.  Raises when {u, v} is not an edge."""
    w, x = mesh.apex(u, v), mesh.apex(v, u)
    if w is None and x is None:
        raise PreconditionError("lepp", f"({u}, {v}) is not an edge of the mesh", edge=(u, v))
    return _constraint_kind(mesh, u, v, w, x) is not None


def _constraint_kind(
    mesh: MeshLike, u: int, v: int, w: int | None, x: int | None
) -> TerminalKind | None:
    if w is None or x is None:
        return "boundary"
    if _segment(mesh, u, v):
        return "constrained"
    if _attributes(mesh, (u, v, w)) != _attributes(mesh, (v, u, x)):
        return "constrained"
    return None


@attrs.frozen(slots=True)
class Lepp:
    """The longest-edge propagation path of a triangle.

    ``path``: t0, t1, …, tk (canonical triangles); ``terminal_edge``:
    the directed edge (u, v) of tk where the path stops; ``terminal_triangles``: (tk,) for a
    boundary terminal edge, else (tk, the triangle on the other side); ``kind``:
    ``"interior"`` (a longest edge of both triangles, unconstrained), ``"boundary"`` or
    ``"constrained"`` (a segment, or between different attributes)."""

    path: tuple[Triangle, ...]
    terminal_edge: Edge
    terminal_triangles: tuple[Triangle, ...]
    kind: TerminalKind


def lepp(mesh: MeshLike, triangle: Triangle) -> Lepp:
    """The Lepp of ``triangle`` (any rotation of a counter-clockwise triangle of ``mesh``).

    O(length of the path) exact comparisons; the path has at most as many triangles as
    there are distinct edge lengths in the mesh."""
    path = [canonical_triangle(*triangle)]
    u, v = longest_edge(mesh, triangle)
    while True:
        w, x = mesh.apex(u, v), mesh.apex(v, u)
        kind = _constraint_kind(mesh, u, v, w, x)
        if kind == "boundary":
            return Lepp(tuple(path), (u, v), (path[-1],), kind)
        assert x is not None
        neighbour = canonical_triangle(v, u, x)
        if kind == "constrained":
            return Lepp(tuple(path), (u, v), (path[-1], neighbour), kind)
        pu, pv, px = mesh.point(u), mesh.point(v), mesh.point(x)
        if (
            compare_squared_lengths(pu, pv, pv, px) != _LESS
            and compare_squared_lengths(pu, pv, px, pu) != _LESS
        ):
            return Lepp(tuple(path), (u, v), (path[-1], neighbour), "interior")
        path.append(neighbour)
        # {u, v} is strictly shorter than another edge of the neighbour: the longest edge
        # is {u, x} or {x, v}
        u, v = (u, x) if _before(pu, px, u, x, px, pv, x, v) else (x, v)
