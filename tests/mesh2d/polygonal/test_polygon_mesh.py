"""The PolygonMesh value: construction errors, queries, the exact checker (every
violation kind, with and without sources), statistics, and the vectorised orientation
test against orient2d."""

from __future__ import annotations

import doctest
import importlib

import pytest
from hypothesis import given
from hypothesis import strategies as st

import geomexact.mesh2d.polygonal.polygon_mesh as polymesh_module
from geomexact import InvalidMeshError, mesh_from_triangles, mpq, point2
from geomexact.errors import PreconditionError
from geomexact.kernel.points import Point2
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.polygonal.polygon_mesh import (
    PolygonMesh,
    check_polygon_mesh,
    interior_angles_degrees,
    is_convex_polygon,
    mesh_stats,
    nonconvex_polygons,
    orientation_signs,
    reflex_vertices,
    validate_polygon_mesh,
)
from geomexact.mesh2d.polygonal.polylla_meshing import polylla
from geomexact.strategies import near_degenerate_points2, points2

SQUARE = [point2(0, 0), point2(2, 0), point2(2, 2), point2(0, 2), point2(1, 1)]


def kinds(mesh: PolygonMesh, **options: object) -> list[str]:
    return [v.kind for v in validate_polygon_mesh(mesh, **options)]  # type: ignore[arg-type]


def test_module_doctests() -> None:
    # ``geomexact.mesh2d.polygonal.polylla_meshing`` is also the function re-exported by the
    # package: import the module by name
    polylla_module = importlib.import_module("geomexact.mesh2d.polygonal.polylla_meshing")
    assert doctest.testmod(polylla_module).failed == 0
    assert doctest.testmod(polymesh_module).failed == 0


def test_constructor_checks_structure() -> None:
    with pytest.raises(PreconditionError, match="< 3"):
        PolygonMesh(SQUARE, [(0, 1)])
    with pytest.raises(PreconditionError, match="missing vertex 9"):
        PolygonMesh(SQUARE, [(0, 1, 9)])
    with pytest.raises(PreconditionError, match="one per polygon"):
        PolygonMesh(SQUARE, [(0, 1, 2)], [((0, 1, 2),), ((0, 2, 3),)])
    with pytest.raises(PreconditionError, match="empty source"):
        PolygonMesh(SQUARE, [(0, 1, 2)], [()])
    with pytest.raises(PreconditionError, match="not a triangle"):
        PolygonMesh(SQUARE, [(0, 1, 2)], [((0, 1, 7),)])


def test_queries() -> None:
    mesh = PolygonMesh(SQUARE, [[0, 1, 2, 3]])  # lists are converted to tuples
    assert mesh.polygons == ((0, 1, 2, 3),)
    assert mesh.polygon_points(0) == tuple(SQUARE[:4])
    assert mesh.edges() == [(0, 1), (0, 3), (1, 2), (2, 3)]
    assert mesh.area(0) == 4 and mesh.total_area() == 4
    assert "polygons=1" in repr(mesh)
    assert mesh == PolygonMesh(tuple(SQUARE), ((0, 1, 2, 3),))


def test_valid_meshes_with_and_without_sources() -> None:
    plain = PolygonMesh(SQUARE, [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)])
    assert plain.validate() == []
    triangulation = mesh_from_triangles(SQUARE, [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)])
    polygons = PolygonMesh(SQUARE, [(0, 1, 2, 4), (0, 4, 2, 3)],
                           [((0, 1, 4), (1, 2, 4)), ((0, 4, 3), (2, 3, 4))])
    assert polygons.validate(triangulation) == []
    assert polygons.validate(triangulation, geometric=True) == []
    assert check_polygon_mesh(polygons, triangulation) is polygons


def test_single_polygon_violations() -> None:
    assert kinds(PolygonMesh(SQUARE, [(0, 3, 2, 1)])) == ["orientation"]
    flat = kinds(PolygonMesh([point2(0, 0), point2(1, 1), point2(2, 2)], [(0, 1, 2)]))
    assert flat[0] == "orientation" and set(flat[1:]) == {"self-intersection"}
    repeated = PolygonMesh(SQUARE, [(0, 1, 4, 2, 3, 4)])
    assert "repeated-vertex" in kinds(repeated)
    bowtie = PolygonMesh([point2(0, 0), point2(2, 2), point2(2, 0), point2(0, 2)],
                         [(0, 1, 2, 3)])  # self-crossing, zero signed area
    assert kinds(bowtie) == ["orientation", "self-intersection"]
    crossing_self = PolygonMesh(
        [point2(0, 0), point2(4, 0), point2(4, 4), point2(1, -1), point2(0, 4)],
        [(0, 1, 2, 3, 4)])
    assert "self-intersection" in kinds(crossing_self)
    with pytest.raises(InvalidMeshError):
        check_polygon_mesh(crossing_self)


