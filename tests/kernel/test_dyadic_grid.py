"""The dyadic grid (exact float fast paths): membership, midpoints, and the exactness of
degree-2 expressions in floats on it; the refinement engines agree on grid inputs."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from geomexact import mpq
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.dyadic_grid import GRID_BITS, grid_flags, grid_unit, midpoint_on_grid, on_grid
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.transient import mesh_from_triangles

LIMIT = 2**GRID_BITS


def test_unit_is_chosen_from_the_largest_coordinate() -> None:
    assert grid_unit([point2(0, 0), point2(1, "1/2")]) == 2.0 ** (GRID_BITS - 1)
    assert grid_unit([point2(-3, 0)]) == 2.0 ** (GRID_BITS - 2)
    assert grid_unit([point2("3/4", 0)]) == 2.0**GRID_BITS
    assert grid_unit([point2(0, 0)]) is None
    assert grid_unit([]) is None
    assert grid_unit([point2(mpq(2) ** 600, 0)]) is None  # products would overflow
    assert grid_unit([point2(mpq(1, 2**600), 0)]) is None  # unit² would underflow


def test_membership_is_exact() -> None:
    scale = grid_unit([point2(1, 1)])
    assert scale is not None
    assert on_grid(point2("1/2", "3/1024"), scale)
    assert not on_grid(point2("1/3", 0), scale)  # its float is not its value
    assert not on_grid(point2(mpq(1, 2**40), 0), scale)  # a float, but finer than the unit
    assert not on_grid(point2(0, 0), None)
    scale, flags = grid_flags([point2(1, 1), point2("1/10", 0), point2("5/8", "1/4")])
    assert flags == [True, False, True]


def grid_points(exponent: int) -> st.SearchStrategy[Point2]:
    """Points of the grid for inputs below 2^exponent: integers below 2^GRID_BITS units."""
    unit = mpq(2) ** (exponent - GRID_BITS)
    coordinate = st.integers(-(LIMIT - 1), LIMIT - 1).map(lambda k: k * unit)
    return st.builds(point2, coordinate, coordinate)


@given(st.integers(-60, 60).flatmap(lambda e: st.tuples(st.just(e), *[grid_points(e)] * 4)))
def test_squared_lengths_compare_exactly_in_floats_on_the_grid(
    case: tuple[int, Point2, Point2, Point2, Point2],
) -> None:
    exponent, a, b, c, d = case
    scale = math.ldexp(1.0, GRID_BITS - exponent)
    assert all(on_grid(p, scale) for p in (a, b, c, d))

    def in_floats(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
        ux, uy, vx, vy = b.fx - a.fx, b.fy - a.fy, d.fx - c.fx, d.fy - c.fy
        first, second = ux * ux + uy * uy, vx * vx + vy * vy
        return (first > second) - (first < second)

    assert in_floats(a, b, c, d) == compare_squared_lengths(a, b, c, d)
    assert in_floats(a, b, a, b) == 0


@given(st.integers(-60, 60).flatmap(lambda e: st.tuples(st.just(e), *[grid_points(e)] * 4)))
def test_dot_products_are_exact_in_floats_on_the_grid(
    case: tuple[int, Point2, Point2, Point2, Point2],
) -> None:
    _, p, a, b, _ = case
    exact = (a.x - p.x) * (b.x - p.x) + (a.y - p.y) * (b.y - p.y)
    floats = (a.fx - p.fx) * (b.fx - p.fx) + (a.fy - p.fy) * (b.fy - p.fy)
    assert mpq(floats) == exact


@given(st.integers(-60, 60).flatmap(lambda e: st.tuples(st.just(e), *[grid_points(e)] * 2)))
def test_a_midpoint_is_on_the_grid_exactly_when_its_coordinates_are(
    case: tuple[int, Point2, Point2],
) -> None:
    exponent, u, v = case
    scale = math.ldexp(1.0, GRID_BITS - exponent)
    middle = point2((u.x + v.x) / 2, (u.y + v.y) / 2)
    assert midpoint_on_grid(u, v, scale) == on_grid(middle, scale)


@given(st.integers(1, LIMIT - 1), st.integers(1, LIMIT - 1), st.booleans())
def test_engines_agree_on_boxes_at_the_grid_limit(width: int, height: int, delaunay: bool) -> None:
    """A box with integer corners up to 2^24 - 1 (on the grid, at its limit): the fast
    engine (float paths) and the reference engine (exact arithmetic) record the same run."""
    box = mesh_from_triangles(
        [(0, 0), (width, 0), (width, height), (0, height)], [(0, 1, 2), (0, 2, 3)],
        [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)],
    )
    criterion = MaxArea(mpq(width * height, 40))
    fast = refine(box, criterion, delaunay=delaunay)
    reference = refine(box, criterion, delaunay=delaunay, engine="reference")
    assert fast.trace == reference.trace
    assert fast.mesh == reference.mesh
