"""Refinement criteria and regions: exact decisions at their thresholds and borders,
priority keys, argument checks (``specs/refine.md``)."""

from __future__ import annotations

import doctest
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from geomexact import PreconditionError, mpq, point2
from geomexact.kernel.angles import angle_degrees
from geomexact.kernel.points import Point2
from geomexact.mesh2d.refinement import criteria as criteria_module
from geomexact.mesh2d.refinement import regions as regions_module
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    CallableCriterion,
    Criterion,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
    as_criterion,
    doubled_area,
    smallest_angle_cos2,
)
from geomexact.mesh2d.refinement.regions import (
    CallableRegion,
    Circle,
    Polygon,
    Rectangle,
    Region,
    Whole,
    as_region,
)
from geomexact.strategies import rationals

A, B, C = point2(0, 0), point2(2, 0), point2(0, 1)  # area 1, angles 90, ~26.57, ~63.43


def test_module_doctests() -> None:
    """The examples in the criteria and regions docstrings hold."""
    for module in (criteria_module, regions_module):
        assert doctest.testmod(module).failed == 0


# -- criteria -------------------------------------------------------------------------------
def test_max_area_is_exact_at_the_threshold() -> None:
    """Area equal to the maximum is accepted; a hair above is not; the key is −2·area."""
    assert MaxArea(1).rate(A, B, C) is None
    assert MaxArea(mpq(1) - mpq(1, 10**30)).rate(A, B, C) == -2
    assert MaxArea("0.5").rate(A, B, C) == -2


def test_max_area_key_orders_larger_triangles_first() -> None:
    """A larger triangle has a smaller key."""
    big = MaxArea("0.1").rate(A, point2(4, 0), C)
    small = MaxArea("0.1").rate(A, B, C)
    assert big is not None and small is not None and big < small


@pytest.mark.parametrize(
    "make", [lambda: MaxArea(0), lambda: MaxArea(-1), lambda: MaxEdgeLength("0"),
             lambda: AverageAreaFactor(0), lambda: MinAngle(0), lambda: MinAngle(60),
             lambda: MinAngle("75.5")],
)
def test_criteria_refuse_values_out_of_range(make: object) -> None:
    """Non-positive sizes and factors, angles outside (0°, 60°) are refused."""
    with pytest.raises(PreconditionError):
        make()  # type: ignore[operator]


def test_min_angle_accepts_exactly_the_threshold_when_cos2_is_rational() -> None:
    """45° is an exact threshold: a right isosceles triangle is acceptable at 45° and not
    at 45° plus a hair."""
    a, b, c = point2(0, 0), point2(1, 0), point2(1, 1)  # 45°, 90°, 45°
    assert MinAngle(45).rate(a, b, c) is None
    assert MinAngle(mpq(45) + mpq(1, 10**20)).rate(a, b, c) is not None


@given(st.integers(1, 59), st.integers(1, 50), st.integers(-50, 50), st.integers(1, 50))
def test_min_angle_never_accepts_an_angle_below_the_threshold(
    degrees: int, x: int, y: int, height: int
) -> None:
    """Accepted triangles have every angle >= θ (checked in high precision); rejected
    ones have a smaller angle or one within 1e-9° of θ (an inexact threshold)."""
    a, b, c = point2(0, 0), point2(x, 0), point2(y, height)
    criterion = MinAngle(degrees)
    smallest = min(angle_degrees(c, a, b), angle_degrees(a, b, c), angle_degrees(b, c, a))
    if criterion.rate(a, b, c) is None:
        assert smallest >= degrees - 1e-9
    else:
        assert smallest < degrees + 1e-9


