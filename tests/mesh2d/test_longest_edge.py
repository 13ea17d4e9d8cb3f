"""Longest-edge propagation paths: edge order and its tie rule, constraint edges, Lepp
paths and their terminal edges (``specs/lepp.md``)."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st

from geomexact import PreconditionError, mesh_from_triangles, mpq, point2
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.longest_edge import (
    edge_order,
    edges_by_length,
    is_constraint_edge,
    lepp,
    longest_edge,
    second_longest_edge,
)
from geomexact.mesh2d.snapshot import Mesh2, canonical_triangle
from geomexact.mesh2d.transient import Transient2
from geomexact.strategies import meshes_with_traces


def square(constrained: bool = False) -> Mesh2:
    segments = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)] if constrained else []
    return mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], segments
    )


def squared(mesh: Mesh2, u: int, v: int) -> object:
    p, q = mesh.point(u), mesh.point(v)
    return (q.x - p.x) ** 2 + (q.y - p.y) ** 2




# -- edge order -----------------------------------------------------------------------------
def test_edge_order_puts_the_longest_edge_first() -> None:
    """A scalene triangle: edges by decreasing exact length."""
    a, b, c = point2(0, 0), point2(4, 0), point2(1, 2)
    # |ab|^2 = 16, |bc|^2 = 13, |ca|^2 = 5
    assert edge_order(a, b, c, 0, 1, 2) == (0, 1, 2)
    assert edge_order(b, c, a, 1, 2, 0) == (2, 0, 1)  # the same triangle, rotated


def test_edge_order_breaks_ties_by_the_smaller_vertex_pair() -> None:
    """Equal lengths: the edge with the smaller (min id, max id) pair comes first."""
    # right isosceles: the hypotenuse, then the two legs ordered by their vertex pairs
    a, b, c = point2(0, 0), point2(1, 0), point2(0, 1)  # legs ab, ca; hypotenuse bc
    assert edge_order(a, b, c, 7, 3, 5) == (1, 0, 2)  # {3,5}; legs {3,7} before {5,7}
    assert edge_order(a, b, c, 3, 7, 5) == (1, 2, 0)  # {5,7}; legs {3,5} before {3,7}
    # two equal longest edges: the smaller pair is the longest edge
    p, q, r = point2(0, 0), point2(2, 0), point2(1, 3)  # |qr| = |rp| = 10 > |pq| = 4
    assert edge_order(p, q, r, 0, 1, 2) == (2, 1, 0)  # {0,2} before {1,2}
    assert edge_order(p, q, r, 2, 1, 0) == (1, 2, 0)  # {0,1} before {0,2}


@given(st.permutations([0, 1, 2]), st.integers(0, 5), st.integers(0, 5), st.integers(1, 5))
def test_edge_order_is_the_same_for_every_rotation(
    ids: list[int], x: int, y: int, height: int
) -> None:
    """The order of the three (undirected) edges does not depend on where the triangle
    starts."""
    points = [point2(0, 0), point2(x + 1, 0), point2(y, height)]
    a, b, c = ids
    pa, pb, pc = (points[i] for i in ids)
    edges = [frozenset(e) for e in ((a, b), (b, c), (c, a))]
    order = [edges[i] for i in edge_order(pa, pb, pc, a, b, c)]
    rotated = [frozenset(e) for e in ((b, c), (c, a), (a, b))]
    order_rotated = [rotated[i] for i in edge_order(pb, pc, pa, b, c, a)]
    assert order == order_rotated


def test_longest_and_second_longest_edges_are_directed_with_the_triangle_left() -> None:
    """The square's triangle (0, 1, 2): hypotenuse (2, 0), then legs by pair."""
    mesh = square()
    assert edges_by_length(mesh, (0, 1, 2)) == ((2, 0), (0, 1), (1, 2))
    assert longest_edge(mesh, (1, 2, 0)) == (2, 0)
    assert second_longest_edge(mesh, (0, 1, 2)) == (0, 1)
    for u, v in edges_by_length(mesh, (0, 2, 3)):
        apex = mesh.apex(u, v)
        assert apex is not None and canonical_triangle(u, v, apex) == (0, 2, 3)


def test_edges_by_length_refuses_a_non_triangle() -> None:
    """A clockwise or missing triple is not a triangle of the mesh."""
    with pytest.raises(PreconditionError, match="not a counter-clockwise triangle"):
        edges_by_length(square(), (0, 2, 1))


