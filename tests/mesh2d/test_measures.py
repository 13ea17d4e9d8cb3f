"""Exact measures (``geomexact.mesh2d.measures``) and the mesh report
(``geomexact.mesh2d.summary``): exact signed, triangle, total and boundary-enclosed areas;
angles in degrees; the keys and values of ``mesh_summary``."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings

from geomexact.kernel.numbers import format_rational, mpq, parse_rational, to_float
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.measures import (
    atan2_degrees,
    boundary_enclosed_area,
    signed_area,
    total_area,
    triangle_angles_degrees,
    triangle_area,
)
from geomexact.mesh2d.snapshot import Mesh2, empty_mesh
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.strategies import meshes_with_traces, points2, rationals
from geomexact.trace.record import Trace

FEW = settings(max_examples=min(settings().max_examples, 40))
exact_points = points2(rationals())

SUMMARY_KEYS = {
    "vertices", "triangles", "edges", "boundary_edges", "constrained_edges", "min_angle_deg",
    "max_angle_deg", "min_area", "max_area", "mean_area", "total_area", "is_delaunay",
    "digest",
}


def square_with_centre() -> Mesh2:
    return mesh_from_triangles(
        [(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)],
        [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
        [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)],
    )


def annulus() -> Mesh2:
    """The square [0, 3]^2 with the square hole [1, 2]^2."""
    return mesh_from_triangles(
        [(0, 0), (3, 0), (3, 3), (0, 3), (1, 1), (2, 1), (2, 2), (1, 2)],
        [(0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4),
         (3, 4, 7)],
    )


def shoelace(polygon: list[Point2]) -> mpq:
    """The exact signed area of a polygon, by the shoelace formula."""
    twice = sum(
        (p.x * q.y - q.x * p.y for p, q in zip(polygon, polygon[1:] + polygon[:1], strict=True)),
        mpq(0),
    )
    return twice / 2


# -- signed and triangle areas ----------------------------------------------------------------
def test_signed_area_of_the_unit_right_triangle() -> None:
    """(0,0), (1,0), (0,1) has area 1/2 counter-clockwise and -1/2 clockwise."""
    a, b, c = point2(0, 0), point2(1, 0), point2(0, 1)
    assert signed_area(a, b, c) == mpq(1, 2)
    assert signed_area(a, c, b) == mpq(-1, 2)
    assert signed_area(a, b, point2(2, 0)) == 0


def test_signed_area_is_exact_far_below_double_precision() -> None:
    """A triangle of legs 2^-600 and 3^-300 has area exactly their product over two."""
    leg, other = mpq(1, 2**600), mpq(1, 3**300)
    area = signed_area(point2(1, 1), point2(1 + leg, 1), point2(1, 1 + other))
    assert area == leg * other / 2 and area > 0


@FEW
@given(exact_points, exact_points, exact_points)
def test_signed_area_follows_the_orientation(a: Point2, b: Point2, c: Point2) -> None:
    """The sign is orient2d's; rotating keeps it, swapping two vertices negates it, and
    translating changes nothing."""
    area = signed_area(a, b, c)
    expected = {Orientation.COUNTERCLOCKWISE: 1, Orientation.COLLINEAR: 0,
                Orientation.CLOCKWISE: -1}[orient2d(a, b, c)]
    assert (area > 0) - (area < 0) == expected
    assert signed_area(b, c, a) == area == signed_area(c, a, b)
    assert signed_area(b, a, c) == -area
    d = point2(mpq(7, 3), mpq(-5, 11))
    moved = [point2(p.x + d.x, p.y + d.y) for p in (a, b, c)]
    assert signed_area(*moved) == area


def test_triangle_area_reads_the_mesh_points() -> None:
    """triangle_area is the signed area of the mesh triangle, in any rotation."""
    mesh = square_with_centre()
    assert triangle_area(mesh, (0, 1, 4)) == 1
    assert triangle_area(mesh, (4, 0, 1)) == 1
    assert triangle_area(mesh, (0, 4, 1)) == -1


# -- total and enclosed areas -----------------------------------------------------------------
def test_total_area_of_known_meshes() -> None:
    """A 2x2 square has area 4, the annulus 9 - 1 = 8, the empty mesh 0."""
    assert total_area(square_with_centre()) == 4
    assert total_area(annulus()) == 8
    assert total_area(empty_mesh()) == 0


def test_a_hole_counts_negatively_in_the_enclosed_area() -> None:
    """The boundary of the annulus encloses 9 (outer loop) - 1 (inner loop, clockwise)."""
    ring = annulus()
    assert boundary_enclosed_area(ring) == 8 == total_area(ring)
    inner = [(u, v) for u, v in ring.boundary_edges() if u >= 4]
    assert sorted(inner) == [(4, 7), (5, 4), (6, 5), (7, 6)]  # the hole's loop, clockwise
    twice = sum((ring.point(u).x * ring.point(v).y - ring.point(v).x * ring.point(u).y
                 for u, v in inner), mpq(0))
    assert twice / 2 == -1


@FEW
@given(meshes_with_traces(max_steps=20))
def test_areas_after_random_steps_equal_the_polygon_area(
    case: tuple[Mesh2, Mesh2, Trace],
) -> None:
    """After any steps, the total area, the sum of triangle areas and the boundary-enclosed
    area all equal the shoelace area of the starting convex polygon, exactly."""
    start, end, _ = case
    polygon = [start.point(i) for i in range(start.vertex_count)]
    area = shoelace(polygon)
    assert area > 0
    assert total_area(end) == area
    assert sum((triangle_area(end, t) for t in end.triangles()), mpq(0)) == area
    assert boundary_enclosed_area(end) == area


# -- angles -----------------------------------------------------------------------------------
def test_angles_of_a_right_isosceles_triangle() -> None:
    """The right isosceles triangle has angles 90, 45, 45 (at a, b, c)."""
    assert triangle_angles_degrees(point2(0, 0), point2(1, 0), point2(0, 1)) == (90.0, 45.0, 45.0)


def test_angles_of_a_degenerate_triangle() -> None:
    """Three collinear points, c between a and b: angles 0, 0 and 180."""
    assert triangle_angles_degrees(point2(0, 0), point2(2, 0), point2(1, 0)) == (0.0, 0.0, 180.0)


@FEW
@given(exact_points, exact_points, exact_points)
def test_angles_do_not_depend_on_orientation(a: Point2, b: Point2, c: Point2) -> None:
    """Reversing the triangle permutes its angles and changes none of them."""
    at_a, at_b, at_c = triangle_angles_degrees(a, b, c)
    assert triangle_angles_degrees(a, c, b) == (at_a, at_c, at_b)
    assert triangle_angles_degrees(b, c, a) == (at_b, at_c, at_a)


@pytest.mark.parametrize("exponent", [-100, -20, 20, 100])
def test_angles_do_not_change_under_power_of_two_scaling(exponent: int) -> None:
    """Scaling a triangle by 2^k (exact in floating point, within range) gives exactly the
    same angles."""
    scale = mpq(2) ** exponent
    corners = [(0, 0), (3, 1), (1, 4)]
    base = triangle_angles_degrees(*(point2(x, y) for x, y in corners))
    scaled = triangle_angles_degrees(*(point2(x * scale, y * scale) for x, y in corners))
    assert scaled == base


@pytest.mark.parametrize("exponent", [-1100, -600, 600, 1100])
def test_angles_of_a_tiny_or_huge_triangle_are_its_angles(exponent: int) -> None:
    """A triangle scaled by 2^±600 keeps its angles."""
    scale = mpq(2) ** exponent
    corners = [(0, 0), (3, 1), (1, 4)]
    base = triangle_angles_degrees(*(point2(x, y) for x, y in corners))
    scaled = triangle_angles_degrees(*(point2(x * scale, y * scale) for x, y in corners))
    assert scaled == base


# -- the summary ------------------------------------------------------------------------------
def test_summary_of_a_square() -> None:
    """The square fanned from its centre: counts, angles 45..90, areas 1, total "4",
    Delaunay, and the digest text."""
    mesh = square_with_centre()
    summary = mesh_summary(mesh)
    assert set(summary) == SUMMARY_KEYS
    assert summary == {
        "vertices": 5, "triangles": 4, "edges": 8, "boundary_edges": 4,
        "constrained_edges": 4, "min_angle_deg": 45.0, "max_angle_deg": 90.0,
        "min_area": 1.0, "max_area": 1.0, "mean_area": 1.0, "total_area": "4",
        "is_delaunay": True, "digest": mesh.digest_text,
    }


def test_summary_writes_the_total_area_exactly() -> None:
    """A total with a finite decimal expansion is written as that decimal, another as p/q;
    the min/max/mean areas are the nearest doubles."""
    eighth = mesh_from_triangles([(0, 0), ("0.5", 0), (0, "0.5")], [(0, 1, 2)])
    assert mesh_summary(eighth)["total_area"] == "0.125"
    third = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, mpq(1, 3))],
                                [(0, 1, 2), (0, 2, 3)])
    summary = mesh_summary(third)
    assert summary["total_area"] == "2/3"
    assert summary["min_area"] == to_float(mpq(1, 6)) and summary["max_area"] == 0.5
    assert summary["mean_area"] == to_float(mpq(1, 3))


def test_summary_reports_a_non_delaunay_mesh() -> None:
    """A rhombus split along its long diagonal is not Delaunay."""
    mesh = mesh_from_triangles([(0, 0), (2, -1), (4, 0), (2, 1)], [(0, 1, 2), (0, 2, 3)])
    assert mesh_summary(mesh)["is_delaunay"] is False


@pytest.mark.parametrize(
    "mesh",
    [empty_mesh(), mesh_from_triangles([(0, 0), (1, 0), (5, 5)], [])],
    ids=["empty", "vertices only"],
)
def test_summary_of_a_mesh_without_triangles(mesh: Mesh2) -> None:
    """Without triangles, angle and area entries are None and the total is "0"."""
    summary = mesh_summary(mesh)
    assert set(summary) == SUMMARY_KEYS
    for key in ("min_angle_deg", "max_angle_deg", "min_area", "max_area", "mean_area"):
        assert summary[key] is None
    assert summary["total_area"] == "0" and summary["triangles"] == 0
    assert summary["vertices"] == mesh.vertex_count and summary["edges"] == 0


@FEW
@given(meshes_with_traces(max_steps=20))
def test_summary_agrees_with_the_mesh(case: tuple[Mesh2, Mesh2, Trace]) -> None:
    """Every entry agrees with the mesh's own queries and exact measures, and the summary is
    JSON."""
    mesh = case[1]
    summary = mesh_summary(mesh)
    areas = [triangle_area(mesh, t) for t in mesh.triangles()]
    assert summary["vertices"] == mesh.vertex_count
    assert summary["triangles"] == mesh.triangle_count == len(areas)
    assert summary["edges"] == len(mesh.edges())
    assert summary["boundary_edges"] == len(mesh.boundary_edges())
    assert summary["constrained_edges"] == len(mesh.segment_list())
    assert parse_rational(summary["total_area"]) == total_area(mesh)
    assert summary["total_area"] == format_rational(total_area(mesh))
    assert summary["min_area"] == to_float(min(areas))
    assert summary["max_area"] == to_float(max(areas))
    assert summary["mean_area"] == to_float(total_area(mesh) / len(areas))
    assert 0 < summary["min_angle_deg"] <= 60 <= summary["max_angle_deg"] < 180
    assert summary["is_delaunay"] == is_delaunay(mesh)
    assert summary["digest"] == mesh.digest_text
    assert json.loads(json.dumps(summary)) == summary


def test_summary_of_a_mesh_with_huge_coordinates() -> None:
    """A valid mesh with coordinates near 1e200 (areas near 1e400) still gets a report:
    its areas beyond the doubles as exact text, its angles right."""
    big = mpq(10) ** 200
    mesh = mesh_from_triangles([(0, 0), (big, 0), (0, big)], [(0, 1, 2)])
    summary = mesh_summary(mesh)
    assert summary["total_area"] == format_rational(big * big / 2)
    assert summary["min_area"] == summary["max_area"] == format_rational(big * big / 2)
    assert summary["min_angle_deg"] == 45.0 and summary["max_angle_deg"] == 90.0


@pytest.mark.parametrize("scale", [mpq(10) ** -400, mpq(2) ** -1074, mpq(10) ** -200,
                                   mpq(1, 3), mpq(10) ** 309, mpq(10) ** 200_000])
def test_summary_reports_areas_below_the_normal_doubles_exactly(scale: object) -> None:
    """An area whose nearest double is 0 or subnormal is reported as its exact text (not
    0, a wrong number), one beyond the doubles too; a normal one as the double."""
    mesh = mesh_from_triangles([(0, 0), (3 * scale, scale), (scale, 4 * scale)], [(0, 1, 2)])
    area = mpq(11, 2) * scale * scale
    summary = mesh_summary(mesh)
    normal = 2.0**-1022 <= abs(area) < 2**1024
    assert summary["min_area"] == (to_float(area) if normal else format_rational(area))
    assert round(summary["min_angle_deg"], 9) == 47.726310994


@pytest.mark.parametrize("exponent", [-1330, -1074, -600, 0, 600, 1100, 1330, 700_000])
def test_atan2_degrees_at_any_magnitude(exponent: int) -> None:
    scale = mpq(2) ** exponent
    assert atan2_degrees(scale, scale) == 45.0
    assert atan2_degrees(-scale, 0 * scale) == -90.0
    assert atan2_degrees(0 * scale, -scale) == 180.0
    assert atan2_degrees(scale * 3, scale * 4) == atan2_degrees(mpq(3), mpq(4))
