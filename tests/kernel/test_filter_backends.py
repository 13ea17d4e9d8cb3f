"""Every backend of the certified float filters against the exact predicates.

Three copies of the filters exist: the Python ones inside the predicates
(``geomexact.kernel.predicates2d`` / ``predicates3d`` / ``comparisons`` / ``angles``), the
numpy ones (``geomexact.kernel.array_filters``) and the C ones of ``ckernel.h`` (reached
through the test-facing extension ``geomexact.kernel.cfilters``, with the C kernels'
exact predicates on the dyadic grid).  On adversarial near-degenerate inputs:

1. whenever a backend certifies a sign, it is the exact sign (undecided is allowed);
2. the numpy and C copies certify exactly the queries the Python filter certifies, with
   the same sign: they are the same operations in the same order with the same constants,
   so a drift in one copy (a constant, an operation order, a missing term) shows up even
   where it would still happen to give right answers.  Random inputs rarely land near a
   bound, so this is also checked right at the bound: an exactly degenerate configuration
   with one coordinate moved by the number of ulps (found by bisection) where the Python
   filter starts to decide;
3. on ordinary inputs every backend decides almost everything (the checks above are not
   vacuous).

A Python filter "decides" when its hit counter moves (``filter_bounds.filter_counters``).
"""

from __future__ import annotations

import importlib
import itertools
import math
import random
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import attrs
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geomexact.kernel.angles import AngleThreshold, compare_angle
from geomexact.kernel.array_filters import (
    incircle_signs,
    orient2d_signs,
    orient3d_signs,
    point_doubles,
    point_doubles3,
    squared_length_signs,
)
from geomexact.kernel.comparisons import compare_areas, compare_squared_lengths
from geomexact.kernel.filter_bounds import filter_counters, reset_filter_counters
from geomexact.kernel.numbers import Rational, mpq, scaled_to_integers, sign
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicates2d import (
    _orient2d_float,
    incircle,
    incircle_exact,
    orient2d,
    orient2d_exact,
)
from geomexact.kernel.predicates3d import insphere, insphere_exact, orient3d, orient3d_exact
from geomexact.strategies import (
    Magnitude,
    cocircular_quadruples,
    collinear_triples,
    coordinates,
    coplanar_quadruples,
    cospherical_quintuples,
    near_degenerate_points2,
    near_degenerate_points3,
    points2,
    points3,
    rationals,
)

Point = Point2 | Point3
Query = tuple[Any, ...]
Decisions = list[int | None]  # a certified sign, or None where the backend does not decide


def _load_cfilters() -> Any:
    try:
        return importlib.import_module("geomexact.kernel.cfilters")
    except ImportError:  # not built: the C cases skip (tests/package/test_kernels_built.py says why)
        return None


cfilters = _load_cfilters()

# ---- adversarial inputs ----------------------------------------------------------------

_UNIT = rationals(max_numerator=1000, max_denominator=97)


@st.composite
def _nudged(draw: st.DrawFn, value: Rational) -> Rational:
    """``value`` moved by +-2^-k of its magnitude (k up to 110), or to a neighbouring
    double, or not at all."""
    kind = draw(st.sampled_from(("power", "next_double", "none")))
    direction = draw(st.sampled_from((-1, 1)))
    magnitude = abs(value) if value != 0 else mpq(1)
    if kind == "power":
        return value + direction * magnitude * mpq(1, 2 ** draw(st.integers(20, 110)))
    if kind == "next_double":
        try:
            return mpq(math.nextafter(float(value), direction * math.inf))
        except (OverflowError, ValueError):  # beyond the doubles: no neighbour
            return value
    return value


def _rotation(m: int, n: int) -> tuple[Rational, Rational]:
    """cos and sin of an exact rational rotation (a Pythagorean triple)."""
    return mpq(m * m - n * n, m * m + n * n), mpq(2 * m * n, m * m + n * n)


_ROTATIONS = st.tuples(st.integers(1, 30), st.integers(0, 30)).map(lambda mn: _rotation(*mn))
_FRAMES = coordinates(("ordinary", "decimal", "dyadic", "huge", "tiny"))  # finite doubles


