"""Adaptive exact predicates: the float filter never changes an answer, the sign
conventions are the documented ones, ties are exact, and the error-bound constants cover
the derivation in ``specs/predicates.md``."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction
from functools import cache

import pytest
import sympy
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from geomexact.errors import PreconditionError
from geomexact.kernel import filter_bounds as P
from geomexact.kernel.angles import AngleThreshold, angle_degrees, compare_angle
from geomexact.kernel.comparisons import compare_areas, compare_squared_lengths
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicate_results import (
    CircleLocation,
    Comparison,
    Orientation,
    SphereLocation,
)
from geomexact.kernel.predicates2d import incircle, incircle_exact, orient2d, orient2d_exact
from geomexact.kernel.predicates3d import insphere, insphere_exact, orient3d, orient3d_exact
from geomexact.strategies import (
    cocircular_quadruples,
    collinear_triples,
    coordinates,
    coplanar_quadruples,
    cospherical_quintuples,
    decimal_rationals,
    near_degenerate_points2,
    near_degenerate_points3,
    points2,
    points3,
    rationals,
)

FAST = settings(suppress_health_check=[HealthCheck.too_slow])

ordinary2 = points2(coordinates(("ordinary", "decimal", "dyadic")))
ordinary3 = points3(coordinates(("ordinary", "decimal", "dyadic")))
any2 = points2()
any3 = points3()


def sign(value: object) -> int:
    return int((value > 0) - (value < 0))  # type: ignore[operator]


def permuted(points: tuple[object, ...], order: tuple[int, ...]) -> tuple[object, ...]:
    return tuple(points[i] for i in order)


def permutation_parity(order: tuple[int, ...]) -> int:
    inversions = sum(
        1 for i, j in itertools.combinations(range(len(order)), 2) if order[i] > order[j]
    )
    return -1 if inversions % 2 else 1


# ---- the filter never changes an answer --------------------------------------------------


def assert_adaptive_is_exact2(points: tuple[Point2, ...]) -> None:
    for triple in itertools.permutations(points, 3):
        assert orient2d(*triple) == orient2d_exact(*triple)
    if len(points) >= 4:
        for quadruple in itertools.permutations(points[:4]):
            assert incircle(*quadruple) == incircle_exact(*quadruple)


def assert_adaptive_is_exact3(points: tuple[Point3, ...]) -> None:
    for quadruple in itertools.permutations(points[:4]):
        assert orient3d(*quadruple) == orient3d_exact(*quadruple)
    if len(points) >= 5:
        for order in itertools.islice(itertools.permutations(range(5)), 0, 120, 7):
            quintuple = permuted(points, order)
            assert insphere(*quintuple) == insphere_exact(*quintuple)  # type: ignore[arg-type]


@given(collinear_triples())
def test_adaptive_equals_exact_on_collinear_triples(triple: tuple[Point2, Point2, Point2]) -> None:
    assert_adaptive_is_exact2(triple)
    assert orient2d(*triple) == Orientation.COLLINEAR


@given(cocircular_quadruples())
def test_adaptive_equals_exact_on_cocircular_quadruples(points: tuple[Point2, ...]) -> None:
    assert_adaptive_is_exact2(points)
    assert incircle(*points) == CircleLocation.COCIRCULAR


@given(st.one_of(near_degenerate_points2(3), near_degenerate_points2(4)))
def test_adaptive_equals_exact_on_near_degenerate_points2(points: tuple[Point2, ...]) -> None:
    assert_adaptive_is_exact2(points)


@given(st.lists(any2, min_size=4, max_size=4))
def test_adaptive_equals_exact_on_points_of_every_magnitude2(points: list[Point2]) -> None:
    assert_adaptive_is_exact2(tuple(points))


@given(st.lists(points2(decimal_rationals(max_digits=3, max_places=3)), min_size=4, max_size=4))
def test_adaptive_equals_exact_on_decimal_grids(points: list[Point2]) -> None:
    """Small decimals (0.1, 0.25, ...) make many exact ties with inexact floats."""
    assert_adaptive_is_exact2(tuple(points))


@given(coplanar_quadruples())
def test_adaptive_equals_exact_on_coplanar_quadruples(points: tuple[Point3, ...]) -> None:
    assert_adaptive_is_exact3(points)
    assert orient3d(*points) == Orientation.COLLINEAR


@settings(max_examples=60)
@given(cospherical_quintuples())
def test_adaptive_equals_exact_on_cospherical_quintuples(points: tuple[Point3, ...]) -> None:
    assert_adaptive_is_exact3(points)
    assert insphere(*points) == SphereLocation.COSPHERICAL


@settings(max_examples=60)
@given(st.one_of(near_degenerate_points3(4), near_degenerate_points3(5)))
def test_adaptive_equals_exact_on_near_degenerate_points3(points: tuple[Point3, ...]) -> None:
    assert_adaptive_is_exact3(points)


@settings(max_examples=60)
@given(st.lists(any3, min_size=5, max_size=5))
def test_adaptive_equals_exact_on_points_of_every_magnitude3(points: list[Point3]) -> None:
    assert_adaptive_is_exact3(tuple(points))


def test_adaptive_equals_exact_when_subnormal_floats_meet_huge_differences() -> None:
    """Inputs whose floats are subnormal or flushed to zero carry an absolute, not a
    relative, rounding error; multiplied by huge differences it must stay covered."""
    tiny = [mpq(k, 10**320) for k in (1, 2, 3, 7)] + [mpq(1, 10**400), mpq(3, 10**330)]
    huge = [mpq(k) * mpq(10) ** 300 for k in (1, -1, 3)]
    values = tiny + huge + [mpq(0), mpq(1, 3)]
    for xs in itertools.product(values, repeat=2):
        a = point2(xs[0], xs[1])
        for b, c in itertools.product(
            [point2(tiny[0], tiny[2]), point2(huge[0], huge[0]), point2(tiny[1], huge[2])],
            [point2(tiny[3], tiny[1]), point2(huge[1], tiny[0]), point2(0, 0)],
        ):
            assert orient2d(a, b, c) == orient2d_exact(a, b, c)
            assert incircle(a, b, c, point2(tiny[4], tiny[5])) == incircle_exact(
                a, b, c, point2(tiny[4], tiny[5])
            )


# ---- exact versions follow the definitions -----------------------------------------------


def det(rows: list[list[Fraction]]) -> int:
    return int(sympy.sign(sympy.Matrix(rows).det()))


def rational(value: object) -> sympy.Rational:
    return sympy.Rational(str(value))


@settings(max_examples=40)
@given(st.lists(points2(rationals(max_numerator=20, max_denominator=4)), min_size=4, max_size=4))
def test_exact_orient2d_and_incircle_are_the_textbook_determinants(points: list[Point2]) -> None:
    a, b, c, d = points

    def row(p: Point2) -> list[Fraction]:
        x, y = rational(p.x - d.x), rational(p.y - d.y)
        return [x, y, x * x + y * y]

    vector = [[rational(p.x - a.x), rational(p.y - a.y)] for p in (b, c)]
    assert orient2d_exact(a, b, c) == det(vector)
    assert incircle_exact(a, b, c, d) == det([row(a), row(b), row(c)])


@settings(max_examples=40)
@given(st.lists(points3(rationals(max_numerator=20, max_denominator=4)), min_size=5, max_size=5))
def test_exact_orient3d_and_insphere_are_the_documented_determinants(points: list[Point3]) -> None:
    a, b, c, d, e = points
    vectors = [[rational(p[i] - a[i]) for i in range(3)] for p in (b, c, d)]
    assert orient3d_exact(a, b, c, d) == det(vectors)

    def row(p: Point3) -> list[Fraction]:
        v = [rational(p[i] - e[i]) for i in range(3)]
        return [*v, sum(x * x for x in v)]

    # positive when e is inside the sphere of a positively oriented abcd
    assert insphere_exact(a, b, c, d, e) == -det([row(a), row(b), row(c), row(d)])


def test_sign_conventions_on_unit_simplices() -> None:
    a, b, c = point2(0, 0), point2(1, 0), point2(0, 1)
    assert orient2d(a, b, c) == Orientation.COUNTERCLOCKWISE
    assert orient2d(a, c, b) == Orientation.CLOCKWISE
    assert incircle(a, b, c, point2("0.1", "0.1")) == CircleLocation.INSIDE
    assert incircle(a, c, b, point2("0.1", "0.1")) == CircleLocation.OUTSIDE  # clockwise flips
    assert incircle(a, b, c, point2(1, 1)) == CircleLocation.COCIRCULAR
    o, x, y, z = point3(0, 0, 0), point3(1, 0, 0), point3(0, 1, 0), point3(0, 0, 1)
    assert orient3d(o, x, y, z) == Orientation.COUNTERCLOCKWISE  # z above the ccw base
    assert orient3d(o, x, y, point3(0, 0, -1)) == Orientation.CLOCKWISE
    inside = point3("0.1", "0.1", "0.1")
    assert insphere(o, x, y, z, inside) == SphereLocation.INSIDE
    assert insphere(o, y, x, z, inside) == SphereLocation.OUTSIDE  # negative tetrahedron
    assert insphere(o, x, y, z, point3(1, 1, 0)) == SphereLocation.COSPHERICAL


def test_beyond_double_coordinates_use_the_exact_path() -> None:
    big = mpq(10) ** 400
    a, b, c = point2(big, 0), point2(0, big), point2(-big, 0)
    assert math.isnan(a.fx)
    P.reset_filter_counters()
    assert orient2d(a, b, c) == Orientation.COUNTERCLOCKWISE
    assert incircle(a, b, c, point2(0, -big)) == CircleLocation.COCIRCULAR
    assert P.filter_counters()["orient2d"] == (0, 1)


# ---- permutation symmetry ----------------------------------------------------------------


@given(st.one_of(near_degenerate_points2(4), st.tuples(any2, any2, any2, any2)))
def test_orient2d_and_incircle_are_alternating(points: tuple[Point2, ...]) -> None:
    """Odd permutations negate, even permutations keep the answer."""
    base3 = orient2d(*points[:3])
    for order in itertools.permutations(range(3)):
        assert orient2d(*permuted(points, order)) == base3 * permutation_parity(order)  # type: ignore[arg-type]
    base4 = incircle(*points)
    for order in itertools.permutations(range(4)):
        assert incircle(*permuted(points, order)) == base4 * permutation_parity(order)  # type: ignore[arg-type]


@settings(max_examples=50)
@given(st.one_of(near_degenerate_points3(5), st.tuples(any3, any3, any3, any3, any3)))
def test_orient3d_and_insphere_are_alternating(points: tuple[Point3, ...]) -> None:
    base4 = orient3d(*points[:4])
    for order in itertools.permutations(range(4)):
        assert orient3d(*permuted(points, order)) == base4 * permutation_parity(order)  # type: ignore[arg-type]
    base5 = insphere(*points)
    for order in itertools.permutations(range(5)):
        assert insphere(*permuted(points, order)) == base5 * permutation_parity(order)  # type: ignore[arg-type]


# ---- comparisons -------------------------------------------------------------------------


def pythagorean_rotation(m: int, n: int) -> tuple[Fraction, Fraction]:
    """cos and sin of an exact rational rotation."""
    return Fraction(m * m - n * n, m * m + n * n), Fraction(2 * m * n, m * m + n * n)


rotations = st.tuples(st.integers(1, 30), st.integers(0, 30)).map(
    lambda mn: pythagorean_rotation(*mn)
)


def rotate(p: Point2, rotation: tuple[Fraction, Fraction], center: Point2) -> Point2:
    cos, sin = rotation
    x, y = p.x - center.x, p.y - center.y
    return point2(center.x + cos * x - sin * y, center.y + sin * x + cos * y)


@given(st.lists(any2, min_size=4, max_size=4))
def test_compare_squared_lengths_agrees_with_exact_lengths2(points: list[Point2]) -> None:
    a, b, c, d = points
    expected = sign((b.x - a.x) ** 2 + (b.y - a.y) ** 2 - (d.x - c.x) ** 2 - (d.y - c.y) ** 2)
    assert compare_squared_lengths(a, b, c, d) == expected
    assert compare_squared_lengths(c, d, a, b) == -expected


@settings(max_examples=60)
@given(st.lists(any3, min_size=4, max_size=4))
def test_compare_squared_lengths_agrees_with_exact_lengths3(points: list[Point3]) -> None:
    a, b, c, d = points
    expected = sign(sum((b[i] - a[i]) ** 2 - (d[i] - c[i]) ** 2 for i in range(3)))
    assert compare_squared_lengths(a, b, c, d) == expected


@given(any2, any2, rotations, st.sampled_from([None, "ulp"]))
def test_compare_squared_lengths_is_exact_on_rotated_copies(
    a: Point2, b: Point2, rotation: tuple[Fraction, Fraction], nudge: str | None
) -> None:
    """A segment and its exact rotation have equal length (a tie the filter must not
    break); moving one end by a tiny amount gives the exact strict answer."""
    c, d = rotate(a, rotation, a), rotate(b, rotation, a)
    assert compare_squared_lengths(a, b, c, d) == Comparison.EQUAL
    if nudge and a != b:
        far = point2(b.x + (b.x - a.x) * mpq(1, 2**70), b.y + (b.y - a.y) * mpq(1, 2**70))
        assert compare_squared_lengths(a, far, c, d) == Comparison.GREATER
        assert compare_squared_lengths(c, d, a, far) == Comparison.LESS


@given(st.lists(any2, min_size=6, max_size=6))
def test_compare_areas_agrees_with_exact_areas(points: list[Point2]) -> None:
    a, b, c, d, e, f = points

    def doubled(p: Point2, q: Point2, r: Point2) -> object:
        return abs((p.x - r.x) * (q.y - r.y) - (p.y - r.y) * (q.x - r.x))

    expected = sign(doubled(a, b, c) - doubled(d, e, f))
    assert compare_areas(a, b, c, d, e, f) == expected
    assert compare_areas(c, a, b, f, e, d) == expected  # orientation does not matter


@given(any2, any2, any2, rationals(), rotations)
def test_compare_areas_is_exact_on_sheared_and_rotated_copies(
    a: Point2, b: Point2, c: Point2, shift: object, rotation: tuple[Fraction, Fraction]
) -> None:
    """Moving c parallel to ab keeps the area; so does an exact rotation."""
    sheared = point2(c.x + shift * (b.x - a.x), c.y + shift * (b.y - a.y))  # type: ignore[operator]
    assert compare_areas(a, b, c, a, b, sheared) == Comparison.EQUAL
    turned = [rotate(p, rotation, a) for p in (a, b, c)]
    assert compare_areas(a, b, c, *turned) == Comparison.EQUAL


# ---- angles ------------------------------------------------------------------------------

EXACT_DEGREES = (30, 45, 60, 90, 120, 135, 150)


def test_angle_thresholds_are_exact_exactly_for_the_niven_angles() -> None:
    for degrees in range(1, 180):
        threshold = AngleThreshold.from_degrees(degrees)
        assert threshold.exact == (degrees in EXACT_DEGREES)
    assert AngleThreshold.from_degrees(30).cos2 == mpq(3, 4)
    assert AngleThreshold.from_degrees("45").cos2 == mpq(1, 2)
    assert AngleThreshold.from_degrees(60.0).cos2 == mpq(1, 4)
    assert AngleThreshold.from_degrees(mpq(90)).cos2 == 0
    assert AngleThreshold.from_degrees(120).cos_sign == -1
    assert not AngleThreshold.from_degrees("30.000000000000000001").exact


@given(st.one_of(st.integers(1, 179), st.fractions(0, 180).filter(lambda f: 0 < f < 180)))
def test_inexact_thresholds_round_to_the_safe_side(degrees: object) -> None:
    threshold = AngleThreshold.from_degrees(Fraction(degrees))  # type: ignore[arg-type]
    if threshold.exact:
        return
    turn = sympy.Rational(Fraction(degrees).numerator, Fraction(degrees).denominator)  # type: ignore[arg-type]
    true = sympy.cos(sympy.pi * turn / 180) ** 2
    stored = sympy.Rational(int(threshold.cos2.numerator), int(threshold.cos2.denominator))
    gap = (stored - true).evalf(200)
    if threshold.cos_sign > 0:
        assert gap <= 0  # smaller cos^2: effective angle larger
    else:
        assert gap >= 0
    assert abs(gap) <= true.evalf(200) * sympy.Rational(1, 2**64)


@pytest.mark.parametrize("degrees", [0, 180, -5, 200, "nan", "abc"])
def test_angle_threshold_rejects_angles_outside_the_open_interval(degrees: object) -> None:
    with pytest.raises(ValueError, match=str(degrees) if degrees != "abc" else "abc"):
        AngleThreshold.from_degrees(degrees)


@cache
def reference_angle(u: tuple[Fraction, ...], v: tuple[Fraction, ...]) -> sympy.Float:
    """The angle between u and v in degrees with 80 correct digits (sympy)."""
    su = [sympy.Rational(x.numerator, x.denominator) for x in u]
    sv = [sympy.Rational(x.numerator, x.denominator) for x in v]
    dot = sum(x * y for x, y in zip(su, sv, strict=True))
    lengths = sum(x * x for x in su) * sum(y * y for y in sv)
    return (sympy.acos(dot / sympy.sqrt(lengths)) * 180 / sympy.pi).evalf(80)


def as_fractions(p: Point2 | Point3, q: Point2 | Point3) -> tuple[Fraction, ...]:
    dimension = 2 if isinstance(p, Point2) else 3
    return tuple(
        Fraction(int((q[i] - p[i]).numerator), int((q[i] - p[i]).denominator))
        for i in range(dimension)
    )


thresholds = st.one_of(
    st.sampled_from(EXACT_DEGREES),
    st.integers(1, 179),
    st.fractions(1, 179, max_denominator=1000),
).map(AngleThreshold.from_degrees)


@settings(max_examples=150)
@given(st.lists(ordinary2, min_size=3, max_size=3, unique=True), thresholds)
def test_compare_angle_agrees_with_a_high_precision_reference(
    points: list[Point2], threshold: AngleThreshold
) -> None:
    a, b, c = points
    if a == b or c == b:
        return
    angle = reference_angle(as_fractions(b, a), as_fractions(b, c))
    theta = sympy.Rational(int(threshold.degrees.numerator), int(threshold.degrees.denominator))
    result = compare_angle(a, b, c, threshold)
    if abs(angle - theta) > sympy.Rational(1, 10**12):
        assert result == (Comparison.GREATER if angle > theta else Comparison.LESS)
    assert result == compare_angle(c, b, a, threshold)
    assert abs(angle_degrees(a, b, c) - float(angle)) <= 1e-9


# Integer vector pairs making each exact angle, in 3D (a 30/60-degree angle has no rational
# 2D realisation; 45/90/135 have both).
EXACT_ANGLE_VECTORS3 = {
    30: ((1, 1, 0), (1, 2, 1)),
    45: ((1, 0, 0), (1, 1, 0)),
    60: ((1, 1, 0), (1, 0, 1)),
    90: ((1, 2, 3), (3, 0, -1)),
    120: ((1, 1, 0), (0, -1, -1)),
    135: ((1, 0, 0), (-1, 1, 0)),
    150: ((1, 1, 0), (-1, -2, -1)),
}


@given(
    st.sampled_from(EXACT_DEGREES),
    points3(coordinates(("ordinary", "decimal", "huge", "tiny"))),
    rationals().filter(lambda r: r > 0),
    rationals().filter(lambda r: r > 0),
)
def test_compare_angle_is_exact_at_the_exact_thresholds(
    degrees: int, apex: Point3, scale_u: object, scale_v: object
) -> None:
    """An angle of exactly 30/45/60/90/120/135/150 degrees is EQUAL to that threshold, and a
    nudge of 2^-60 of one side moves it to the right strict side."""
    u, v = EXACT_ANGLE_VECTORS3[degrees]
    a = point3(*(apex[i] + scale_u * u[i] for i in range(3)))  # type: ignore[operator]
    c = point3(*(apex[i] + scale_v * v[i] for i in range(3)))  # type: ignore[operator]
    threshold = AngleThreshold.from_degrees(degrees)
    assert compare_angle(a, apex, c, threshold) == Comparison.EQUAL
    # rotate c slightly away from a within the plane of the angle: larger angle
    normal = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    away = [
        v[1] * normal[2] - v[2] * normal[1],
        v[2] * normal[0] - v[0] * normal[2],
        v[0] * normal[1] - v[1] * normal[0],
    ]
    # 'away' is perpendicular to v in the plane; orient it away from u
    if sum(x * y for x, y in zip(away, u, strict=True)) > 0:
        away = [-x for x in away]
    epsilon = mpq(1, 2**60) * scale_v  # type: ignore[operator]
    wider = point3(*(c[i] + epsilon * away[i] for i in range(3)))
    narrower = point3(*(c[i] - epsilon * away[i] for i in range(3)))
    assert compare_angle(a, apex, wider, threshold) == Comparison.GREATER
    assert compare_angle(a, apex, narrower, threshold) == Comparison.LESS


@given(any2, st.sampled_from([45, 90, 135]), rotations, rationals().filter(lambda r: r > 0))
def test_compare_angle_is_exact_on_rotated_right_isosceles_triangles(
    apex: Point2, degrees: int, rotation: tuple[Fraction, Fraction], scale: object
) -> None:
    u = {45: (1, 0), 90: (1, 0), 135: (1, 0)}[degrees]
    v = {45: (1, 1), 90: (0, 1), 135: (-1, 1)}[degrees]
    a = rotate(point2(apex.x + scale * u[0], apex.y + scale * u[1]), rotation, apex)  # type: ignore[operator]
    c = rotate(point2(apex.x + scale * v[0], apex.y + scale * v[1]), rotation, apex)  # type: ignore[operator]
    assert compare_angle(a, apex, c, AngleThreshold.from_degrees(degrees)) == Comparison.EQUAL
    assert compare_angle(a, apex, c, AngleThreshold.from_degrees(degrees - 1)) == Comparison.GREATER
    assert compare_angle(a, apex, c, AngleThreshold.from_degrees(degrees + 1)) == Comparison.LESS


def test_compare_angle_rejects_a_degenerate_angle() -> None:
    a = point2(1, 1)
    with pytest.raises(PreconditionError):
        compare_angle(a, a, point2(0, 0), AngleThreshold.from_degrees(30))
    with pytest.raises(PreconditionError):
        angle_degrees(point2(0, 0), a, a)


def test_angle_degrees_reports_exact_angles() -> None:
    assert angle_degrees(point2(1, 0), point2(0, 0), point2(0, 1)) == 90.0
    assert angle_degrees(point2(1, 0), point2(0, 0), point2(1, 1)) == pytest.approx(45.0, abs=1e-12)
    assert angle_degrees(point2(1, 0), point2(0, 0), point2(-1, 0)) == 180.0
    assert angle_degrees(point2(mpq(10) ** 400, 0), point2(0, 0), point2(1, 0)) == 0.0


# ---- the filter is used --------------------------------------------------------------------


@example(seed=0)
@given(st.integers(0, 2**32))
def test_filter_counters_show_hits_on_ordinary_inputs_and_misses_on_ties(seed: int) -> None:
    import random

    rng = random.Random(seed)
    offset = rng.randrange(-1000, 1000)

    def coordinate() -> Fraction:
        # a point of a unit box somewhere; p/q is not a double, so inputs are inexact
        return offset + Fraction(rng.randrange(10**9), 3 * 10**9 + 2 * rng.randrange(10**6) + 1)

    ps = [point2(coordinate(), coordinate()) for _ in range(6)]
    qs = [point3(coordinate(), coordinate(), coordinate()) for _ in range(5)]
    threshold = AngleThreshold.from_degrees(20)
    P.reset_filter_counters()
    orient2d(*ps[:3])
    incircle(*ps[:4])
    orient3d(*qs[:4])
    insphere(*qs)
    compare_squared_lengths(*ps[:4])
    compare_areas(*ps)
    compare_angle(*ps[:3], threshold)
    counters = P.filter_counters()
    assert all(counts == (1, 0) for counts in counters.values()), counters
    P.reset_filter_counters()
    o, x, y = point2(0, 0), point2(1, 0), point2(0, 1)
    orient2d(o, x, point2(2, 0))
    incircle(o, x, y, point2(1, 1))
    orient3d(point3(0, 0, 0), point3(1, 0, 0), point3(0, 1, 0), point3(1, 1, 0))
    insphere(*(point3(*v) for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]))
    compare_squared_lengths(o, x, o, y)
    compare_areas(o, x, y, x, o, point2(1, -1))
    compare_angle(x, o, point2(1, 1), AngleThreshold.from_degrees(45))
    counters = P.filter_counters()
    assert all(counts == (0, 1) for counts in counters.values()), counters


# ---- the error-bound constants cover the derivation ----------------------------------------

U = Fraction(1, 2**53)
ETA = Fraction(1, 2**1075)
RHO = 2 * U / (1 - U)
RHO_PRIME = RHO / (1 + RHO)


def gamma(n: int) -> Fraction:
    return n * U / (1 - n * U)


def amgm_coefficient_bounds(rows: int, coordinates_per_row: int) -> dict[int, Fraction]:
    """For a lifted predicate (incircle: 3 rows x 2, insphere: 4 rows x 3), bounds h_s of
    the coefficients of lambda^s in F_abs(y + lambda) over sum(S) = 1, by weighted AM-GM
    on each monomial of the dominating polynomial (specs/predicates.md, step 4)."""
    s_vars = sympy.symbols(f"S0:{rows}", nonnegative=True)
    lam = sympy.Symbol("lam")
    total = sympy.Integer(0)
    for r in range(rows):
        others = [s_vars[o] for o in range(rows) if o != r]
        lift = s_vars[r] ** 2 + 2 * lam * s_vars[r] + coordinates_per_row * lam**2
        perm = sum(
            math.factorial(s)
            * sum(
                (sympy.Mul(*c) for c in itertools.combinations(others, len(others) - s)),
                sympy.Integer(0),
            )
            * lam**s
            for s in range(len(others) + 1)
        )
        total += lift * perm
    bounds: dict[int, Fraction] = {}
    for monomial, coefficient in sympy.Poly(sympy.expand(total), lam, *s_vars).terms():
        power, alpha = monomial[0], monomial[1:]
        degree = sum(alpha)
        value = Fraction(int(coefficient))
        for a in alpha:
            if a:
                value *= Fraction(a, degree) ** a
        bounds[power] = bounds.get(power, Fraction(0)) + value
    return bounds


def filter_constant_is_certified(
    *,
    C: float,
    k: int,
    n: int,
    b0: Fraction,
    b1: Fraction,
    h: dict[int, Fraction],
    n_t: int,
    n_m: int,
    n_mul: int,
    K: float,
    extra0: Fraction = Fraction(0),
) -> bool:
    """The inequalities of specs/predicates.md, step 6, in exact rational arithmetic."""
    R = (k - 1) * n_t + (k - 2) + max(n_t, n_m) + 3
    c_rounded = Fraction(C) * (1 - U) ** R
    c_success = (1 - Fraction(1, 2**42)) * c_rounded
    beta = c_success / ((1 + gamma(n)) * b0 - c_success)
    q = RHO_PRIME * (1 / beta + Fraction(1, 2**400))
    higher = b1 + sum(hs * q ** (s - 1) for s, hs in h.items() if s >= 2)
    a0 = ((1 + RHO) ** k - 1 + gamma(n)) * b0 + extra0
    a1 = (1 + RHO) ** k * RHO_PRIME * higher
    room = c_rounded * (1 - Fraction(1, 2**41))
    underflow = 8 * n_mul * ETA * (1 + U) ** n * (1 + Fraction(1, 2**50))
    return (
        a0 <= room
        and a1 <= room
        and underflow <= Fraction(1, 2**42) * c_rounded * Fraction(K) ** k
        and 2 * ETA * higher * (1 + RHO) ** k <= Fraction(1, 2**42) * c_rounded * Fraction(K)
    )


def test_filter_constants_cover_the_error_bound_derivation() -> None:
    incircle_h = amgm_coefficient_bounds(3, 2)
    insphere_h = amgm_coefficient_bounds(4, 3)
    assert incircle_h[0] == Fraction(3, 64) and insphere_h[1] == Fraction(7, 32)  # sanity
    angle_h = {s: 2 * math.comb(4, s) * 3**s * Fraction(1, 2) ** (4 - s) for s in (2, 3, 4)}
    cases = {
        "orient2d": dict(
            C=P.ORIENT2D_C,
            K=P.ORIENT2D_K,
            k=2,
            n=2,
            b0=Fraction(1, 4),
            b1=Fraction(1),
            h={2: Fraction(2)},
            n_t=4,
            n_m=1,
            n_mul=2,
        ),
        "orient3d": dict(
            C=P.ORIENT3D_C,
            K=P.ORIENT3D_K,
            k=3,
            n=5,
            b0=Fraction(1, 27),
            b1=Fraction(1, 3),
            h={2: Fraction(2), 3: Fraction(6)},
            n_t=9,
            n_m=2,
            n_mul=9,
        ),
        "incircle": dict(
            C=P.INCIRCLE_C,
            K=P.INCIRCLE_K,
            k=4,
            n=5,
            b0=Fraction(1, 27),
            b1=Fraction(4, 9),
            h=incircle_h,
            n_t=6,
            n_m=1,
            n_mul=15,
        ),
        "insphere": dict(
            C=P.INSPHERE_C,
            K=P.INSPHERE_K,
            k=5,
            n=8,
            b0=Fraction(1, 256),
            b1=Fraction(5, 64),
            h=insphere_h,
            n_t=12,
            n_m=2,
            n_mul=40,
        ),
        "lengths": dict(
            C=P.LENGTHS_C,
            K=P.LENGTHS_K,
            k=2,
            n=4,
            b0=Fraction(1),
            b1=Fraction(2),
            h={2: Fraction(6)},
            n_t=6,
            n_m=5,
            n_mul=6,
        ),
        "dot": dict(
            C=P.DOT_C,
            K=P.DOT_K,
            k=2,
            n=3,
            b0=Fraction(1, 4),
            b1=Fraction(1),
            h={2: Fraction(3)},
            n_t=6,
            n_m=2,
            n_mul=3,
        ),
        "angle": dict(
            C=P.ANGLE_C,
            K=P.ANGLE_K,
            k=4,
            n=6,
            b0=Fraction(1, 8),
            b1=Fraction(1),
            h=angle_h,
            n_t=8,
            n_m=8,
            n_mul=12,
            extra0=U / 16,
        ),
    }
    for name, case in cases.items():
        assert filter_constant_is_certified(**case), name  # type: ignore[arg-type]
        smaller = dict(case, C=case["C"] * 0.85)
        assert not filter_constant_is_certified(**smaller), f"{name}: C is needlessly large"  # type: ignore[arg-type]


# ---- the public point strategies validate their arguments eagerly ------------------------


def test_point_strategies_validate_their_arguments() -> None:
    from hypothesis.errors import InvalidArgument

    from geomexact import strategies

    bad = [
        lambda: strategies.rationals(max_denominator=0),
        lambda: strategies.decimal_rationals(max_digits=0),
        lambda: strategies.extreme_rationals(min_exponent=5, max_exponent=4),
        lambda: strategies.coordinates(()),
        lambda: strategies.coordinates(("galactic",)),  # type: ignore[arg-type]
        lambda: strategies.coordinates("huge"),  # type: ignore[arg-type]
        lambda: strategies.collinear_triples(()),
        lambda: strategies.near_degenerate_points2(5),
        lambda: strategies.near_degenerate_points3(3),
    ]
    for build in bad:
        with pytest.raises(InvalidArgument):
            build()
