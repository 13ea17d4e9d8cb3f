"""The refinement work queue (``geomexact.mesh2d.refinement.queue``): it pops the smallest
(key, canonical triangle) exactly as one heap of such pairs would (``specs/refine.md``,
"The pop order"): equal keys in increasing vertex-id order, keys beyond the double range
ordered exactly; ``rank`` is a monotone float approximation of a key."""

from __future__ import annotations

import heapq
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.kernel.numbers import mpq
from geomexact.mesh2d.refinement.queue import WorkQueue, rank
from geomexact.strategies import coordinates, rationals

FEW = settings(max_examples=min(settings().max_examples, 60))

triangles = st.tuples(st.integers(0, 30), st.integers(0, 30), st.integers(0, 30))
# keys of every magnitude, with many exact ties and pairs closer than a double can tell
keys = st.one_of(
    coordinates(),
    rationals(max_numerator=4, max_denominator=3),
    st.builds(lambda k: 1 + mpq(k, 2**80), st.integers(-3, 3)),
)


def drain(queue: WorkQueue) -> list[tuple[int, int, int]]:
    popped = []
    while (triangle := queue.pop()) is not None:
        popped.append(triangle)
    return popped


# -- rank -------------------------------------------------------------------------------------
@FEW
@given(keys, keys)
def test_rank_is_monotone(a: mpq, b: mpq) -> None:
    """rank never inverts two keys: a < b implies rank(a) <= rank(b), equal keys rank
    alike."""
    if a < b:
        assert rank(a) <= rank(b)
    elif a == b:
        assert rank(a) == rank(b)


def test_rank_beyond_the_double_range() -> None:
    """Keys too large for a double rank as ±infinity, keys too small as zero, and ordinary
    keys as their nearest double."""
    assert rank(mpq(10) ** 400) == math.inf
    assert rank(-(mpq(10) ** 400)) == -math.inf
    assert rank(10**400) == math.inf
    assert rank(mpq(1, 10**400)) == 0.0
    assert rank(mpq(1, 3)) == 1 / 3
    assert rank(7) == 7.0


def test_rank_of_keys_without_a_float_is_zero() -> None:
    """A key that is not a number (a tuple) ranks 0.0, leaving the order to the key."""
    assert rank((mpq(1), 2)) == 0.0
    assert rank("text") == 0.0


# -- the queue --------------------------------------------------------------------------------
def test_an_empty_queue_pops_none() -> None:
    """pop on an empty queue returns None and the size stays 0."""
    queue = WorkQueue()
    assert queue.pop() is None and queue.size == 0


def test_equal_keys_pop_in_increasing_triangle_order() -> None:
    """Triangles with the same key come out by increasing canonical vertex triple, whatever
    the push order; smaller keys first."""
    queue = WorkQueue()
    for triangle in [(3, 4, 5), (0, 7, 9), (0, 2, 8), (1, 2, 3), (0, 2, 5)]:
        queue.push(mpq(1, 2), triangle)
    queue.push(mpq(1, 3), (9, 10, 11))
    queue.push(mpq(2, 4), (0, 0, 1))
    assert queue.size == 7
    assert drain(queue) == [(9, 10, 11), (0, 0, 1), (0, 2, 5), (0, 2, 8), (0, 7, 9),
                            (1, 2, 3), (3, 4, 5)]
    assert queue.size == 0 and queue.buckets == {} and queue.keys == []


def test_keys_a_double_cannot_tell_apart_are_ordered_exactly() -> None:
    """Keys equal as doubles but not as rationals, and keys beyond the double range
    (ranked ±inf alike), pop in exact order."""
    queue = WorkQueue()
    queue.push(1 + mpq(2, 2**80), (0, 1, 2))
    queue.push(1 + mpq(1, 2**80), (5, 6, 7))
    queue.push(mpq(1), (8, 9, 10))
    queue.push(mpq(10) ** 401, (1, 1, 1))
    queue.push(mpq(10) ** 400, (2, 2, 2))
    queue.push(-(mpq(10) ** 400), (3, 3, 3))
    queue.push(-(mpq(10) ** 401), (4, 4, 4))
    assert drain(queue) == [(4, 4, 4), (3, 3, 3), (8, 9, 10), (5, 6, 7), (0, 1, 2),
                            (2, 2, 2), (1, 1, 1)]


def test_a_triangle_pushed_twice_pops_twice() -> None:
    """Like a heap of pairs, the queue keeps duplicates (lazy deletion skips them later)."""
    queue = WorkQueue()
    queue.push(mpq(1), (0, 1, 2))
    queue.push(mpq(1), (0, 1, 2))
    queue.push(mpq(2), (0, 1, 2))
    assert drain(queue) == [(0, 1, 2)] * 3


def test_tuple_keys_are_ordered_exactly() -> None:
    """Keys that are tuples (no float rank) still pop in exact tuple order."""
    queue = WorkQueue()
    queue.push((mpq(2), 0), (0, 1, 2))
    queue.push((mpq(1), 5), (3, 4, 5))
    queue.push((mpq(1), 2), (6, 7, 8))
    assert drain(queue) == [(6, 7, 8), (3, 4, 5), (0, 1, 2)]


@FEW
@given(st.lists(st.tuples(keys, triangles), max_size=40))
def test_pop_order_is_the_sorted_order_of_pairs(pairs: list[tuple[mpq, tuple[int, int, int]]]
                                               ) -> None:
    """Pushing pairs then draining gives the triangles of the pairs in sorted
    (key, triangle) order."""
    queue = WorkQueue()
    for key, triangle in pairs:
        queue.push(key, triangle)
    assert queue.size == len(pairs)
    assert drain(queue) == [triangle for _, triangle in sorted(pairs)]


@FEW
@given(st.lists(st.one_of(st.tuples(keys, triangles), st.none()), max_size=60))
def test_interleaved_pushes_and_pops_match_a_heap_of_pairs(
    operations: list[tuple[mpq, tuple[int, int, int]] | None],
) -> None:
    """Any interleaving of pushes and pops (None) gives what a single heap of (key,
    triangle) pairs gives, and the same size at every moment."""
    queue = WorkQueue()
    reference: list[tuple[mpq, tuple[int, int, int]]] = []
    for operation in operations:
        if operation is None:
            expected = heapq.heappop(reference)[1] if reference else None
            assert queue.pop() == expected
        else:
            queue.push(*operation)
            heapq.heappush(reference, operation)
        assert queue.size == len(reference)
    assert drain(queue) == [triangle for _, triangle in sorted(reference)]


@pytest.mark.parametrize("order", [range(12), reversed(range(12))], ids=["up", "down"])
def test_the_order_does_not_depend_on_push_order(order: range) -> None:
    """The same pairs pushed in opposite orders pop identically."""
    queue = WorkQueue()
    for i in order:
        queue.push(mpq(i % 3, 2), (i % 5, i, 20 - i))
    expected = [t for _, t in sorted((mpq(i % 3, 2), (i % 5, i, 20 - i)) for i in range(12))]
    assert drain(queue) == expected
