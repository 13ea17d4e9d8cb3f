"""Exact segment relations (``geomexact.mesh2d.segments``): when two segments meet other than
at a common endpoint, which pairs of a set meet (a sweep, checked against all pairs), and
the exact crossing point of two lines."""

from __future__ import annotations

from collections import Counter

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.segments import (
    crossing_point,
    meeting_pairs,
    segments_meet_improperly,
    within_box,
)
from geomexact.strategies import coordinates, points2, rationals

FEW = settings(max_examples=min(settings().max_examples, 60))
Segment = tuple[int, int]


# -- a brute-force reference: exact parametric intersection ----------------------------------
def reference_meet(points: list[Point2], first: Segment, second: Segment) -> bool:
    """True when the closed segments share a point other than a common endpoint (by id),
    from the exact parameters of their intersection."""
    (u, v), (a, b) = first, second
    shared = {u, v} & {a, b}
    if len(shared) == 2:
        return True
    p, q, r, s = points[u], points[v], points[a], points[b]
    dx, dy = q.x - p.x, q.y - p.y
    ex, ey = s.x - r.x, s.y - r.y
    wx, wy = r.x - p.x, r.y - p.y
    denominator = dx * ey - dy * ex
    if denominator != 0:  # the lines meet in exactly one point
        t = (wx * ey - wy * ex) / denominator
        w = (wx * dy - wy * dx) / denominator
        inside = 0 <= t <= 1 and 0 <= w <= 1
        return inside and not shared  # a shared endpoint is that one point
    if wx * dy - wy * dx != 0:  # distinct parallel lines
        return False
    length = dx * dx + dy * dy
    tr = (wx * dx + wy * dy) / length
    ts = ((s.x - p.x) * dx + (s.y - p.y) * dy) / length
    low, high = max(mpq(0), min(tr, ts)), min(mpq(1), max(tr, ts))
    if low > high:
        return False
    return not shared or low < high  # with a common endpoint: more than that point


@st.composite
def segment_sets(
    draw: st.DrawFn, min_segments: int = 0, max_segments: int = 10
) -> tuple[list[Point2], list[Segment]]:
    """Points on a small grid (with coincident points under different ids), mapped by a
    random similarity, and segments of non-zero length between them."""
    raw = draw(st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)),
                        min_size=2, max_size=9).filter(lambda raw: len(set(raw)) > 1))
    scale = draw(rationals(max_numerator=1000, max_denominator=1000).filter(bool))
    dx, dy = draw(coordinates(("ordinary", "decimal", "huge"))), draw(rationals())
    points = [point2(x * scale + dx, y * scale + dy) for x, y in raw]
    n = len(points)
    pairs = st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)).filter(
        lambda pair: points[pair[0]] != points[pair[1]])
    return points, draw(st.lists(pairs, min_size=min_segments, max_size=max_segments))


def grid(*coordinates: tuple[int, int]) -> list[Point2]:
    return [point2(x, y) for x, y in coordinates]


# -- two segments -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("points", "first", "second", "meet"),
    [
        (grid((0, 0), (2, 2), (0, 2), (2, 0)), (0, 1), (2, 3), True),  # proper crossing
        (grid((0, 0), (2, 0), (1, 0), (1, 5)), (0, 1), (2, 3), True),  # T: endpoint inside
        (grid((0, 0), (2, 0), (1, 0), (3, 0)), (0, 1), (2, 3), True),  # collinear overlap
        (grid((0, 0), (1, 0), (2, 0), (3, 0)), (0, 1), (2, 3), False),  # collinear apart
        (grid((0, 0), (1, 0), (1, 0), (3, 0)), (0, 1), (2, 3), True),  # touch, other ids
        (grid((0, 0), (1, 0), (0, 1), (1, 1)), (0, 1), (2, 3), False),  # parallel
        (grid((0, 0), (1, 0), (5, 5), (5, 9)), (0, 1), (2, 3), False),  # far apart
        (grid((0, 0), (2, 0), (1, 1)), (0, 1), (0, 2), False),  # common endpoint only
        (grid((0, 0), (2, 0), (1, 0)), (0, 1), (0, 2), True),  # common end, overlapping
        (grid((0, 0), (2, 0), (-1, 0)), (0, 1), (0, 2), False),  # common end, opposite
        (grid((0, 0), (2, 0)), (0, 1), (1, 0), True),  # the same segment twice
        (grid((0, 0), (2, 0)), (0, 1), (0, 1), True),
    ],
)
def test_segments_meet_improperly_cases(
    points: list[Point2], first: Segment, second: Segment, meet: bool
) -> None:
    """Crossings, touchings, overlaps and the same segment twice meet; apart, parallel
    and common-endpoint-only pairs do not; the answer is symmetric."""
    assert segments_meet_improperly(points, first, second) is meet
    assert segments_meet_improperly(points, second, first) is meet
    flipped = (first[1], first[0])
    assert segments_meet_improperly(points, flipped, second) is meet


