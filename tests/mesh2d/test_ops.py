"""Pure steps on 2D meshes: unit tests of each op and a state machine over random op
sequences checking the snapshot invariants."""

from __future__ import annotations

import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, rule

from geomexact import (
    Mesh2,
    PreconditionError,
    Step,
    Trace,
    TransientSealedError,
    apply,
    bisect,
    flip,
    insert_centroid,
    insert_in_edge,
    insert_in_triangle,
    is_delaunay,
    legalize,
    mesh_from_triangles,
    mpq,
    point2,
    total_area,
    validate,
)
from geomexact.mesh2d.ops import apply_in, flip_in
from geomexact.mesh2d.transient import Transient2
from geomexact.strategies import convex_polygons, meshes_with_traces


def unit_square(constrained: bool = True) -> Mesh2:
    segments = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)] if constrained else []
    return mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], segments
    )


# -- flip ---------------------------------------------------------------------------------
def test_flip_replaces_the_diagonal() -> None:
    """Flipping the diagonal of the square gives the other diagonal."""
    flipped = flip(unit_square(), (0, 2))
    assert flipped.triangles() == [(0, 1, 3), (1, 2, 3)]
    assert validate(flipped) == []


def test_flip_twice_is_identity() -> None:
    """flip(flip(m, e), e') == m, digest included."""
    square = unit_square()
    again = flip(flip(square, (0, 2)), (1, 3))
    assert again == square and again.digest == square.digest


@pytest.mark.parametrize("edge", [(0, 1), (1, 0), (3, 0)])
def test_flip_refuses_boundary_edges(edge: tuple[int, int]) -> None:
    """A boundary edge has one triangle and cannot be flipped."""
    with pytest.raises(PreconditionError, match="boundary"):
        flip(unit_square(constrained=False), edge)


def test_flip_refuses_constrained_edges() -> None:
    """An interior constrained segment cannot be flipped."""
    mesh = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 2, 5)]
    )
    with pytest.raises(PreconditionError, match="constrained"):
        flip(mesh, (0, 2))


def test_flip_refuses_non_convex_quadrilateral() -> None:
    """An edge whose quadrilateral is not strictly convex (here: a reflex corner and a
    straight corner) cannot be flipped."""
    reflex = mesh_from_triangles([(0, 0), (4, 0), (1, 1), (0, 4)], [(0, 1, 2), (0, 2, 3)])
    with pytest.raises(PreconditionError, match="convex"):
        flip(reflex, (0, 2))
    straight = mesh_from_triangles([(0, 0), (2, 0), (1, 1), (0, 2)], [(0, 1, 2), (0, 2, 3)])
    with pytest.raises(PreconditionError, match="convex"):
        flip(straight, (0, 2))


def test_flip_refuses_a_missing_edge() -> None:
    with pytest.raises(PreconditionError, match="not an edge"):
        flip(unit_square(), (1, 3))


# -- bisect / insert_in_edge ------------------------------------------------------------
def test_bisect_interior_edge_makes_four_triangles() -> None:
    """The midpoint of the diagonal joins all four corners."""
    mesh = bisect(unit_square(), (0, 2))
    assert mesh.point(4) == point2(mpq(1, 2), mpq(1, 2))
    assert mesh.triangle_count == 4 and validate(mesh) == []


def test_bisect_constrained_edge_keeps_both_halves_constrained() -> None:
    """A constrained edge becomes two constrained halves with its marker; the new vertex
    takes the marker."""
    mesh = bisect(unit_square(), (0, 1))
    assert mesh.segment_list() == [(0, 3, 1), (0, 4, 1), (1, 2, 1), (1, 4, 1), (2, 3, 1)]
    assert mesh.vertex_markers.get(4) == 1
    assert mesh.triangle_count == 3 and validate(mesh) == []


def test_insert_in_edge_requires_a_point_strictly_inside() -> None:
    square = unit_square()
    with pytest.raises(PreconditionError, match="strictly inside"):
        insert_in_edge(square, (0, 1), point2(2, 0))
    with pytest.raises(PreconditionError, match="strictly inside"):
        insert_in_edge(square, (0, 1), point2(mpq(1, 2), mpq(1, 10**9)))
    with pytest.raises(PreconditionError, match="strictly inside"):
        insert_in_edge(square, (0, 1), point2(1, 0))
    mesh = insert_in_edge(square, (0, 2), point2(mpq(1, 3), mpq(1, 3)))
    assert validate(mesh) == [] and mesh.triangle_count == 4


# -- insert_in_triangle ------------------------------------------------------------------
def test_insert_in_triangle_makes_three() -> None:
    mesh = insert_in_triangle(unit_square(), (0, 1, 2), point2(mpq(2, 3), mpq(1, 3)))
    assert mesh.triangle_count == 4 and validate(mesh) == []
    assert sorted(mesh.star(4)) == [(4, 0, 1), (4, 1, 2), (4, 2, 0)]


