"""Exact points (``geomexact.kernel.points``): exact conversion of coordinates, the nearest
doubles kept for the filters (``nan`` beyond the double range), equality and hashing by
exact coordinates only, and exact midpoints."""

from __future__ import annotations

import math
import sys
from fractions import Fraction

import pytest
from hypothesis import given, settings

from geomexact.errors import RationalParseError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, Point3, midpoint2, midpoint3, point2, point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.strategies import coordinates, points2, points3, rationals

FEW = settings(max_examples=min(settings().max_examples, 60))


def nearest_double(value: mpq) -> float:
    """The double nearest to ``value``: Python's int/int division is correctly rounded."""
    return int(value.numerator) / int(value.denominator)


# -- construction ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("raw", "exact"),
    [
        ("0.1", mpq(1, 10)),
        ("-2.75", mpq(-11, 4)),
        ("3/9", mpq(1, 3)),
        ("1e-3", mpq(1, 1000)),
        (7, mpq(7)),
        (Fraction(2, 6), mpq(1, 3)),
        (mpq(5, 10), mpq(1, 2)),
        (0.1, mpq(3602879701896397, 36028797018963968)),  # the exact binary value of 0.1
    ],
)
def test_point2_converts_coordinates_exactly(raw: object, exact: mpq) -> None:
    """Text, ints, Fractions, mpq and floats become their exact rational value."""
    p = point2(raw, raw)
    assert p.x == exact and p.y == exact
    assert type(p.x) is type(mpq(0)) and type(p.y) is type(mpq(0))


def test_point3_converts_coordinates_exactly() -> None:
    """point3 converts each coordinate exactly, like point2."""
    p = point3("0.1", 2, 0.5)
    assert (p.x, p.y, p.z) == (mpq(1, 10), mpq(2), mpq(1, 2))
    assert (p.fx, p.fy, p.fz) == (0.1, 2.0, 0.5)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, True, "abc", "1/0", None])
def test_points_refuse_values_that_are_not_exact_numbers(bad: object) -> None:
    """nan, infinities, bools, unreadable text and None are not coordinates."""
    with pytest.raises(RationalParseError):
        point2(bad, 0)
    with pytest.raises(RationalParseError):
        point3(0, 0, bad)


@FEW
@given(coordinates(), coordinates())
def test_point2_keeps_the_nearest_doubles(x: mpq, y: mpq) -> None:
    """fx, fy are the doubles nearest to x, y; nan when a coordinate is beyond the double
    range (so the predicates take their exact path)."""
    p = point2(x, y)
    for exact, approx in ((x, p.fx), (y, p.fy)):
        try:
            expected = nearest_double(exact)
        except OverflowError:
            assert math.isnan(approx)
        else:
            assert approx == expected


@FEW
@given(coordinates(), coordinates(), coordinates())
def test_point3_keeps_the_nearest_doubles(x: mpq, y: mpq, z: mpq) -> None:
    """fx, fy, fz are the nearest doubles of x, y, z (nan beyond the double range)."""
    p = point3(x, y, z)
    for exact, approx in ((x, p.fx), (y, p.fy), (z, p.fz)):
        try:
            expected = nearest_double(exact)
        except OverflowError:
            assert math.isnan(approx)
        else:
            assert approx == expected


def test_doubles_at_the_edges_of_the_double_range() -> None:
    """The largest double stays finite, half an ulp beyond it is nan, and values below the
    smallest subnormal round to zero (with their sign) or to the smallest subnormal."""
    largest = mpq(sys.float_info.max)
    ulp = mpq(2) ** (1023 - 52)
    assert point2(largest, 0).fx == sys.float_info.max
    assert point2(largest + ulp / 4, 0).fx == sys.float_info.max
    assert math.isnan(point2(largest + ulp / 2, 0).fx)
    assert math.isnan(point2(0, -(largest + ulp)).fy)
    tiny = mpq(2) ** -1074
    assert point2(tiny / 4, 0).fx == 0.0
    assert math.copysign(1.0, point2(-tiny / 4, 0).fx) == -1.0
    assert point2(tiny * 3 / 4, 0).fx == 5e-324
    assert point2(mpq(1, 10**400), 0).fx == 0.0


# -- equality and hashing ---------------------------------------------------------------------
def test_equality_ignores_the_doubles() -> None:
    """Two points with the same exact coordinates are equal whatever their doubles."""
    exact = point2(mpq(1, 3), 2)
    stale = Point2(exact.x, exact.y, 123.0, math.nan)
    assert exact == stale
    assert not exact != stale  # noqa: SIM202 (__ne__ is overridden too)
    assert hash(exact) == hash(stale)
    assert {exact, stale} == {exact}


