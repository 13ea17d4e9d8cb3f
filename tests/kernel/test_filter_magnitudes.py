"""Every copy of the certified float filters at every magnitude (issue 11).

Exact rationals ``m * 2^e`` (|e| <= 1330, crowded near the ends of the double range: the
subnormals around 2^-1074, the overflow around 2^1024) and ``m * 10^e`` (|e| <= 400), so
from about 1e-400 to 1e400: far beyond the doubles (whose floats are NaN), right at
their ends, in the subnormals (whose floats carry an absolute error) and where products
underflow or overflow.  Random configurations and near-degenerate ones (an exactly
degenerate configuration mapped by a similarity of any magnitude, one coordinate then
moved by a relative 2^-k or to a neighbouring double).

Checked for every query, against the sign computed here from the textbook determinant
with plain :class:`fractions.Fraction` arithmetic:

* the Python predicates (orient2d, incircle, orient3d, insphere, compare_squared_lengths
  in 2D and 3D, compare_areas, compare_angle in 2D and 3D) give the exact sign;
* the numpy filters (``array_filters``) and the C filters (``ckernel.h`` through
  ``cfilters``), where they decide, give the exact sign, and they decide exactly where
  the Python filter decides (an overflow, underflow or NaN must make every copy
  undecided, never wrong).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from geomexact.kernel.angles import AngleThreshold, compare_angle
from geomexact.kernel.array_filters import orient2d_signs, point_doubles, squared_length_signs
from geomexact.kernel.comparisons import compare_areas, compare_squared_lengths
from geomexact.kernel.filter_bounds import filter_counters, reset_filter_counters
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.kernel.predicates3d import insphere, orient3d


def _load_cfilters() -> Any:
    try:
        return importlib.import_module("geomexact.kernel.cfilters")
    except ImportError:  # not built: tests/package/test_kernels_built.py says why
        return None


cfilters = _load_cfilters()
Point = Point2 | Point3

# ---- magnitudes ----------------------------------------------------------------------------

# a predicate of degree k evaluated on differences near 2^(-1074/k) has its products at
# the subnormals: where an error bound without its K term would certify a wrong sign
_UNDERFLOW_EXPONENTS = st.sampled_from((537, 358, 268, 215)).flatmap(
    lambda e: st.integers(-e - 8, -e + 8))
_BINARY_EXPONENTS = st.one_of(
    st.integers(-1330, 1330),
    st.integers(-1130, -1010),  # subnormals, the smallest normals, products below them
    _UNDERFLOW_EXPONENTS,
    st.integers(440, 560),  # products of two of these overflow
    st.integers(990, 1030),  # the largest doubles and just beyond
)
_MANTISSAS = st.integers(1, 2**60).flatmap(lambda m: st.sampled_from((m, -m)))
_BINARY = st.builds(lambda m, e: mpq(m) * mpq(2) ** e, _MANTISSAS, _BINARY_EXPONENTS)
_DECIMAL = st.builds(lambda m, e: mpq(m) * mpq(10) ** e,
                     st.integers(-(10**17), 10**17).filter(bool), st.integers(-400, 400))
_NONZERO = st.one_of(_BINARY, _DECIMAL)
MAGNITUDES = st.one_of(st.just(mpq(0)), _NONZERO)
"""Exact rationals from about 1e-400 to 1e400, and 0."""
_UNIT = st.builds(lambda p, q: mpq(p, q), st.integers(-1000, 1000), st.integers(1, 97))


@st.composite
def _moved(draw: st.DrawFn, value: Rational, size: Rational) -> Rational:
    """``value`` moved by +-2^-k * size (k <= 120), or to a neighbouring double, or not."""
    kind = draw(st.sampled_from(("relative", "next_double", "none")))
    direction = draw(st.sampled_from((-1, 1)))
    if kind == "relative":
        return value + direction * abs(size) * mpq(1, 2 ** draw(st.integers(0, 120)))
    if kind == "next_double":
        try:
            return mpq(math.nextafter(float(value), direction * math.inf))
        except (OverflowError, ValueError):  # beyond the doubles: no neighbour
            return value
    return value


@st.composite
def _similar(draw: st.DrawFn, unit: Sequence[Sequence[Rational]]) -> list[list[Rational]]:
    """The unit configuration mapped by x -> scale * x + offset (scale and offset of any
    magnitude: collinearity, cocircularity, equal lengths ... are kept), then one
    coordinate moved by :func:`_moved`."""
    scale = draw(_NONZERO)
    # an offset of any magnitude, or one no bigger than the configuration (a pivot
    # magnitude below its differences: the underflow cases)
    offsets = st.one_of(MAGNITUDES, _UNIT.map(lambda u: u * scale))
    offset = [draw(offsets) for _ in unit[0]]
    coordinates = [[o + scale * u for o, u in zip(offset, point, strict=True)]
                   for point in unit]
    i = draw(st.integers(0, len(coordinates) - 1))
    k = draw(st.integers(0, len(coordinates[0]) - 1))
    coordinates[i][k] = draw(_moved(coordinates[i][k], scale))
    return coordinates


def _circle_point(t: Rational) -> list[Rational]:
    """A rational point of the unit circle (t = tan of half its angle)."""
    return [(1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)]


def _sphere_point(a: Rational, b: Rational) -> list[Rational]:
    """A rational point of the unit sphere (inverse stereographic projection of (a, b))."""
    n = a * a + b * b + 1
    return [2 * a / n, 2 * b / n, (n - 2) / n]


def _rotation(m: int, n: int) -> tuple[Rational, Rational]:
    """cos and sin of an exact rational rotation (a Pythagorean triple)."""
    return mpq(m * m - n * n, m * m + n * n), mpq(2 * m * n, m * m + n * n)


@st.composite
def _collinear(draw: st.DrawFn, count: int, dimension: int) -> list[list[Rational]]:
    direction = [draw(_UNIT) for _ in range(dimension)]
    return [[t * d for d in direction] for t in (draw(_UNIT) for _ in range(count))]


@st.composite
def _cocircular(draw: st.DrawFn) -> list[list[Rational]]:
    return [_circle_point(draw(_UNIT)) for _ in range(4)]


@st.composite
def _coplanar(draw: st.DrawFn) -> list[list[Rational]]:
    u = [draw(_UNIT) for _ in range(3)]
    v = [draw(_UNIT) for _ in range(3)]
    weights = [(draw(_UNIT), draw(_UNIT)) for _ in range(4)]
    return [[a * ui + b * vi for ui, vi in zip(u, v, strict=True)] for a, b in weights]


@st.composite
def _cospherical(draw: st.DrawFn) -> list[list[Rational]]:
    return [_sphere_point(draw(_UNIT), draw(_UNIT)) for _ in range(5)]


@st.composite
def _equal_lengths(draw: st.DrawFn) -> list[list[Rational]]:
    """ab, and cd an exact rotation of it placed elsewhere."""
    ux, uy = draw(_UNIT), draw(_UNIT)
    cos, sin = _rotation(draw(st.integers(1, 30)), draw(st.integers(0, 30)))
    px, py = draw(_UNIT), draw(_UNIT)
    return [[0, 0], [ux, uy], [px, py], [px + cos * ux - sin * uy, py + sin * ux + cos * uy]]


@st.composite
def _right_angle(draw: st.DrawFn) -> list[list[Rational]]:
    """(p, a, b) with a right angle at p."""
    ux, uy, stretch = draw(_UNIT), draw(_UNIT), draw(_UNIT)
    return [[0, 0], [ux, uy], [-stretch * uy, stretch * ux]]


@st.composite
def _equal_areas(draw: st.DrawFn) -> list[list[Rational]]:
    """Triangle abc and def, def = abc sheared (area kept) and moved."""
    abc = [[draw(_UNIT), draw(_UNIT)] for _ in range(3)]
    shear, dx, dy = draw(_UNIT), draw(_UNIT), draw(_UNIT)
    return abc + [[x + shear * y + dx, y + dy] for x, y in abc]


def _points(coordinates: Sequence[Sequence[Rational]]) -> list[Any]:
    make: Callable[..., Any] = point2 if len(coordinates[0]) == 2 else point3
    return [make(*point) for point in coordinates]


def _configurations(unit: st.SearchStrategy[list[list[Rational]]], count: int,
                    dimension: int) -> st.SearchStrategy[list[Any]]:
    """Near-degenerate (from ``unit``) or random configurations of ``count`` points."""
    random = st.lists(st.lists(MAGNITUDES, min_size=dimension, max_size=dimension),
                      min_size=count, max_size=count)
    return st.one_of(unit.flatmap(_similar), random).map(_points)


# ---- the exact signs, from the textbook determinants in Fractions --------------------------

def _fractions(p: Point) -> list[Fraction]:
    return [Fraction(int(c.numerator), int(c.denominator)) for c in p[: len(p) // 2]]


def _det(rows: list[list[Fraction]]) -> Fraction:
    if len(rows) == 1:
        return rows[0][0]
    return sum((-1) ** j * rows[0][j] * _det([row[:j] + row[j + 1:] for row in rows[1:]])
               for j in range(len(rows)))  # type: ignore[return-value]


def _sign(value: Fraction) -> int:
    return (value > 0) - (value < 0)


def _minus(p: Point, q: Point) -> list[Fraction]:
    return [a - b for a, b in zip(_fractions(p), _fractions(q), strict=True)]


def _dot(u: list[Fraction], v: list[Fraction]) -> Fraction:
    return sum((a * b for a, b in zip(u, v, strict=True)), Fraction(0))


def exact_orientation(points: Sequence[Point]) -> int:
    """orient2d(a, b, c) = det[b - a, c - a]; orient3d(a, b, c, d) = det[b - a, c - a, d - a]."""
    first = points[0]
    return _sign(_det([_minus(p, first) for p in points[1:]]))


def exact_in_sphere(points: Sequence[Point]) -> int:
    """incircle(a, b, c, d) = det[[ad, |ad|^2] ...] (3 rows); insphere(a, ..., e) is minus
    the 4-row determinant (``specs/predicates.md``)."""
    pivot = points[-1]
    rows = []
    for p in points[:-1]:
        difference = _minus(p, pivot)
        rows.append([*difference, _dot(difference, difference)])
    value = _det(rows)
    return _sign(value if len(rows) == 3 else -value)


def exact_lengths(a: Point, b: Point, c: Point, d: Point) -> int:
    u, v = _minus(b, a), _minus(d, c)
    return _sign(_dot(u, u) - _dot(v, v))


def exact_areas(points: Sequence[Point2]) -> int:
    return _sign(abs(_det([_minus(points[1], points[0]), _minus(points[2], points[0])]))
                 - abs(_det([_minus(points[4], points[3]), _minus(points[5], points[3])])))


def exact_angle(a: Point, b: Point, c: Point, threshold: AngleThreshold) -> int:
    """1 when the angle at b exceeds θ: cos(angle) < cos(θ), i.e. the sign of
    cos(θ)·sqrt(L) - D, D = u.v, L = |u|^2 |v|^2 (θ exact: cos2 is cos^2 θ)."""
    u, v = _minus(a, b), _minus(c, b)
    dot = _dot(u, v)
    left, right = threshold.cos_sign, _sign(dot)
    if left != right:
        return _sign(Fraction(left - right))
    cos2 = Fraction(int(threshold.cos2.numerator), int(threshold.cos2.denominator))
    return left * _sign(cos2 * _dot(u, u) * _dot(v, v) - dot * dot)


# ---- the copies ----------------------------------------------------------------------------

def _python(counter: str, predicate: Callable[..., Any], *args: Any) -> tuple[int, bool]:
    """(answer, whether the Python filter decided it: its hit counter moved)."""
    reset_filter_counters()
    answer = int(predicate(*args))
    return answer, filter_counters()[counter][0] == 1


def _doubles(points: Sequence[Point2]) -> list[float]:
    return [value for p in points for value in (p.fx, p.fy)]


def _numpy(signs: Callable[..., Any], points: Sequence[Point2]) -> int:
    fx, fy = point_doubles(points)
    return int(signs(fx, fy, *(np.array([i]) for i in range(len(points))))[0])


def assert_copies(exact: int, python: tuple[int, bool], *others: int | None) -> None:
    """The Python predicate is exact; every other copy (None: not built) decides where
    the Python filter decides, and then with the exact sign."""
    answer, decided = python
    assert answer == exact
    for other in others:
        if other is not None:
            assert other in (0, exact)
            assert (other != 0) == decided


ORIENT_TRIPLES = _configurations(_collinear(3, 2), 3, 2)
CIRCLE_QUADRUPLES = _configurations(_cocircular(), 4, 2)
LENGTH_QUADRUPLES2 = _configurations(_equal_lengths(), 4, 2)
LENGTH_QUADRUPLES3 = _configurations(_collinear(4, 3), 4, 3)
ANGLE_TRIPLES2 = _configurations(_right_angle(), 3, 2)
AREA_SEXTUPLES = _configurations(_equal_areas(), 6, 2)
PLANE_QUADRUPLES = _configurations(_coplanar(), 4, 3)
SPHERE_QUINTUPLES = _configurations(_cospherical(), 5, 3)
ANGLE_TRIPLES3 = _configurations(_collinear(3, 3), 3, 3)
THRESHOLDS = st.sampled_from([AngleThreshold.from_degrees(d)
                              for d in (30, 45, 60, 90, 120, 135, 150)])
RIGHT_ANGLE = AngleThreshold.from_degrees(90)


def check_orient2d(points: list[Point2]) -> None:
    a, b, c = points
    c_copy = cfilters.orient2d_filter(*_doubles(points)) if cfilters else None
    assert_copies(exact_orientation(points), _python("orient2d", orient2d, a, b, c),
                  _numpy(orient2d_signs, points), c_copy)


def check_incircle(points: list[Point2]) -> None:
    c_copy = cfilters.incircle_filter(*_doubles(points)) if cfilters else None
    assert_copies(exact_in_sphere(points), _python("incircle", incircle, *points), c_copy)


def check_lengths2(points: list[Point2]) -> None:
    c_copy = cfilters.squared_lengths_filter(*_doubles(points)) if cfilters else None
    assert_copies(exact_lengths(*points),
                  _python("compare_squared_lengths", compare_squared_lengths, *points),
                  _numpy(squared_length_signs, points), c_copy)


def check_dot_and_angles2(points: list[Point2], threshold: AngleThreshold) -> None:
    """The sign of (a - p).(b - p): the C dot filter, and compare_angle's first stage
    (against 90 degrees it decides on that sign alone: LESS for a positive dot); then
    compare_angle at p against ``threshold``."""
    p, a, b = points
    if p in (a, b):
        return
    c_copy = cfilters.dot_filter(*_doubles(points)) if cfilters else None
    less, decided = _python("compare_angle", compare_angle, a, p, b, RIGHT_ANGLE)
    assert_copies(-exact_angle(a, p, b, RIGHT_ANGLE), (-less, decided), c_copy)
    assert int(compare_angle(a, p, b, threshold)) == exact_angle(a, p, b, threshold)


def check_areas(points: list[Point2]) -> None:
    assert int(compare_areas(*points)) == exact_areas(points)


def check_orient3d(points: list[Point3]) -> None:
    assert int(orient3d(*points)) == exact_orientation(points)


def check_insphere(points: list[Point3]) -> None:
    assert int(insphere(*points)) == exact_in_sphere(points)


def check_lengths3(points: list[Point3]) -> None:
    assert int(compare_squared_lengths(*points)) == exact_lengths(*points)


def check_angles3(points: list[Point3], threshold: AngleThreshold) -> None:
    a, b, c = points
    if b not in (a, c):
        assert int(compare_angle(a, b, c, threshold)) == exact_angle(a, b, c, threshold)


CASES = st.one_of(
    ORIENT_TRIPLES.map(lambda points: (check_orient2d, points)),
    CIRCLE_QUADRUPLES.map(lambda points: (check_incircle, points)),
    LENGTH_QUADRUPLES2.map(lambda points: (check_lengths2, points)),
    st.tuples(ANGLE_TRIPLES2, THRESHOLDS).map(
        lambda case: (lambda points: check_dot_and_angles2(points, case[1]), case[0])),
    AREA_SEXTUPLES.map(lambda points: (check_areas, points)),
    PLANE_QUADRUPLES.map(lambda points: (check_orient3d, points)),
    SPHERE_QUINTUPLES.map(lambda points: (check_insphere, points)),
    LENGTH_QUADRUPLES3.map(lambda points: (check_lengths3, points)),
    st.tuples(ANGLE_TRIPLES3, THRESHOLDS).map(
        lambda case: (lambda points: check_angles3(points, case[1]), case[0])),
)
"""(check, points): one query of one predicate, checked in every copy."""


def _run(case: tuple[Callable[[Any], None], list[Any]]) -> None:
    check, points = case
    check(points)


_HUGE = mpq(2) ** 1023 * 3 / 2  # a finite double whose differences overflow
_TINY = mpq(2) ** -1074  # the smallest subnormal
_BEYOND = mpq(10) ** 309
_S259, _S310 = mpq(2) ** -259, mpq(2) ** -310


@settings(suppress_health_check=[HealthCheck.too_slow])
@given(CASES)
@example((check_orient2d, _points([[_HUGE, _HUGE], [-_HUGE, _HUGE], [_HUGE, -_HUGE]])))
@example((check_orient2d, _points([[_TINY, 0], [0, _TINY], [3 * _TINY, 2 * _TINY]])))
@example((check_orient2d, _points([[_BEYOND, 1], [-_BEYOND, 0], [0, mpq(1, 2)]])))
@example((check_incircle, _points([[_TINY, 0], [0, _TINY], [-_TINY, 0], [0, -_TINY]])))
@example((check_incircle, _points([[_HUGE, 0], [0, _HUGE], [-_HUGE, 0], [0, -_HUGE]])))
# products at the subnormals (differences near 2^-259): a bound without INCIRCLE_K
# certifies the wrong sign here
@example((check_incircle, _points([[-1351079888211149 * _S310, -_S259 * 4 / 5], [-_S259, 0],
                                   [0, _S259], [0, -_S259]])))
@example((check_lengths2, _points([[0, 0], [_HUGE, 0], [0, 0], [0, -_HUGE]])))
@example((check_insphere, _points([[_HUGE, 0, 0], [0, _HUGE, 0], [0, 0, _HUGE],
                                   [-_HUGE, 0, 0], [0, -_HUGE, 0]])))
def test_every_filter_copy_is_exact_at_every_magnitude(
        case: tuple[Callable[[Any], None], list[Any]]) -> None:
    _run(case)


@pytest.mark.slow
@settings(max_examples=20_000, suppress_health_check=[HealthCheck.too_slow])
@given(CASES)
def test_every_filter_copy_is_exact_at_every_magnitude_many_examples(
        case: tuple[Callable[[Any], None], list[Any]]) -> None:
    _run(case)


def test_the_magnitudes_reach_beyond_the_doubles_at_both_ends() -> None:
    """The strategy is not confined to the doubles: it reaches 1e-400 and 1e400."""
    from hypothesis import find, settings

    # derandomized and without the example database: the same search on every run
    search = settings(database=None, derandomize=True, max_examples=20_000)
    assert find(_NONZERO, lambda v: abs(v) > mpq(10) ** 399, settings=search) != 0
    assert find(_NONZERO, lambda v: abs(v) < mpq(10) ** -399, settings=search) != 0