@st.composite
def _equal_lengths(draw: st.DrawFn) -> tuple[Point2, Point2, Point2, Point2]:
    """Segments ab and cd of equal length: cd is an exact rotation of ab moved elsewhere."""
    scale = draw(_FRAMES.filter(lambda s: s != 0))
    ox, oy, px, py = (draw(_FRAMES) for _ in range(4))
    ux, uy = draw(_UNIT), draw(_UNIT)
    cos, sin = draw(_ROTATIONS)
    a = point2(ox, oy)
    b = point2(ox + scale * ux, oy + scale * uy)
    c = point2(px, py)
    d = point2(px + scale * (cos * ux - sin * uy), py + scale * (sin * ux + cos * uy))
    return a, b, c, d


@st.composite
def _right_angles(draw: st.DrawFn) -> tuple[Point2, Point2, Point2]:
    """(p, a, b) with a right angle at p: b - p is a - p turned by 90 degrees and scaled."""
    scale = draw(_FRAMES.filter(lambda s: s != 0))
    ox, oy = draw(_FRAMES), draw(_FRAMES)
    ux, uy = draw(_UNIT), draw(_UNIT)
    stretch = draw(_UNIT.filter(lambda s: s != 0))
    p = point2(ox, oy)
    a = point2(ox + scale * ux, oy + scale * uy)
    b = point2(ox - scale * stretch * uy, oy + scale * stretch * ux)
    return p, a, b


@st.composite
def _equal_areas(draw: st.DrawFn) -> tuple[Point2, ...]:
    """Triangles abc and def of equal area: def is abc sheared and rotated."""
    a, b, c = (draw(points2(_FRAMES)) for _ in range(3))
    shift = draw(_UNIT)
    cos, sin = draw(_ROTATIONS)
    sheared = (c.x + shift * (b.x - a.x), c.y + shift * (b.y - a.y))
    turned = [(a.x + cos * (x - a.x) - sin * (y - a.y), a.y + sin * (x - a.x) + cos * (y - a.y))
              for x, y in ((a.x, a.y), (b.x, b.y), sheared)]
    d, e, f = (point2(x, y) for x, y in turned)
    return a, b, c, d, e, f


@st.composite
def _at_the_edge(draw: st.DrawFn, base: st.SearchStrategy[tuple[Any, ...]]) -> tuple[Any, ...]:
    """An exactly degenerate configuration with one coordinate :func:`_nudged`."""
    points = list(draw(base))
    index = draw(st.integers(0, len(points) - 1))
    coordinates = [points[index].x, points[index].y]
    axis = draw(st.integers(0, 1))
    coordinates[axis] = draw(_nudged(coordinates[axis]))
    points[index] = point2(*coordinates)
    return tuple(points)


def _any(points: st.SearchStrategy[Any], count: int) -> st.SearchStrategy[tuple[Any, ...]]:
    return st.tuples(*([points] * count))


TRIPLES2 = st.one_of(_at_the_edge(collinear_triples()), near_degenerate_points2(3),
                     collinear_triples(), _any(points2(), 3))
QUADRUPLES2 = st.one_of(_at_the_edge(cocircular_quadruples()), near_degenerate_points2(4),
                        cocircular_quadruples(), _any(points2(), 4))
LENGTHS2 = st.one_of(_at_the_edge(_equal_lengths()), _equal_lengths(), _any(points2(), 4))
LENGTHS3 = st.one_of(near_degenerate_points3(4), _any(points3(), 4))
RIGHT_ANGLES = st.one_of(_at_the_edge(_right_angles()), _right_angles(), _any(points2(), 3))
AREAS = st.one_of(_at_the_edge(_equal_areas()), _equal_areas(), _any(points2(), 6))
QUADRUPLES3 = st.one_of(near_degenerate_points3(4), coplanar_quadruples(), _any(points3(), 4))
QUINTUPLES3 = st.one_of(near_degenerate_points3(5), cospherical_quintuples(), _any(points3(), 5))
THRESHOLDS = st.one_of(
    st.sampled_from((30, 45, 60, 90, 120, 135, 150)),
    st.integers(1, 179),
    st.fractions(1, 179, max_denominator=1000),
).map(AngleThreshold.from_degrees)


def _permutations(points: tuple[Any, ...], size: int, limit: int = 24) -> list[Query]:
    return list(itertools.islice(itertools.permutations(points, size), limit))