def test_points_beyond_the_double_range_equal_themselves() -> None:
    """A point whose doubles are nan still equals an equal point (nan != nan does not leak
    into point equality) and hashes like it."""
    p, q = point2(mpq(10) ** 400, 1), point2(mpq(10) ** 400, 1)
    assert math.isnan(p.fx)
    assert p == q and hash(p) == hash(q)
    assert len({p, q}) == 1
    r = point3(1, mpq(-10) ** 401, 2)
    assert r == point3(1, mpq(-10) ** 401, 2)


def test_points_differing_by_one_exact_coordinate_are_unequal() -> None:
    """A difference far below double precision still makes two points unequal."""
    a = point2(1, 1)
    b = point2(1 + mpq(1, 2**200), 1)
    assert a.fx == b.fx and a.fy == b.fy
    assert a != b
    assert not a == b  # noqa: SIM201 (__eq__ is overridden too)
    c, d = point3(0, 0, 1), point3(0, 0, 1 + mpq(1, 2**200))
    assert c != d


def test_points_are_not_equal_to_plain_tuples_or_other_dimensions() -> None:
    """A Point2 equals only a Point2 (in either operand order), a Point3 only a Point3."""
    p = point2(1, 2)
    assert p != (p.x, p.y, p.fx, p.fy) and (p.x, p.y, p.fx, p.fy) != p
    assert p != (p.x, p.y)
    assert p != point3(1, 2, 0) and point3(1, 2, 0) != p
    q = point3(1, 2, 3)
    assert q != tuple(q)


@FEW
@given(points2(rationals()), points2(rationals()))
def test_point2_equality_is_exact_coordinate_equality(p: Point2, q: Point2) -> None:
    """p == q exactly when both coordinates are equal; equal points hash alike."""
    assert (p == q) == (p.x == q.x and p.y == q.y)
    assert (p != q) == (p.x != q.x or p.y != q.y)
    if p == q:
        assert hash(p) == hash(q)


@FEW
@given(points3(rationals(max_numerator=3, max_denominator=2)),
       points3(rationals(max_numerator=3, max_denominator=2)))
def test_point3_equality_is_exact_coordinate_equality(p: Point3, q: Point3) -> None:
    """p == q exactly when the three coordinates are equal; equal points hash alike."""
    assert (p == q) == (p.x == q.x and p.y == q.y and p.z == q.z)
    assert (p != q) == (p.x != q.x or p.y != q.y or p.z != q.z)
    if p == q:
        assert hash(p) == hash(q)


def test_the_first_two_fields_are_the_exact_coordinates() -> None:
    """``point[:2]`` (what the digest hashes) is the exact pair; unpacking gives all four."""
    p = point2("0.1", "-0.5")
    assert p[:2] == (mpq(1, 10), mpq(-1, 2))
    x, y, fx, fy = p
    assert (x, y, fx, fy) == (mpq(1, 10), mpq(-1, 2), 0.1, -0.5)
    assert point3(1, 2, 3)[:3] == (1, 2, 3)


def test_repr_shows_the_exact_coordinates() -> None:
    """repr prints the exact rationals, not the doubles."""
    assert repr(point2(mpq(1, 3), -2)) == "Point2(1/3, -2)"
    assert repr(point3(mpq(1, 10), 0, 5)) == "Point3(1/10, 0, 5)"


# -- midpoints -----------------------------------------------------------------------------
@FEW
@given(points2(), points2())
def test_midpoint2_is_exact(a: Point2, b: Point2) -> None:
    """The midpoint is exactly (a + b) / 2: on line ab, at equal squared distance from a and
    b, and its doubles are those of the exact midpoint."""
    m = midpoint2(a, b)
    assert 2 * m.x == a.x + b.x and 2 * m.y == a.y + b.y
    assert orient2d(a, b, m) == Orientation.COLLINEAR
    assert (m.x - a.x) ** 2 + (m.y - a.y) ** 2 == (m.x - b.x) ** 2 + (m.y - b.y) ** 2
    try:
        assert m.fx == nearest_double(m.x)
    except OverflowError:
        assert math.isnan(m.fx)


@FEW
@given(points3(), points3())
def test_midpoint3_is_exact(a: Point3, b: Point3) -> None:
    """The midpoint is exactly (a + b) / 2 in each coordinate."""
    m = midpoint3(a, b)
    assert (2 * m.x, 2 * m.y, 2 * m.z) == (a.x + b.x, a.y + b.y, a.z + b.z)


def test_midpoint_of_a_point_with_itself_is_the_point() -> None:
    """midpoint(a, a) == a."""
    a = point2(mpq(1, 3), mpq(-7, 5))
    assert midpoint2(a, a) == a
    b = point3(mpq(1, 3), 0, 9)
    assert midpoint3(b, b) == b


def test_midpoint_beyond_the_double_range_is_finite_again() -> None:
    """The doubles of a midpoint are recomputed from its exact value: the midpoint of
    1e400 and -1e400 is the origin, with finite doubles."""
    big = mpq(10) ** 400
    m = midpoint2(point2(big, big), point2(-big, -big))
    assert (m.x, m.y, m.fx, m.fy) == (0, 0, 0.0, 0.0)