def test_min_angle_key_is_minus_cos2_of_the_smallest_angle() -> None:
    """The key orders sharper triangles first and equals −cos² of the smallest angle."""
    sharp = (point2(0, 0), point2(10, 0), point2(0, 1))
    mild = (point2(0, 0), point2(3, 0), point2(0, 1))
    key_sharp = MinAngle(30).rate(*sharp)
    key_mild = MinAngle(30).rate(*mild)
    assert key_sharp is not None and key_mild is not None and key_sharp < key_mild
    assert key_sharp == -smallest_angle_cos2(*sharp) == -mpq(100, 101)
    smallest = angle_degrees(sharp[0], sharp[1], sharp[2])  # at (10, 0)
    assert math.isclose(math.degrees(math.acos(math.sqrt(100 / 101))), smallest)


@given(st.permutations([0, 1, 2]), st.integers(1, 40), st.integers(-40, 40), st.integers(1, 40))
def test_min_angle_does_not_depend_on_the_rotation(
    order: list[int], x: int, y: int, height: int
) -> None:
    """The same triangle given from another corner gets the same rating."""
    points = [point2(0, 0), point2(x, 0), point2(y, height)]
    rotated = [points[(order[0] + k) % 3] for k in range(3)]
    criterion = MinAngle(30)
    assert criterion.rate(*points) == criterion.rate(*rotated)


def test_max_edge_length_compares_squared_lengths() -> None:
    """The longest edge BC has |BC|² = 5: 2.3 (5.29) accepts it, 2.2 (4.84) does not;
    the key is −|BC|²."""
    assert MaxEdgeLength(3).rate(A, B, C) is None
    assert MaxEdgeLength("2.3").rate(A, B, C) is None
    assert MaxEdgeLength("2.2").rate(A, B, C) == -5


def test_max_edge_length_is_exactly_at_the_threshold() -> None:
    """An edge exactly as long as the maximum is accepted."""
    a, b, c = point2(0, 0), point2(3, 0), point2(0, 4)  # longest edge 5
    assert MaxEdgeLength(5).rate(a, b, c) is None
    assert MaxEdgeLength(mpq(5) - mpq(1, 10**40)).rate(a, b, c) == -25


def test_average_area_factor_rates_every_triangle_and_sets_a_mean_target() -> None:
    """Every triangle is a candidate (largest first); the target is factor × mean."""
    criterion = AverageAreaFactor("0.25")
    assert criterion.rate(A, B, C) == -2
    assert criterion.target_mean_area(mpq(10), 4) == mpq(10, 16)
    assert criterion.target_mean_area(mpq(0), 0) == 0
    assert MaxArea(1).target_mean_area(mpq(10), 4) is None


def test_callable_criterion_uses_the_test_and_an_optional_priority() -> None:
    """A plain function becomes a criterion: bad when true, key −2·area by default."""
    def wide(a: Point2, b: Point2, c: Point2) -> bool:
        return bool(max(p.x for p in (a, b, c)) - min(p.x for p in (a, b, c)) > 1)

    criterion = as_criterion(wide)
    assert isinstance(criterion, CallableCriterion)
    assert criterion.rate(A, B, C) == -2
    assert criterion.rate(A, point2(1, 0), C) is None
    assert criterion.parameters() == {"kind": "callable", "name": wide.__qualname__}
    ranked = CallableCriterion(wide, priority=lambda a, b, c: (a.x, b.x))
    assert ranked.rate(A, B, C) == (0, 2)
    assert ranked.angle_threshold is None


def test_as_criterion_refuses_other_values() -> None:
    """Neither a criterion nor a callable: TypeError."""
    with pytest.raises(TypeError):
        as_criterion(3)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "criterion",
    [MaxArea("0.1"), AverageAreaFactor(2), MinAngle(25), MaxEdgeLength("1/3"),
     CallableCriterion(lambda a, b, c: True, name="always")],
)
def test_criteria_follow_the_protocol_and_describe_themselves(criterion: Criterion) -> None:
    """Each criterion is a Criterion and its parameters are JSON with exact text."""
    import json

    assert isinstance(criterion, Criterion)
    text = json.dumps(criterion.parameters())
    assert "kind" in json.loads(text)


def test_doubled_area_is_signed() -> None:
    """Counter-clockwise positive, clockwise negative."""
    assert doubled_area(A, B, C) == 2
    assert doubled_area(A, C, B) == -2