def test_overlaps_between_polygons() -> None:
    # the same directed edge in two polygons
    assert "duplicate-edge" in kinds(PolygonMesh(SQUARE, [(0, 1, 4), (0, 1, 2)]))
    # crossing edges
    crossing = PolygonMesh(SQUARE, [(0, 1, 2), (0, 1, 3)])
    assert set(kinds(crossing)) & {"crossing", "duplicate-edge"}
    # two polygons sharing vertex 0 and overlapping there, edges not crossing
    fan = [point2(0, 0), point2(4, 0), point2(4, 4), point2(2, mpq(3, 2)), point2(3, 1)]
    overlap = PolygonMesh(fan, [(0, 1, 2), (0, 4, 3)])
    assert kinds(overlap, geometric=True) == ["overlap"]  # (0, 4, 3) inside (0, 1, 2)
    # a polygon strictly inside another, sharing nothing
    big = [point2(0, 0), point2(10, 0), point2(10, 10), point2(0, 10),
           point2(4, 4), point2(6, 4), point2(5, 6)]
    nested = PolygonMesh(big, [(0, 1, 2, 3), (4, 5, 6)])
    assert kinds(nested) == ["overlap"]
    # side by side: fine
    apart = PolygonMesh(big, [(0, 1, 5, 4), (4, 5, 6)])
    assert kinds(apart) == []


def test_source_violations() -> None:
    triangulation = mesh_from_triangles(SQUARE, [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)])
    wrong_cycle = PolygonMesh(SQUARE, [(0, 1, 2, 4), (0, 4, 2, 3)],
                              [((0, 1, 4), (2, 3, 4)), ((1, 2, 4), (3, 0, 4))])
    assert "source-boundary" in kinds(wrong_cycle)
    twice = PolygonMesh(SQUARE, [(0, 1, 4), (0, 1, 4)], [((0, 1, 4),), ((0, 1, 4),)])
    assert "triangle-twice" in kinds(twice)
    clockwise = PolygonMesh(SQUARE, [(0, 1, 4)], [((0, 4, 1),)])
    assert "source-triangle" in kinds(clockwise)
    partial = PolygonMesh(SQUARE, [(0, 1, 4)], [((0, 1, 4),)])
    assert kinds(partial, triangulation=triangulation) == ["coverage"]
    moved = PolygonMesh([*SQUARE[:4], point2(1, mpq(3, 2))], [(0, 1, 2, 4), (0, 4, 2, 3)],
                        [((0, 1, 4), (1, 2, 4)), ((0, 4, 3), (2, 3, 4))])
    assert "vertex" in kinds(moved, triangulation=triangulation)
    bare = PolygonMesh(SQUARE, [(0, 1, 2, 3)])
    assert "coverage" in kinds(bare, triangulation=triangulation)


def test_polygon_helpers() -> None:
    l_shape = [point2(0, 0), point2(2, 0), point2(2, 1), point2(1, 1), point2(1, 2),
               point2(0, 2)]
    polygon = (0, 1, 2, 3, 4, 5)
    assert reflex_vertices(l_shape, polygon) == [3]
    assert not is_convex_polygon(l_shape, polygon)
    assert interior_angles_degrees(l_shape, polygon) == pytest.approx(
        [90, 90, 90, 270, 90, 90])
    for scale in (mpq(10) ** 999, mpq(10) ** -400, mpq(10) ** 200_000):  # any magnitude
        scaled = [point2(p.x * scale, p.y * scale) for p in l_shape]
        assert interior_angles_degrees(scaled, polygon) == pytest.approx(
            [90, 90, 90, 270, 90, 90])
    straight = [point2(0, 0), point2(1, 0), point2(2, 0), point2(1, 1)]
    assert is_convex_polygon(straight, (0, 1, 2, 3))  # 180° at vertex 1 counts as convex
    assert nonconvex_polygons(PolygonMesh(l_shape, [polygon, (0, 1, 3)])) == [0]


def test_mesh_stats() -> None:
    mesh = mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    stats = mesh_stats(polylla(mesh), inserted_edges=0)
    assert stats == {
        "polygons": 1, "convex": 1, "nonconvex": 0, "vertices": 4, "edges": 4,
        "min_polygon_size": 4, "max_polygon_size": 4, "mean_polygon_size": 4.0,
        "min_angle_deg": pytest.approx(90.0), "max_angle_deg": pytest.approx(90.0),
        "min_area": 2.0, "max_area": 2.0, "mean_area": 2.0, "total_area": "2",
        "inserted_edges": 0,
    }
    empty = mesh_stats(PolygonMesh([], []))
    assert empty["polygons"] == 0 and empty["min_area"] is None and empty["total_area"] == "0"
    assert empty["inserted_edges"] is None


@given(st.lists(st.one_of(near_degenerate_points2(), st.tuples(points2(), points2(),
                                                                 points2())),
                min_size=1, max_size=20))
def test_orientation_signs_agree_with_orient2d(triples: list[tuple[Point2, ...]]) -> None:
    points: list[Point2] = []
    a: list[int] = []
    b: list[int] = []
    c: list[int] = []
    for triple in triples:
        base = len(points)
        points.extend(triple[:3])
        a.append(base)
        b.append(base + 1)
        c.append(base + 2)
    expected = [int(orient2d(points[i], points[j], points[k]))
                for i, j, k in zip(a, b, c, strict=True)]
    assert orientation_signs(points, a, b, c) == expected
