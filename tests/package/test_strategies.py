"""The public hypothesis strategies produce what they promise."""

from __future__ import annotations

from hypothesis import given

from geomexact import PSLG, Mesh2, Orientation, orient2d, validate
from geomexact.kernel.points import Point2
from geomexact.strategies import convex_polygons, pslgs, simple_polygons, triangulations


def _proper_crossing(p: Point2, q: Point2, r: Point2, s: Point2) -> bool:
    return (orient2d(p, q, r) * orient2d(p, q, s) <= 0) and (
        orient2d(r, s, p) * orient2d(r, s, q) <= 0
    )


@given(simple_polygons())
def test_simple_polygons_are_simple_and_counterclockwise(polygon: list[Point2]) -> None:
    n = len(polygon)
    area2 = sum(polygon[i].x * polygon[(i + 1) % n].y - polygon[(i + 1) % n].x * polygon[i].y
                for i in range(n))
    assert area2 > 0
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            assert not _proper_crossing(polygon[i], polygon[(i + 1) % n],
                                        polygon[j], polygon[(j + 1) % n])


@given(convex_polygons())
def test_convex_polygons_are_strictly_convex(polygon: list[Point2]) -> None:
    n = len(polygon)
    for i in range(n):
        turn = orient2d(polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n])
        assert turn == Orientation.COUNTERCLOCKWISE


@given(triangulations())
def test_triangulations_are_valid(mesh: Mesh2) -> None:
    assert validate(mesh) == []


@given(pslgs())
def test_pslgs_have_distinct_vertices_and_valid_segments(pslg: PSLG) -> None:
    assert len(set(pslg.vertices)) == len(pslg.vertices)
    assert all(u != v for u, v, _ in pslg.segments)
