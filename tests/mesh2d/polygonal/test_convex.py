"""Convex decomposition: every polygon convex (checked independently and exactly), every
inserted edge an edge of the triangulation, the criteria and their tie rule, the exact
angle arithmetic, preconditions, and the loud failure."""

from __future__ import annotations

import doctest
import math

import pytest
from helpers.polygon_checks import (
    any_meshes,
    assert_partition,
    is_convex,
    polygon_edges,
    undirected,
)
from hypothesis import given
from hypothesis import strategies as st

import geomexact.mesh2d.polygonal.convex as convex_module
from geomexact import Mesh2, Point2, mesh_from_triangles, mpq, point2
from geomexact.errors import PreconditionError
from geomexact.mesh2d.polygonal.convex import (
    ConvexDecompositionError,
    convex_decomposition,
)
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.polygonal.polylla_meshing import polylla

# A hexagon (one polygon of 4 triangles) with two reflex corners, at 1 and 4, that the
# triangulation edge {1, 4} repairs at once: criterion 1 inserts it alone; angle-first
# mode first takes {1, 3} (closest to the bisector at 1), then {1, 4} for vertex 4.
HEXAGON = [(2, 2), (3, 2), (5, 0), (0, 6), (2, 3), (0, 5)]
HEXAGON_TRIANGLES = [(0, 1, 4), (0, 4, 5), (1, 2, 3), (1, 3, 4)]


def one_polygon(points: list[tuple[int, int]], triangles: list[tuple[int, int, int]]
                ) -> tuple[Mesh2, PolygonMesh]:
    mesh = mesh_from_triangles(points, triangles)
    polygon = tuple(range(len(points)))
    return mesh, PolygonMesh(mesh_points(mesh), [polygon], [tuple(mesh.triangles())])


def mesh_points(mesh: Mesh2) -> list[Point2]:
    return [mesh.point(v) for v in range(mesh.vertex_count)]


def test_module_doctests() -> None:
    assert doctest.testmod(convex_module).failed == 0


def test_criterion_one_repairs_two_reflex_corners_with_one_edge() -> None:
    mesh, polygons = one_polygon(HEXAGON, HEXAGON_TRIANGLES)
    assert polygons.validate(mesh) == []
    first = convex_decomposition(polygons)
    assert first.inserted_edges == ((1, 4),)
    assert first.mesh.polygons == ((0, 1, 4, 5), (1, 2, 3, 4))
    assert first.nonconvex_before == 1 and first.criterion_one
    angle_first = convex_decomposition(polygons, criterion_one=False)
    assert angle_first.inserted_edges == ((1, 3), (1, 4))
    assert angle_first.mesh.polygons == ((0, 1, 4, 5), (1, 2, 3), (1, 3, 4))
    assert not angle_first.criterion_one
    for result in (first, angle_first):
        assert_partition(mesh, result.mesh)


def one_polygon_ordered(points: list[tuple[int, int]], triangles: list[tuple[int, int, int]],
                        polygon: tuple[int, ...]) -> tuple[Mesh2, PolygonMesh]:
    mesh = mesh_from_triangles(points, triangles)
    return mesh, PolygonMesh(mesh_points(mesh), [polygon], [tuple(mesh.triangles())])