def test_insert_in_triangle_refuses_points_on_edges_and_outside() -> None:
    square = unit_square()
    for point in (point2(mpq(1, 2), mpq(1, 2)), point2(mpq(1, 2), 0), point2(0, 1)):
        with pytest.raises(PreconditionError, match="strictly inside"):
            insert_in_triangle(square, (0, 1, 2), point)
    with pytest.raises(PreconditionError, match="not a counter-clockwise triangle"):
        insert_in_triangle(square, (0, 2, 1), point2(mpq(2, 3), mpq(1, 3)))


# -- insert_centroid ---------------------------------------------------------------------
def test_area_centroid_of_a_square_is_its_centre() -> None:
    """The QLepp2D A -> B case: one centroid insertion in a diagonal-split square."""
    mesh = insert_centroid(unit_square(), (0, 2))
    assert mesh.point(4) == point2(mpq(1, 2), mpq(1, 2))
    assert mesh.triangle_count == 4 and validate(mesh) == []


def test_area_centroid_differs_from_vertex_average() -> None:
    """For a kite the area centroid and the vertex average are different points, both
    exact."""
    kite = mesh_from_triangles([(0, 0), (4, 0), (5, 5), (0, 4)], [(0, 1, 2), (0, 2, 3)])
    by_area = insert_centroid(kite, (0, 2)).point(4)
    by_vertices = insert_centroid(kite, (0, 2), kind="vertices").point(4)
    assert by_vertices == point2(mpq(9, 4), mpq(9, 4))
    # triangles (0,1,2) and (0,2,3) both have area 10: the mean of their centroids
    # (3, 5/3) and (5/3, 3)
    assert by_area == point2(mpq(7, 3), mpq(7, 3))
    assert by_area != by_vertices


def test_insert_centroid_refuses_boundary_and_non_convex() -> None:
    with pytest.raises(PreconditionError, match="boundary"):
        insert_centroid(unit_square(), (0, 1))
    dart = mesh_from_triangles([(0, 0), (10, 0), (1, 1), (0, 10)], [(0, 1, 2), (0, 2, 3)])
    with pytest.raises(PreconditionError, match="not strictly inside"):
        insert_centroid(dart, (0, 2))


# -- legalize ----------------------------------------------------------------------------
def test_legalize_restores_delaunay_after_insertion() -> None:
    """A point inserted in a Delaunay mesh and legalized gives a Delaunay mesh."""
    mesh = mesh_from_triangles([(0, 0), (4, 0), (4, 3), (0, 3)], [(0, 1, 2), (0, 2, 3)])
    inserted = insert_in_triangle(mesh, (0, 1, 2), point2(3, 1))
    legal, flips = legalize(inserted, 4)
    assert flips == (Step("flip", (2, 0)),)
    assert is_delaunay(legal) and validate(legal) == []


def test_legalize_never_flips_cocircular_points() -> None:
    """The square's corners are cocircular: legalizing the centre changes nothing."""
    centred = bisect(unit_square(), (0, 2))
    assert legalize(centred, 4)[1] == ()


def test_legalize_keeps_constrained_edges() -> None:
    mesh = mesh_from_triangles(
        [(0, 0), (4, 0), (4, 3), (0, 3)], [(0, 1, 2), (0, 2, 3)], [(0, 2, 7)]
    )
    inserted = insert_in_triangle(mesh, (0, 1, 2), point2(3, 1))
    legal, flips = legalize(inserted, 4)
    assert flips == () and legal.is_constrained(0, 2)


# -- steps, apply, transient -------------------------------------------------------------
def test_apply_refuses_unknown_and_malformed_steps() -> None:
    square = unit_square()
    with pytest.raises(PreconditionError, match="unknown step"):
        apply(square, Step("explode", (0,)))
    with pytest.raises(PreconditionError, match="expects 2 arguments"):
        apply(square, Step("flip", (0, 2, 3)))
    with pytest.raises(PreconditionError, match="integers"):
        apply(square, Step("flip", (mpq(1, 2), 2)))


def test_transient_refuses_writes_after_seal() -> None:
    transient = Transient2(unit_square())
    transient.seal()
    with pytest.raises(TransientSealedError):
        flip_in(transient, 0, 2)


def test_failed_op_leaves_transient_unchanged() -> None:
    transient = Transient2(unit_square())
    before = transient.digest
    with pytest.raises(PreconditionError):
        flip_in(transient, 0, 1)
    assert transient.digest == before and transient.steps == []


