"""The 2D snapshot (``geomexact.mesh2d.snapshot``): canonical triangles, the immutable
``Mesh2`` value and its queries, content equality, star walks, boundary walks and the full
digest recomputation."""

from __future__ import annotations

import attrs
import immutables
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.snapshot import (
    Mesh2,
    canonical_triangle,
    empty_mesh,
    full_digest,
    next_boundary_edge,
    previous_boundary_edge,
    undirected,
    walk_star,
)
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.strategies import triangulations

FEW = settings(max_examples=min(settings().max_examples, 40))


def square_with_centre(segments: list[tuple[int, int, int]] | None = None) -> Mesh2:
    """The square 0-1-2-3 split into four triangles at its centre 4."""
    return mesh_from_triangles(
        [(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)],
        [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
        [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)] if segments is None else segments,
    )


# -- canonical forms --------------------------------------------------------------------------
@given(st.lists(st.integers(0, 50), min_size=3, max_size=3, unique=True))
def test_canonical_triangle_starts_at_the_smallest_id_and_keeps_the_cycle(
    triple: list[int],
) -> None:
    """The canonical triangle starts at the smallest id, is a rotation of the input, and is
    the same for all three rotations (but not for the reversed triple)."""
    a, b, c = triple
    canonical = canonical_triangle(a, b, c)
    assert canonical[0] == min(triple)
    assert canonical in ((a, b, c), (b, c, a), (c, a, b))
    assert canonical_triangle(b, c, a) == canonical == canonical_triangle(c, a, b)
    assert canonical_triangle(a, c, b) != canonical


def test_undirected_orders_the_ends() -> None:
    """An edge is the pair (min, max) whichever way it is given."""
    assert undirected(5, 2) == (2, 5) == undirected(2, 5)


# -- the value --------------------------------------------------------------------------------
def test_a_snapshot_is_frozen() -> None:
    """Assigning a field of a Mesh2 raises; its tables are immutable maps."""
    mesh = square_with_centre()
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        mesh.digest = 0  # type: ignore[misc]
    with pytest.raises(TypeError):
        mesh.vertices[9] = point2(0, 0)  # type: ignore[index]
    assert isinstance(mesh.halfedges, immutables.Map)


def test_the_empty_mesh() -> None:
    """The empty mesh has no elements and digest 0, its own recomputation."""
    mesh = empty_mesh()
    assert (mesh.vertex_count, mesh.triangle_count, mesh.digest) == (0, 0, 0)
    assert mesh.triangles() == [] and mesh.edges() == [] and mesh.boundary_edges() == []
    assert full_digest(mesh) == 0
    assert mesh.digest_text == "0" * 32
    assert mesh == empty_mesh()


def test_sizes_and_digest_text() -> None:
    """Counts match the tables; digest_text is the digest in 32 hex digits."""
    mesh = square_with_centre()
    assert mesh.vertex_count == 5 and mesh.triangle_count == 4
    assert len(mesh.halfedges) == 12
    assert int(mesh.digest_text, 16) == mesh.digest and len(mesh.digest_text) == 32
    assert repr(mesh) == (
        f"Mesh2(vertices=5, triangles=4, segments=4, digest={mesh.digest_text})"
    )


# -- queries ----------------------------------------------------------------------------------
def test_point_and_apex() -> None:
    """point gives the exact vertex; apex the third vertex left of a directed edge, None on
    the outside of the boundary or off the mesh."""
    mesh = square_with_centre()
    assert mesh.point(4) == point2(1, 1)
    with pytest.raises(KeyError):
        mesh.point(5)
    assert mesh.apex(0, 1) == 4 and mesh.apex(4, 0) == 1 and mesh.apex(1, 4) == 0
    assert mesh.apex(1, 0) is None
    assert mesh.apex(0, 2) is None


def test_has_triangle_accepts_rotations_not_reflections() -> None:
    """A counter-clockwise triangle is found in each rotation, never reversed."""
    mesh = square_with_centre()
    assert mesh.has_triangle((0, 1, 4)) and mesh.has_triangle((1, 4, 0))
    assert mesh.has_triangle((4, 0, 1))
    assert not mesh.has_triangle((0, 4, 1))
    assert not mesh.has_triangle((0, 1, 2))