def test_bisector_tie_goes_to_the_smaller_vertex_pair() -> None:
    """The reflex corner at 0 spans 270° (from the direction to 1, straight down, round to
    the direction to 6, to the left); its bisector points along (1, 1), where no edge is.
    The candidates towards (2, 1) and (1, 2) are exactly as close: the smaller pair (0, 3)
    wins, whichever of the two directions carries id 3."""
    points = [(0, 0), (0, -2), (2, -2), (2, 1), (1, 2), (-2, 2), (-2, 0)]
    triangles = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 5, 6)]
    mesh, polygons = one_polygon_ordered(points, triangles, (0, 1, 2, 3, 4, 5, 6))
    result = convex_decomposition(polygons, criterion_one=False)
    assert result.inserted_edges == ((0, 3),)
    assert result.mesh.polygons == ((0, 1, 2, 3), (0, 3, 4, 5, 6))
    swapped = [(0, 0), (0, -2), (2, -2), (1, 2), (2, 1), (-2, 2), (-2, 0)]
    triangles = [(0, 1, 2), (0, 2, 4), (0, 4, 3), (0, 3, 5), (0, 5, 6)]
    mesh, polygons = one_polygon_ordered(swapped, triangles, (0, 1, 2, 4, 3, 5, 6))
    result = convex_decomposition(polygons, criterion_one=False)
    assert result.inserted_edges == ((0, 3),)  # now the direction (1, 2)
    assert result.mesh.polygons == ((0, 1, 2, 4, 3), (0, 3, 5, 6))
    assert_partition(mesh, result.mesh)


def test_trisectors_when_no_single_edge_suffices() -> None:
    """The corner at 0 spans about 332° (from the direction to (4, 1) round to (4, -1));
    its candidates point at 90°, 135°, 225° and 270°.  The two closest to the bisector
    (180°) tie, and either leaves a piece above 180°, so the candidates closest to the
    trisector rays (about 125° and 235°) are inserted: (0, 3) and (0, 4)."""
    points = [(0, 0), (4, 1), (0, 4), (-4, 4), (-4, -4), (0, -4), (4, -1)]
    triangles = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5), (0, 5, 6)]
    mesh, polygons = one_polygon(points, triangles)
    for criterion_one in (True, False):  # only one reflex corner: criterion 1 cannot apply
        result = convex_decomposition(polygons, criterion_one=criterion_one)
        assert result.inserted_edges == ((0, 3), (0, 4))
        assert result.mesh.polygons == ((0, 1, 2, 3), (0, 3, 4), (0, 4, 5, 6))
        assert_partition(mesh, result.mesh)


def test_convex_polygons_are_left_alone() -> None:
    mesh = mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    polygons = polylla(mesh)
    result = convex_decomposition(polygons)
    assert result.mesh == polygons
    assert result.inserted_edges == () and result.nonconvex_before == 0


# -----------------------------------------------------------------------------------------
# properties
# -----------------------------------------------------------------------------------------
@given(any_meshes(), st.booleans())
def test_every_polygon_is_convex_and_every_added_edge_is_a_triangulation_edge(
    mesh: Mesh2, criterion_one: bool
) -> None:
    polygons = polylla(mesh)
    result = convex_decomposition(polygons, criterion_one=criterion_one)
    assert all(is_convex(result.mesh.vertices, p) for p in result.mesh.polygons)
    assert_partition(mesh, result.mesh)  # includes validate(mesh) == []
    original = {undirected(e) for p in polygons.polygons for e in polygon_edges(p)}
    for edge in result.inserted_edges:
        assert mesh.is_edge(*edge)
        assert edge not in original
    assert len(set(result.inserted_edges)) == len(result.inserted_edges)
    assert len(result.mesh.polygons) == len(polygons.polygons) + len(result.inserted_edges)
    final = {undirected(e) for p in result.mesh.polygons for e in polygon_edges(p)}
    assert final == original | set(result.inserted_edges)
    # convex input polygons come through unchanged
    kept = set(result.mesh.polygons)
    for polygon in polygons.polygons:
        if is_convex(polygons.vertices, polygon):
            assert polygon in kept
    nonconvex = sum(not is_convex(polygons.vertices, p) for p in polygons.polygons)
    assert result.nonconvex_before == nonconvex


@given(any_meshes())
def test_decomposition_is_idempotent_and_deterministic(mesh: Mesh2) -> None:
    result = convex_decomposition(polylla(mesh))
    again = convex_decomposition(result.mesh)
    assert again.mesh == result.mesh and again.inserted_edges == ()
    assert convex_decomposition(polylla(mesh)) == result


# -----------------------------------------------------------------------------------------
# exact angles
# -----------------------------------------------------------------------------------------
def _angle_of(x: int, y: int) -> float:
    value = math.atan2(y, x)
    return value + 2 * math.pi if value < 0 else value