# ---- the exact answers -----------------------------------------------------------------


def _squared_length(p: Point, q: Point) -> Rational:
    return sum(((q[i] - p[i]) ** 2 for i in range(len(p) // 2)), mpq(0))


def _dot(p: Point, a: Point, b: Point) -> Rational:
    return sum(((a[i] - p[i]) * (b[i] - p[i]) for i in range(len(p) // 2)), mpq(0))


def exact_lengths(a: Point, b: Point, c: Point, d: Point) -> int:
    return sign(_squared_length(a, b) - _squared_length(c, d))


def exact_dot(p: Point2, a: Point2, b: Point2) -> int:
    return sign(_dot(p, a, b))


def _area2(a: Point2, b: Point2, c: Point2) -> Rational:
    return abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x))


def exact_areas(a: Point2, b: Point2, c: Point2, d: Point2, e: Point2, f: Point2) -> int:
    return sign(_area2(a, b, c) - _area2(d, e, f))


def exact_angle(a: Point, b: Point, c: Point, threshold: AngleThreshold) -> int:
    """GREATER (1) when the angle at b exceeds the threshold's angle: cos(angle) < cos(θ),
    i.e. the sign of cos(θ)·sqrt(L) - D with D = u.v and L = |u|^2 |v|^2."""
    dot = _dot(b, a, c)
    lengths = _squared_length(b, a) * _squared_length(b, c)
    left_sign, right_sign = threshold.cos_sign, sign(dot)
    if left_sign != right_sign:
        return sign(left_sign - right_sign)
    return left_sign * sign(threshold.cos2 * lengths - dot * dot)


# ---- the backends --------------------------------------------------------------------------


def _python(counter: str, predicate: Callable[..., Any], to_sign: Callable[[Any], int] = int,
            ) -> Callable[[Sequence[Query]], Decisions]:
    """The Python filter inside ``predicate``: its answer when the hit counter moved."""

    def decide(queries: Sequence[Query]) -> Decisions:
        decisions: Decisions = []
        for query in queries:
            reset_filter_counters()
            answer = predicate(*query)
            hit = filter_counters()[counter][0] == 1
            decisions.append(to_sign(answer) if hit else None)
        return decisions

    return decide


RIGHT_ANGLE = AngleThreshold.from_degrees(90)
_angle_at_p = _python("compare_angle", lambda p, a, b: compare_angle(a, p, b, RIGHT_ANGLE),
                      lambda answer: -int(answer))  # LESS than 90 degrees: a positive dot


def _python_dot(queries: Sequence[Query]) -> Decisions:
    """The Python dot filter is compare_angle's first stage: against 90 degrees it decides
    on the sign of (a - p).(b - p) alone."""
    return [None if p in (a, b) else _angle_at_p([(p, a, b)])[0] for p, a, b in queries]


def _python_angle(queries: Sequence[Query]) -> Decisions:
    decide = _python("compare_angle", compare_angle)
    return [None if b in (a, c) else decide([(a, b, c, threshold)])[0]
            for a, b, c, threshold in queries]


def _orient2d_float_decide(queries: Sequence[Query]) -> Decisions:
    """``predicates2d._orient2d_float`` (orient2d's filter as a function, for compare_areas):
    the sign of its value when that exceeds its bound."""
    decisions: Decisions = []
    for query in queries:
        det, bound = _orient2d_float(*query)
        decisions.append((1 if det > 0 else -1) if det > bound or -det > bound else None)
    return decisions


def _numpy(signs: Callable[..., Any]) -> Callable[[Sequence[Query]], Decisions]:
    """A vectorised filter over all queries at once (one point array, one index array per
    argument position)."""

    def decide(queries: Sequence[Query]) -> Decisions:
        points = list(dict.fromkeys(p for query in queries for p in query))  # equal = same id
        ids = {p: i for i, p in enumerate(points)}
        fx, fy = point_doubles(points)
        columns = [np.array([ids[q[k]] for q in queries], dtype=np.intp)
                   for k in range(len(queries[0]))]
        return [int(s) or None for s in signs(fx, fy, *columns).tolist()]

    return decide


def _numpy3(signs: Callable[..., Any]) -> Callable[[Sequence[Query]], Decisions]:
    """:func:`_numpy` for points in space (``fx``, ``fy``, ``fz``)."""

    def decide(queries: Sequence[Query]) -> Decisions:
        points = list(dict.fromkeys(p for query in queries for p in query))
        ids = {p: i for i, p in enumerate(points)}
        columns = [np.array([ids[q[k]] for q in queries], dtype=np.intp)
                   for k in range(len(queries[0]))]
        return [int(s) or None for s in signs(*point_doubles3(points), *columns).tolist()]

    return decide


def _c(name: str) -> Callable[[Sequence[Query]], Decisions]:
    """A C filter of ckernel.h on the points' doubles."""

    def decide(queries: Sequence[Query]) -> Decisions:
        function = getattr(cfilters, name)
        return [function(*(v for p in q for v in (p.fx, p.fy))) or None for q in queries]

    return decide


def _c_grid(name: str) -> Callable[[Sequence[Query]], Decisions]:
    """A C exact predicate on the dyadic grid: the query's coordinates scaled to integers
    (a positive scale keeps the sign of these homogeneous predicates), when they fit."""

    def decide(queries: Sequence[Query]) -> Decisions:
        function = getattr(cfilters, name)
        decisions: Decisions = []
        for q in queries:
            values = scaled_to_integers([v for p in q for v in (p.x, p.y)])
            fits = all(abs(v) <= cfilters.GRID_LIMIT for v in values)
            decisions.append(function(*(int(v) for v in values)) if fits else None)
        return decisions

    return decide


@attrs.frozen
class Case:
    """One backend of one predicate: its inputs, its decisions, the exact answer."""

    backend: str
    predicate: str
    points: st.SearchStrategy[tuple[Any, ...]]
    size: int
    decide: Callable[[Sequence[Query]], Decisions]
    exact: Callable[..., int]
    max_examples: int = 100
    permute: bool = True  # query the permutations of the drawn points, else those points

    @property
    def id(self) -> str:
        return f"{self.backend}-{self.predicate}"

    def queries(self, points: tuple[Any, ...]) -> list[Query]:
        return _permutations(points, self.size) if self.permute else [points]


def _angle_points() -> st.SearchStrategy[tuple[Any, ...]]:
    triples = st.one_of(TRIPLES2, RIGHT_ANGLES, near_degenerate_points3(4).map(lambda q: q[:3]),
                        _any(points3(), 3))
    return st.tuples(triples, THRESHOLDS).map(lambda pair: (*pair[0], pair[1]))


PYTHON = [
    Case("python", "orient2d", TRIPLES2, 3, _python("orient2d", orient2d), orient2d_exact),
    Case("python", "orient2d-float", TRIPLES2, 3, _orient2d_float_decide, orient2d_exact),
    Case("python", "incircle", QUADRUPLES2, 4, _python("incircle", incircle), incircle_exact),
    Case("python", "lengths2d", LENGTHS2, 4,
         _python("compare_squared_lengths", compare_squared_lengths), exact_lengths),
    Case("python", "lengths3d", LENGTHS3, 4,
         _python("compare_squared_lengths", compare_squared_lengths), exact_lengths, 50),
    Case("python", "dot", RIGHT_ANGLES, 3, _python_dot, exact_dot),
    Case("python", "areas", AREAS, 6, _python("compare_areas", compare_areas), exact_areas,
         permute=False),
    Case("python", "angle", _angle_points(), 4, _python_angle, exact_angle, permute=False),
    Case("python", "orient3d", QUADRUPLES3, 4, _python("orient3d", orient3d), orient3d_exact, 50),
    Case("python", "insphere", QUINTUPLES3, 5, _python("insphere", insphere), insphere_exact, 25),
]
COPIES = [
    Case("numpy", "orient2d", TRIPLES2, 3, _numpy(orient2d_signs), orient2d_exact),
    Case("numpy", "incircle", QUADRUPLES2, 4, _numpy(incircle_signs), incircle_exact),
    Case("numpy", "lengths2d", LENGTHS2, 4, _numpy(squared_length_signs), exact_lengths),
    Case("c", "orient2d", TRIPLES2, 3, _c("orient2d_filter"), orient2d_exact),
    Case("c", "incircle", QUADRUPLES2, 4, _c("incircle_filter"), incircle_exact),
    Case("c", "lengths2d", LENGTHS2, 4, _c("squared_lengths_filter"), exact_lengths),
    Case("c", "dot", RIGHT_ANGLES, 3, _c("dot_filter"), exact_dot),
]
# copies in space: checked against the Python filter and the exact sign (the bound-crossing
# test below moves points in the plane)
SPACE = [
    Case("numpy", "orient3d", QUADRUPLES3, 4, _numpy3(orient3d_signs), orient3d_exact, 50),
]
GRID = [
    Case("c-grid", "orient2d", TRIPLES2, 3, _c_grid("grid_orient2d"), orient2d_exact),
    Case("c-grid", "incircle", QUADRUPLES2, 4, _c_grid("grid_incircle"), incircle_exact),
    Case("c-grid", "lengths2d", LENGTHS2, 4, _c_grid("grid_squared_lengths"), exact_lengths),
    Case("c-grid", "dot", RIGHT_ANGLES, 3, _c_grid("grid_dot"), exact_dot),
]
PYTHON_BY_PREDICATE = {case.predicate: case for case in PYTHON}


def _needs_backend(case: Case) -> None:
    if case.backend.startswith("c") and cfilters is None:
        pytest.importorskip("geomexact.kernel.cfilters")


def _run(case: Case, check: Callable[[Case, tuple[Any, ...]], None]) -> None:
    examples = min(case.max_examples, settings().max_examples)  # the CI profile has fewer
    @settings(max_examples=examples, suppress_health_check=[HealthCheck.too_slow], database=None)
    @given(case.points)
    def run(points: tuple[Any, ...]) -> None:
        check(case, points)

    run()


def _certified_signs_are_exact(case: Case, points: tuple[Any, ...]) -> None:
    queries = case.queries(points)
    for query, decision in zip(queries, case.decide(queries), strict=True):
        if decision is not None:
            assert decision == int(case.exact(*query)), (case.id, query, decision)


def _same_decisions_as_python(case: Case, points: tuple[Any, ...]) -> None:
    queries = case.queries(points)
    expected = PYTHON_BY_PREDICATE[case.predicate].decide(queries)
    assert case.decide(queries) == expected, (case.id, queries)


@pytest.mark.parametrize("case", PYTHON + COPIES + SPACE + GRID, ids=lambda case: case.id)
def test_a_certified_sign_is_the_exact_sign(case: Case) -> None:
    _needs_backend(case)
    _run(case, _certified_signs_are_exact)


@pytest.mark.parametrize("case", COPIES + SPACE, ids=lambda case: case.id)
def test_every_copy_certifies_what_the_python_filter_certifies(case: Case) -> None:
    _needs_backend(case)
    _run(case, _same_decisions_as_python)


# Exactly degenerate configurations of each predicate of the copies: moving one coordinate
# away from them by n ulps crosses the filter's bound at some n.
FINITE: tuple[Magnitude, ...] = ("ordinary", "decimal", "dyadic", "huge", "tiny")  # no NaN
DEGENERATE = {
    "orient2d": collinear_triples(FINITE),
    "incircle": cocircular_quadruples(FINITE),
    "lengths2d": _equal_lengths(),
    "dot": _right_angles(),
}


def _moved(query: Query, index: int, axis: int, steps: int) -> Query:
    """``query`` with coordinate ``axis`` of point ``index`` moved by ``steps`` ulps of its
    double (to an exact double value)."""
    point = query[index]
    value = float(point[axis])
    coordinates = [point.x, point.y]
    coordinates[axis] = mpq(value) + steps * mpq(math.ulp(value))
    return (*query[:index], point2(*coordinates), *query[index + 1 :])


def _boundary(decide: Callable[[Sequence[Query]], Decisions], query: Query, index: int,
              axis: int, direction: int) -> tuple[Query, Query] | None:
    """Two queries one ulp apart, the first undecided by ``decide`` and the second decided,
    found by bisection on the number of ulps a coordinate moves; None when moving it never
    decides (or the start is decided already)."""

    def decided(steps: int) -> bool:
        return decide([_moved(query, index, axis, direction * steps)])[0] is not None

    if not math.isfinite(query[index][axis + 2]) or decided(0):
        return None
    high = next((2**k for k in range(64) if decided(2**k)), None)
    if high is None:
        return None
    low = high // 2 if high > 1 else 0
    while high - low > 1:
        middle = (low + high) // 2
        if decided(middle):
            high = middle
        else:
            low = middle
    return (_moved(query, index, axis, direction * low),
            _moved(query, index, axis, direction * high))


@pytest.mark.parametrize("case", COPIES, ids=lambda case: case.id)
def test_every_copy_agrees_with_the_python_filter_at_its_bound(case: Case) -> None:
    """Right where the Python filter starts to decide (a float determinant about its bound)
    every copy decides the same way, with the exact sign: a copy whose bound differs by a
    few ulps of the bound would already disagree on one side."""
    _needs_backend(case)
    python = PYTHON_BY_PREDICATE[case.predicate].decide

    def check(case: Case, drawn: tuple[Any, ...]) -> None:
        query, index, axis, direction = drawn
        pair = _boundary(python, query, index % len(query), axis, direction)
        if pair is None:
            return
        undecided, decided = pair
        assert python([undecided, decided])[0] is None
        assert case.decide([undecided, decided]) == python([undecided, decided]), case.id
        _certified_signs_are_exact(case, decided)

    strategy = st.tuples(DEGENERATE[case.predicate], st.integers(0, 5), st.integers(0, 1),
                         st.sampled_from((-1, 1)))
    _run(attrs.evolve(case, points=strategy, max_examples=50), check)


@pytest.mark.parametrize("case", PYTHON + COPIES + GRID, ids=lambda case: case.id)
def test_every_backend_decides_ordinary_inputs(case: Case) -> None:
    """Not vacuous: on ordinary inputs (small inexact rationals, no degeneracy) every
    backend certifies almost every query."""
    _needs_backend(case)
    rng = random.Random(7)

    def coordinate() -> Fraction:
        # grid coordinates are integers (scaled): small denominators would not fit 2**60
        denominator = 1 if case.backend == "c-grid" else rng.randrange(1, 1000)
        return Fraction(rng.randrange(-10**6, 10**6), denominator)

    decided = total = 0
    dimension = 3 if case.predicate in ("orient3d", "insphere", "lengths3d") else 2
    make = point2 if dimension == 2 else point3
    count = 3 if case.predicate == "angle" else case.size
    for _ in range(50):
        points: tuple[Any, ...] = tuple(make(*(coordinate() for _ in range(dimension)))
                                        for _ in range(count))
        if case.predicate == "angle":
            points = (*points, AngleThreshold.from_degrees(rng.randrange(1, 180)))
        queries = case.queries(points)
        decisions = case.decide(queries)
        decided += sum(d is not None for d in decisions)
        total += len(decisions)
    assert decided >= 0.9 * total, (case.id, decided, total)


def _orient2d_shortcut(a: Point2, b: Point2, c: Point2) -> bool:
    """orient2d decides by the signs of its two products alone (before its bound)."""
    left = (a.fx - c.fx) * (b.fy - c.fy)
    right = (a.fy - c.fy) * (b.fx - c.fx)
    return (left > 0.0 > right) or (left < 0.0 < right)


def test_orient2d_float_is_orient2d_s_bound() -> None:
    """``_orient2d_float`` (compare_areas' copy of orient2d's filter) decides exactly where
    orient2d's bound does, random and right at the bound (orient2d also has its sign
    shortcut, which ``_orient2d_float`` lacks)."""
    case = PYTHON_BY_PREDICATE["orient2d-float"]
    python = PYTHON_BY_PREDICATE["orient2d"].decide

    def same(queries: Sequence[Query]) -> None:
        for query, expected, decision in zip(
            queries, python(queries), case.decide(queries), strict=True
        ):
            assert decision == expected or _orient2d_shortcut(*query), query

    def check(case: Case, drawn: tuple[Any, ...]) -> None:
        query, index, axis, direction = drawn
        same(_permutations(query, 3))
        pair = _boundary(python, query, index % 3, axis, direction)
        if pair is not None:
            same(pair)

    strategy = st.tuples(st.one_of(DEGENERATE["orient2d"], TRIPLES2), st.integers(0, 5),
                         st.integers(0, 1), st.sampled_from((-1, 1)))
    _run(attrs.evolve(case, points=strategy, max_examples=100), check)