def test_triangles_edges_and_boundary_are_sorted_canonical_lists() -> None:
    """triangles() are canonical and sorted, edges() sorted (min, max) pairs, and
    boundary_edges() the sorted counter-clockwise half-edges with nothing on their right."""
    mesh = square_with_centre()
    assert mesh.triangles() == [(0, 1, 4), (0, 4, 3), (1, 2, 4), (2, 3, 4)]
    assert sorted(mesh.iter_triangles()) == mesh.triangles()
    assert mesh.edges() == [(0, 1), (0, 3), (0, 4), (1, 2), (1, 4), (2, 3), (2, 4), (3, 4)]
    assert mesh.boundary_edges() == [(0, 1), (1, 2), (2, 3), (3, 0)]


def test_boundary_and_edge_membership() -> None:
    """is_edge and is_boundary_edge ignore the direction; diagonals through the centre are
    interior edges, sides are boundary edges, non-edges are neither."""
    mesh = square_with_centre()
    assert mesh.is_edge(0, 4) and mesh.is_edge(4, 0)
    assert mesh.is_boundary_edge(0, 1) and mesh.is_boundary_edge(1, 0)
    assert not mesh.is_boundary_edge(0, 4)
    assert not mesh.is_edge(0, 2) and not mesh.is_boundary_edge(0, 2)


def test_segment_queries() -> None:
    """segment_list is sorted (u, v, marker) with u < v; is_constrained ignores direction."""
    mesh = square_with_centre([(3, 0, 7), (1, 0, 2), (4, 2, 5)])
    assert mesh.segment_list() == [(0, 1, 2), (0, 3, 7), (2, 4, 5)]
    assert mesh.is_constrained(0, 3) and mesh.is_constrained(3, 0)
    assert mesh.is_constrained(2, 4) and not mesh.is_constrained(1, 2)


def test_star_of_an_interior_vertex_turns_once_counter_clockwise() -> None:
    """The star of the centre lists its four triangles in counter-clockwise order, each
    starting at the centre, each following the previous one."""
    star = square_with_centre().star(4)
    assert len(star) == 4
    assert all(t[0] == 4 for t in star)
    assert {canonical_triangle(*t) for t in star} == {
        (0, 1, 4), (1, 2, 4), (2, 3, 4), (0, 4, 3)}
    for (_, _, x), (_, w, _) in zip(star, star[1:] + star[:1], strict=True):
        assert x == w


def test_star_of_a_boundary_vertex_starts_after_the_gap() -> None:
    """At a boundary vertex the star runs counter-clockwise from the boundary edge leaving
    it to the one entering it; an isolated vertex has an empty star."""
    fan = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1), (5, 5)], [(0, 1, 2), (0, 2, 3)]
    )
    assert fan.star(0) == [(0, 1, 2), (0, 2, 3)]
    assert fan.star(2) == [(2, 3, 0), (2, 0, 1)]
    assert fan.star(4) == []


def test_walk_star_with_any_apex_function() -> None:
    """walk_star needs only an apex function: from any starting neighbour of an interior
    vertex it returns the same cycle, rotated to that neighbour."""
    mesh = square_with_centre()
    for start in (0, 1, 2, 3):
        star = walk_star(mesh.apex, 4, start)
        assert star[0][1] == start and len(star) == 4
    assert walk_star(mesh.apex, 4, None) == []
    table = {(9, 1): 2, (1, 2): 9, (2, 9): 1}
    assert walk_star(lambda u, v: table.get((u, v)), 9, 1) == [(9, 1, 2)]


def test_boundary_walks_go_round_the_loop() -> None:
    """next_boundary_edge and previous_boundary_edge follow the boundary loop both ways;
    an interior half-edge is refused."""
    mesh = square_with_centre()
    assert next_boundary_edge(mesh.apex, 0, 1) == (1, 2)
    assert next_boundary_edge(mesh.apex, 3, 0) == (0, 1)
    assert previous_boundary_edge(mesh.apex, 0, 1) == (3, 0)
    assert previous_boundary_edge(mesh.apex, 1, 2) == (0, 1)
    with pytest.raises(ValueError, match="not a boundary half-edge"):
        next_boundary_edge(mesh.apex, 1, 0)
    with pytest.raises(ValueError, match="not a boundary half-edge"):
        previous_boundary_edge(mesh.apex, 1, 0)


@FEW
@given(triangulations(max_steps=12))
def test_boundary_walks_visit_every_boundary_edge_of_a_convex_mesh(mesh: Mesh2) -> None:
    """On a mesh of a convex polygon the boundary is one loop: next_boundary_edge from any
    boundary edge visits all of them and returns; previous_boundary_edge inverts it."""
    boundary = mesh.boundary_edges()
    edge = boundary[0]
    seen = [edge]
    while True:
        following = next_boundary_edge(mesh.apex, *edge)
        assert previous_boundary_edge(mesh.apex, *following) == edge
        if following == seen[0]:
            break
        seen.append(following)
        edge = following
    assert sorted(seen) == boundary