def test_meeting_is_exact_far_below_double_precision() -> None:
    """Segments 2^-200 apart do not meet; moved onto each other they do."""
    gap = mpq(1, 2**200)
    apart = [*grid((0, 0), (1, 0)), point2(mpq(1, 2), gap), point2(mpq(1, 2), 1)]
    assert segments_meet_improperly(apart, (0, 1), (2, 3)) is False
    touching = [*grid((0, 0), (1, 0)), point2(mpq(1, 2), 0), point2(mpq(1, 2), 1)]
    assert segments_meet_improperly(touching, (0, 1), (2, 3)) is True


@FEW
@given(segment_sets(min_segments=2, max_segments=2))
def test_segments_meet_improperly_agrees_with_brute_force(
    case: tuple[list[Point2], list[Segment]],
) -> None:
    """On random near-degenerate inputs the predicate equals the exact parametric
    reference, both ways round."""
    points, segments = case
    first, second = segments
    expected = reference_meet(points, first, second)
    assert segments_meet_improperly(points, first, second) == expected
    assert segments_meet_improperly(points, second, first) == expected


def test_points_may_be_a_mapping_of_ids() -> None:
    """Points can be given as a mapping from id to point (a mesh's vertex table)."""
    points = {10: point2(0, 0), 20: point2(2, 2), 30: point2(0, 2), 40: point2(2, 0)}
    assert segments_meet_improperly(points, (10, 20), (30, 40))
    assert meeting_pairs(points, [(10, 20), (30, 40)]) == [((10, 20), (30, 40))]


# -- many segments ------------------------------------------------------------------------------
def unordered(pairs: list[tuple[Segment, Segment]]) -> Counter[tuple[Segment, Segment]]:
    return Counter(tuple(sorted(pair)) for pair in pairs)  # type: ignore[misc]


@FEW
@given(segment_sets())
def test_meeting_pairs_finds_exactly_the_meeting_pairs(
    case: tuple[list[Point2], list[Segment]],
) -> None:
    """The sweep reports every pair (each once) that the brute-force reference says meets,
    and no other."""
    points, segments = case
    expected = [
        (segments[i], segments[j])
        for i in range(len(segments))
        for j in range(i + 1, len(segments))
        if reference_meet(points, segments[i], segments[j])
    ]
    assert unordered(meeting_pairs(points, segments)) == unordered(expected)


@FEW
@given(segment_sets(), st.randoms(use_true_random=False))
def test_meeting_pairs_does_not_depend_on_the_input_order(
    case: tuple[list[Point2], list[Segment]], random: object
) -> None:
    """The pairs come in sweep order: the same list for any order of the input."""
    points, segments = case
    shuffled = list(segments)
    random.shuffle(shuffled)  # type: ignore[attr-defined]
    assert meeting_pairs(points, shuffled) == meeting_pairs(points, segments)


def test_meeting_pairs_of_few_segments() -> None:
    """No segments or one segment: no pairs; a star of segments from one vertex: none."""
    points = grid((0, 0), (1, 0), (0, 1), (-1, -1))
    assert meeting_pairs(points, []) == []
    assert meeting_pairs(points, [(0, 1)]) == []
    assert meeting_pairs(points, [(0, 1), (0, 2), (0, 3)]) == []
    assert meeting_pairs(points, [(0, 1), (1, 2), (2, 0)]) == []