vectors = st.tuples(st.integers(-30, 30), st.integers(-30, 30)).filter(lambda v: v != (0, 0))


@given(st.lists(vectors, min_size=2, max_size=4), st.lists(vectors, min_size=2, max_size=4))
def test_lifted_angle_sums_compare_like_real_angle_sums(
    first: list[tuple[int, int]], second: list[tuple[int, int]]
) -> None:
    def total(vs: list[tuple[int, int]]) -> tuple[convex_module._Angle, float]:
        angle: convex_module._Angle = (0, mpq(vs[0][0]), mpq(vs[0][1]))
        real = _angle_of(*vs[0])
        for x, y in vs[1:]:
            angle = convex_module._add(angle, (0, mpq(x), mpq(y)))
            real += _angle_of(x, y)
        return angle, real

    a, ra = total(first)
    b, rb = total(second)
    exact = convex_module._compare(a, b)
    if abs(ra - rb) > 1e-9:
        assert exact == (1 if ra > rb else -1)
    # the turns count is the real sum's number of full turns
    assert a[0] == math.floor(ra / (2 * math.pi) + 1e-12) or abs(
        ra / (2 * math.pi) - round(ra / (2 * math.pi))) < 1e-9


def test_angle_times_and_turn() -> None:
    points = [point2(0, 0), point2(1, 0), point2(0, 1), point2(-1, 0)]
    quarter = convex_module._turn(points, 0, 1, 2)
    assert quarter == (0, 0, 1)
    assert convex_module._compare(convex_module._times(quarter, 2),
                                  convex_module._turn(points, 0, 1, 3)) == 0
    assert convex_module._times(quarter, 4)[0] == 1  # a full turn
    assert convex_module._compare(convex_module._times(quarter, 5),
                                  convex_module._times(quarter, 4)) == 1


# -----------------------------------------------------------------------------------------
# preconditions and the loud failure
# -----------------------------------------------------------------------------------------
def test_requires_sources() -> None:
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    bare = PolygonMesh(mesh_points(mesh), [(0, 1, 2)])
    with pytest.raises(PreconditionError, match="no sources"):
        convex_decomposition(bare)


def test_rejects_polygons_that_are_not_their_triangles() -> None:
    _, polygons = one_polygon(HEXAGON, HEXAGON_TRIANGLES)
    wrong = PolygonMesh(polygons.vertices, [(0, 1, 2, 3, 5)], polygons.sources)
    with pytest.raises(PreconditionError, match="polygon #0"):
        convex_decomposition(wrong)
    split = PolygonMesh(polygons.vertices, [(0, 1, 4, 5), (1, 2, 3, 4)],
                        [((0, 1, 4), (0, 4, 5)), ((1, 2, 3),)])
    with pytest.raises(PreconditionError, match="polygon #1"):
        convex_decomposition(split)
    twice = PolygonMesh(polygons.vertices, [(0, 1, 4, 5), (0, 1, 4, 5)],
                        [((0, 1, 4), (0, 4, 5)), ((0, 1, 4), (0, 4, 5))])
    with pytest.raises(PreconditionError, match="source of polygons"):
        convex_decomposition(twice)
    repeated = PolygonMesh(polygons.vertices, [(0, 1, 4, 1, 4, 5)], polygons.sources[:1])
    with pytest.raises(PreconditionError, match="not simple"):
        convex_decomposition(repeated)


def test_a_non_convex_result_fails_loudly(monkeypatch: pytest.MonkeyPatch) -> None:
    """With the decomposition disabled the final exact check must refuse the result."""
    monkeypatch.setattr(convex_module, "_decompose", lambda *args: None)
    _, polygons = one_polygon(HEXAGON, HEXAGON_TRIANGLES)
    with pytest.raises(ConvexDecompositionError) as caught:
        convex_decomposition(polygons)
    assert caught.value.polygons == ((0, 1, 2, 3, 4, 5),)
    assert isinstance(caught.value, RuntimeError)