def test_mesh_from_triangles_refuses_bad_tables() -> None:
    points = [(0, 0), (1, 0), (1, 1), (0, 1)]
    with pytest.raises(PreconditionError, match="clockwise"):
        mesh_from_triangles(points, [(0, 2, 1)])
    assert mesh_from_triangles(points, [(0, 2, 1)], orient=True).triangles() == [(0, 1, 2)]
    with pytest.raises(PreconditionError, match="degenerate"):
        mesh_from_triangles([(0, 0), (1, 1), (2, 2)], [(0, 1, 2)])
    with pytest.raises(PreconditionError, match="refers to vertex 9"):
        mesh_from_triangles(points, [(0, 1, 9)])
    with pytest.raises(PreconditionError, match="shares a directed edge"):
        mesh_from_triangles(points, [(0, 1, 2), (0, 1, 3)])


# -- properties --------------------------------------------------------------------------
@given(meshes_with_traces(max_steps=25))
def test_every_op_sequence_gives_a_valid_mesh_with_the_same_area(
    case: tuple[Mesh2, Mesh2, object],
) -> None:
    start, end, _ = case
    assert validate(end) == []
    assert total_area(end) == total_area(start)


@given(meshes_with_traces(max_steps=15))
def test_pure_and_transient_paths_agree(case: tuple[Mesh2, Mesh2, Trace]) -> None:
    """Applying the same steps one pure call at a time or in one transient gives the same
    digest after every step, and the same final mesh."""
    start, end, trace = case
    mesh = start
    transient = Transient2(start)
    for step, digest in zip(trace.steps, trace.digests, strict=True):
        mesh = apply(mesh, step)
        apply_in(transient, step)
        assert mesh.digest == transient.digest == digest
    assert transient.seal() == mesh == end


class SnapshotMachine(RuleBasedStateMachine):
    """Random ops on a growing history of snapshots: old snapshots never change, every
    snapshot is valid, area is conserved exactly, flip∘flip is the identity."""

    def __init__(self) -> None:
        super().__init__()
        self.history: list[tuple[Mesh2, list[tuple[int, int, int]], int]] = []
        self.area = None

    def _current(self) -> Mesh2:
        return self.history[-1][0]

    def _push(self, mesh: Mesh2) -> None:
        self.history.append((mesh, mesh.triangles(), mesh.digest))

    @rule(polygon=convex_polygons())
    def start(self, polygon: list[object]) -> None:
        if self.history:
            return
        n = len(polygon)
        mesh = mesh_from_triangles(polygon, [(0, i, i + 1) for i in range(1, n - 1)],
                                   [(i, (i + 1) % n, 1) for i in range(n)])
        self.area = total_area(mesh)
        self._push(mesh)

    def _edge(self, data: st.DataObject) -> tuple[int, int] | None:
        if not self.history:
            return None
        edges = self._current().edges()
        return data.draw(st.sampled_from(edges)) if edges else None

    @rule(data=st.data())
    def bisect_an_edge(self, data: st.DataObject) -> None:
        edge = self._edge(data)
        if edge is not None:
            self._push(bisect(self._current(), edge))

    @rule(data=st.data())
    def flip_an_edge_and_back(self, data: st.DataObject) -> None:
        edge = self._edge(data)
        if edge is None:
            return
        mesh = self._current()
        try:
            flipped = flip(mesh, edge)
        except PreconditionError:
            return
        u, v = edge
        w = mesh.apex(u, v)
        x = mesh.apex(v, u)
        assert w is not None and x is not None
        assert flip(flipped, (w, x)) == mesh
        self._push(flipped)

    @rule(data=st.data())
    def insert_a_centroid_and_legalize(self, data: st.DataObject) -> None:
        edge = self._edge(data)
        if edge is None:
            return
        try:
            mesh = insert_centroid(self._current(), edge)
        except PreconditionError:
            return
        legal, _ = legalize(mesh, mesh.vertex_count - 1)
        self._push(legal)

    @invariant()
    def snapshots_are_valid_unchanged_and_conserve_area(self) -> None:
        if not self.history:
            return
        mesh, triangles, digest = self.history[-1]
        note(repr(mesh))
        assert validate(mesh) == []
        assert total_area(mesh) == self.area
        for old, old_triangles, old_digest in self.history:
            assert old.triangles() == old_triangles and old.digest == old_digest


TestSnapshotMachine = SnapshotMachine.TestCase
TestSnapshotMachine.settings = settings(max_examples=30, stateful_step_count=20, deadline=None)


def test_validate_finds_a_star_wrapped_twice_around_a_vertex() -> None:
    """Five triangles around vertex 0 turning 144° each (a pentagram fan): every triangle
    is counter-clockwise and every interior edge has two triangles, but the fan wraps twice
    around the centre; validate reports the fold-over."""
    ring = [(10, 0), (-8, 6), (3, -10), (3, 10), (-8, -6)]  # angles 0, 143, 287, 73, 217
    mesh = mesh_from_triangles([(0, 0), *ring], [(0, i, i % 5 + 1) for i in range(1, 6)])
    kinds = {violation.kind for violation in validate(mesh)}
    assert "fold-over" in kinds