# -- constraint edges -------------------------------------------------------------------------
def test_constraint_edges_are_boundary_segments_and_attribute_borders() -> None:
    """Boundary and segment edges are constraints, an unconstrained interior edge is not,
    nor is a non-edge (refused)."""
    mesh = square()
    assert is_constraint_edge(mesh, 0, 1) and is_constraint_edge(mesh, 1, 0)
    assert not is_constraint_edge(mesh, 0, 2)
    inner = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 2, 4)]
    )
    assert is_constraint_edge(inner, 2, 0)
    regions = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
        triangle_attributes=[(mpq(1),), (mpq(2),)],
    )
    assert is_constraint_edge(regions, 0, 2)
    with pytest.raises(PreconditionError, match="not an edge"):
        is_constraint_edge(mesh, 1, 3)


# -- Lepp -------------------------------------------------------------------------------------
def test_lepp_of_the_square_ends_at_its_diagonal() -> None:
    """Both triangles have the diagonal as longest edge: it is terminal, interior."""
    path = lepp(square(), (1, 2, 0))
    assert path.path == ((0, 1, 2),)
    assert path.terminal_edge == (2, 0)
    assert path.terminal_triangles == ((0, 1, 2), (0, 2, 3))
    assert path.kind == "interior"


def test_lepp_stops_at_a_boundary_longest_edge() -> None:
    """A triangle whose longest edge is on the boundary is its own terminal triangle."""
    mesh = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (0, 2)], [(0, 1, 2), (0, 2, 3)])
    path = lepp(mesh, (1, 2, 0))
    assert path.path == ((0, 1, 2),)
    assert path.kind == "boundary"
    assert path.terminal_edge == (0, 1)
    assert path.terminal_triangles == ((0, 1, 2),)
    assert mesh.apex(1, 0) is None


def test_lepp_propagates_to_a_longer_edge() -> None:
    """A small triangle next to a big one: the path enters the big one and stops at the
    big one's longest edge, on the boundary."""
    # (0, 2, 3) has longest edge {0, 2} (17), which is shorter than {0, 1} (64)
    points = [(0, 0), (8, 0), (4, 1), (2, 2)]
    mesh = mesh_from_triangles(points, [(0, 1, 2), (0, 2, 3)])
    path = lepp(mesh, (0, 2, 3))
    assert path.path == ((0, 2, 3), (0, 1, 2))
    assert path.terminal_edge == (0, 1)
    assert path.kind == "boundary"


def test_lepp_stops_at_a_constrained_segment() -> None:
    """An interior segment stops the path; both triangles are reported."""
    path = lepp(square(), (0, 1, 2))
    assert path.kind == "interior"
    constrained = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 2, 9)]
    )
    path = lepp(constrained, (0, 1, 2))
    assert path.kind == "constrained"
    assert path.terminal_triangles == ((0, 1, 2), (0, 2, 3))


def test_lepp_works_on_an_open_transient() -> None:
    """The same path on a snapshot and on a transient opened on it."""
    mesh = square(constrained=True)
    assert lepp(Transient2(mesh), (0, 1, 2)) == lepp(mesh, (0, 1, 2))


@given(meshes_with_traces(max_steps=12), st.data())
def test_lepp_edges_grow_strictly_and_end_at_a_terminal_edge(
    case: tuple[Mesh2, Mesh2, object], data: st.DataObject
) -> None:
    """Along every path the longest edges strictly lengthen, triangles are distinct, and
    the last edge is a constraint or a longest edge of both its triangles."""
    _, mesh, _ = case
    triangle = data.draw(st.sampled_from(mesh.triangles()))
    path = lepp(mesh, triangle)
    assert len(set(path.path)) == len(path.path)
    assert path.path[0] == canonical_triangle(*triangle)
    lengths = [squared(mesh, *longest_edge(mesh, t)) for t in path.path]
    assert all(a < b for a, b in itertools.pairwise(lengths))
    u, v = path.terminal_edge
    assert longest_edge(mesh, path.path[-1]) == (u, v)
    if path.kind == "interior":
        x = mesh.apex(v, u)
        assert x is not None and not is_constraint_edge(mesh, u, v)
        pu, pv, px = mesh.point(u), mesh.point(v), mesh.point(x)
        assert compare_squared_lengths(pu, pv, pv, px) != Comparison.LESS
        assert compare_squared_lengths(pu, pv, px, pu) != Comparison.LESS
        assert path.terminal_triangles[1] == canonical_triangle(v, u, x)
    else:
        assert is_constraint_edge(mesh, u, v)
        assert (path.kind == "boundary") == (mesh.apex(v, u) is None)