def test_meeting_pairs_in_sweep_order() -> None:
    """Each pair lists first the segment the sweep met first (smaller leftmost x)."""
    points = grid((0, 0), (4, 4), (1, 4), (3, 0), (2, -1), (2, 5))
    pairs = meeting_pairs(points, [(4, 5), (2, 3), (0, 1)])
    assert pairs == [((0, 1), (2, 3)), ((0, 1), (4, 5)), ((2, 3), (4, 5))]


# -- crossing points and boxes ----------------------------------------------------------------
def test_crossing_point_of_the_diagonals() -> None:
    """The diagonals of the square [0, 2]^2 cross at (1, 1); the lines of two segments that
    do not reach each other still cross exactly."""
    assert crossing_point(*grid((0, 0), (2, 2), (0, 2), (2, 0))) == point2(1, 1)
    assert crossing_point(*grid((0, 0), (1, 0), (5, 1), (5, 3))) == point2(5, 0)
    p = crossing_point(*grid((0, 0), (3, 1), (0, 1), (1, 0)))
    assert p == point2(mpq(3, 4), mpq(1, 4))


@FEW
@given(points2(), points2(), points2(), points2())
def test_crossing_point_lies_exactly_on_both_lines(
    p: Point2, q: Point2, r: Point2, s: Point2
) -> None:
    """For any two non-parallel lines, of any magnitude, the crossing point is exactly on
    both; parallel lines raise ValueError."""
    parallel = (q.x - p.x) * (s.y - r.y) == (q.y - p.y) * (s.x - r.x)
    if parallel:
        with pytest.raises(ValueError, match="parallel"):
            crossing_point(p, q, r, s)
        return
    x = crossing_point(p, q, r, s)
    assert orient2d(p, q, x) == Orientation.COLLINEAR
    assert orient2d(r, s, x) == Orientation.COLLINEAR
    assert crossing_point(r, s, p, q) == x == crossing_point(q, p, s, r)


def test_crossing_point_of_parallel_or_equal_lines_is_refused() -> None:
    """Parallel, identical and degenerate (zero-length) lines have no single crossing."""
    for points in (grid((0, 0), (1, 1), (0, 1), (1, 2)), grid((0, 0), (1, 1), (2, 2), (3, 3)),
                   grid((0, 0), (0, 0), (0, 1), (1, 2))):
        with pytest.raises(ValueError, match="parallel"):
            crossing_point(*points)


@FEW
@given(segment_sets(min_segments=2, max_segments=2))
def test_a_proper_crossing_lies_in_both_boxes(case: tuple[list[Point2], list[Segment]]) -> None:
    """When two segments without common ends meet and are not parallel, their crossing
    point lies in both closed bounding boxes."""
    points, segments = case
    if set(segments[0]) & set(segments[1]):
        return
    (u, v), (a, b) = segments
    if not segments_meet_improperly(points, (u, v), (a, b)):
        return
    p, q, r, s = points[u], points[v], points[a], points[b]
    if (q.x - p.x) * (s.y - r.y) == (q.y - p.y) * (s.x - r.x):
        return
    x = crossing_point(p, q, r, s)
    assert within_box(x, p, q) and within_box(x, r, s)


def test_within_box_is_the_closed_box() -> None:
    """Corners and sides are inside; a point just outside in x or y is not; the corner
    order does not matter."""
    q, r = point2(0, 0), point2(2, 1)
    for inside in ((0, 0), (2, 1), (1, mpq(1, 2)), (2, 0), (0, 1)):
        assert within_box(point2(*inside), q, r) and within_box(point2(*inside), r, q)
    tiny = mpq(1, 2**100)
    for outside in ((-tiny, 0), (1, 1 + tiny), (2 + tiny, 1), (1, -tiny)):
        assert not within_box(point2(*outside), q, r)