@FEW
@given(triangulations(max_steps=12))
def test_queries_agree_with_the_half_edge_table(mesh: Mesh2) -> None:
    """triangle_count, triangles, edges and boundary edges are consistent: 3 half-edges per
    triangle, each edge once, Euler's formula for a disk, and every vertex star made of
    mesh triangles."""
    triangles = mesh.triangles()
    assert len(triangles) == mesh.triangle_count == len(mesh.halfedges) // 3
    assert all(mesh.has_triangle(t) for t in triangles)
    edges = mesh.edges()
    assert len(edges) == (len(mesh.halfedges) + len(mesh.boundary_edges())) // 2
    assert mesh.vertex_count - len(edges) + len(triangles) == 1  # a disk
    stars = sum(len(mesh.star(v)) for v in range(mesh.vertex_count))
    assert stars == 3 * len(triangles)
    for vertex in range(mesh.vertex_count):
        assert all(mesh.has_triangle(t) for t in mesh.star(vertex))


# -- equality ---------------------------------------------------------------------------------
def test_equality_is_content_equality() -> None:
    """Meshes with the same content built in different orders are equal and hash alike;
    a different marker, an extra vertex or a missing segment makes them unequal."""
    mesh = square_with_centre()
    same = mesh_from_triangles(
        [(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)],
        [(4, 3, 0), (2, 3, 4), (4, 1, 2), (1, 4, 0)],
        [(2, 3, 1), (0, 1, 1), (0, 3, 1), (2, 1, 1)],
    )
    assert mesh == same and hash(mesh) == hash(same)
    assert mesh != square_with_centre([(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 2)])
    assert mesh != square_with_centre([(0, 1, 1), (1, 2, 1), (2, 3, 1)])
    t = Transient2(mesh)
    t.add_vertex(point2(7, 7))
    assert t.seal() != mesh


def test_equality_does_not_rely_on_the_digest_alone() -> None:
    """Two different meshes that claim the same digest are still unequal."""
    mesh = square_with_centre()
    other = square_with_centre([])
    forged = attrs.evolve(other, digest=mesh.digest)
    assert forged.digest == mesh.digest
    assert forged != mesh
    moved = attrs.evolve(mesh, vertices=mesh.vertices.set(4, point2(mpq(1), mpq(1, 2))))
    assert moved != mesh


def test_a_mesh_is_not_equal_to_other_values() -> None:
    """Comparing with something that is not a Mesh2 gives False, not an error."""
    mesh = square_with_centre()
    assert mesh != mesh.digest and mesh != "mesh" and mesh != None  # noqa: E711


# -- digest and transients ----------------------------------------------------------------------
@FEW
@given(triangulations(max_steps=15))
def test_full_digest_equals_the_incremental_digest(mesh: Mesh2) -> None:
    """full_digest recomputes exactly the digest every step kept up to date."""
    assert full_digest(mesh) == mesh.digest


def test_full_digest_counts_markers_and_attributes() -> None:
    """Vertex markers, vertex attributes and triangle attributes each change the digest,
    and the recomputation still agrees."""
    plain = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    variants = [
        mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)], vertex_markers=[0, 3, 0]),
        mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)],
                            vertex_attributes=[(), (mpq(1, 2),), ()]),
        mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)],
                            triangle_attributes=[(mpq(4),)]),
    ]
    digests = {plain.digest}
    for variant in variants:
        assert full_digest(variant) == variant.digest
        digests.add(variant.digest)
        assert variant != plain
    assert len(digests) == 4


def test_transient_opens_on_the_snapshot_and_never_changes_it() -> None:
    """mesh.transient() starts from the mesh's content; edits in it leave the mesh as it
    was."""
    mesh = square_with_centre()
    triangles, digest, segments = mesh.triangles(), mesh.digest, mesh.segment_list()
    t = mesh.transient()
    assert isinstance(t, Transient2) and t.digest == mesh.digest
    t.remove_triangle(0, 1, 4)
    t.remove_segment(0, 1)
    t.add_vertex(point2(5, 5))
    changed = t.seal()
    assert changed.triangle_count == 3 and changed.vertex_count == 6
    assert mesh.triangles() == triangles and mesh.digest == digest
    assert mesh.segment_list() == segments and mesh.vertex_count == 5
    assert full_digest(mesh) == digest