# -- regions --------------------------------------------------------------------------------
def test_circle_counts_its_border_as_inside() -> None:
    """(0.6, 0.8) is exactly on the unit circle."""
    circle = Circle(0, 0, 1)
    assert circle.contains(point2("0.6", "0.8"))
    assert not circle.contains(point2("0.6", mpq(8, 10) + mpq(1, 10**30)))
    with pytest.raises(PreconditionError):
        Circle(0, 0, 0)


def test_rectangle_counts_its_border_as_inside() -> None:
    """Corners and edges belong to the rectangle."""
    rectangle = Rectangle("0.1", 0, 2, 1)
    assert rectangle.contains(point2("0.1", 0))
    assert rectangle.contains(point2("2.1", 1))
    assert not rectangle.contains(point2("2.1", mpq(1) + mpq(1, 10**30)))
    with pytest.raises(PreconditionError):
        Rectangle(0, 0, 0, 1)


def test_polygon_contains_interior_and_border_points_only() -> None:
    """A non-convex polygon (an L): inside, on edges, on vertices, in the notch."""
    ell = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    assert ell.contains(point2("0.5", "0.5"))
    assert ell.contains(point2("0.5", "1.5"))
    assert not ell.contains(point2("1.5", "1.5"))  # the notch
    assert ell.contains(point2(1, "1.5"))  # on an edge of the notch
    assert ell.contains(point2(2, 1))  # a vertex
    assert ell.contains(point2(1, 1))  # the reflex vertex
    assert not ell.contains(point2(3, 0))
    assert not ell.contains(point2(-1, 1))  # on the line of an edge, outside


@given(rationals(max_numerator=40, max_denominator=8), rationals(max_numerator=40,
       max_denominator=8))
def test_polygon_agrees_with_rectangle_for_a_rectangle(x: object, y: object) -> None:
    """A rectangle given as a polygon (either orientation) decides like Rectangle."""
    point = point2(x, y)
    rectangle = Rectangle(-1, -2, 3, 4)
    corners = [(-1, -2), (2, -2), (2, 2), (-1, 2)]
    assert Polygon(corners).contains(point) == rectangle.contains(point)
    assert Polygon(corners[::-1]).contains(point) == rectangle.contains(point)


def test_polygon_even_odd_rule_for_a_self_intersecting_polygon() -> None:
    """A bow-tie: both lobes inside, the outside beyond the crossing outside."""
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    assert bowtie.contains(point2("0.2", 1))
    assert bowtie.contains(point2("1.8", 1))
    assert bowtie.contains(point2(1, 1))  # the crossing is on the border
    assert not bowtie.contains(point2(1, "0.2"))


def test_polygon_refuses_degenerate_input() -> None:
    """Fewer than 3 distinct vertices, or all collinear."""
    with pytest.raises(PreconditionError):
        Polygon([(0, 0), (1, 1), (0, 0)])
    with pytest.raises(PreconditionError):
        Polygon([(0, 0), (1, 1), (2, 2)])


def test_whole_callable_and_as_region() -> None:
    """None is the whole plane; a function becomes a CallableRegion."""
    assert isinstance(as_region(None), Whole)
    assert Whole().contains(point2(10**9, -(10**9)))
    region = as_region(lambda p: p.x > 0)
    assert isinstance(region, CallableRegion)
    assert region.contains(point2(1, 0)) and not region.contains(point2(0, 0))
    circle = Circle(0, 0, 1)
    assert as_region(circle) is circle
    with pytest.raises(TypeError):
        as_region(5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "region",
    [Whole(), Circle("0.5", 0, "1/3"), Rectangle(0, 0, 1, 1), Polygon([(0, 0), (1, 0), (0, 1)]),
     CallableRegion(lambda p: True, name="all")],
)
def test_regions_follow_the_protocol_and_describe_themselves(region: Region) -> None:
    """Each region is a Region and its parameters are JSON."""
    import json

    assert isinstance(region, Region)
    assert json.loads(json.dumps(region.parameters()))["kind"]
