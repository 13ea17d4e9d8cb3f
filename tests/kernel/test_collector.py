"""Pausing the cyclic collector (``geomexact.kernel.collector``): disabled inside the block,
its previous state restored afterwards (also when the block raises), and the block's
objects moved to the oldest generation when the collector was running."""

from __future__ import annotations

import gc
from collections.abc import Iterator

import pytest

from geomexact.kernel.collector import collector_paused


class Sentinel:
    """A container object the collector tracks."""


@pytest.fixture(autouse=True)
def restore_collector() -> Iterator[None]:
    """Whatever a test does, the collector leaves it as it found it."""
    enabled = gc.isenabled()
    yield
    gc.unfreeze()
    if enabled:
        gc.enable()
    else:
        gc.disable()


def in_generation(obj: object, generation: int) -> bool:
    return any(candidate is obj for candidate in gc.get_objects(generation=generation))


@pytest.mark.parametrize("enabled", [True, False])
def test_the_collector_is_paused_inside_and_restored_after(enabled: bool) -> None:
    """Inside the block the collector is off; afterwards it is on again exactly when it was
    on before."""
    gc.enable() if enabled else gc.disable()
    with collector_paused():
        assert not gc.isenabled()
    assert gc.isenabled() == enabled


@pytest.mark.parametrize("enabled", [True, False])
def test_the_state_is_restored_when_the_block_raises(enabled: bool) -> None:
    """An exception leaving the block restores the previous state and propagates
    unchanged."""
    gc.enable() if enabled else gc.disable()
    error = KeyError("from the block")
    with pytest.raises(KeyError) as caught, collector_paused():
        assert not gc.isenabled()
        raise error
    assert caught.value is error
    assert gc.isenabled() == enabled


def test_nested_blocks_restore_each_level() -> None:
    """An inner block leaves the collector paused for the rest of the outer block; the
    outer block re-enables it."""
    gc.enable()
    with collector_paused():
        with collector_paused():
            assert not gc.isenabled()
        assert not gc.isenabled()
    assert gc.isenabled()


def test_generator_closed_early_restores_the_state() -> None:
    """A generator suspended inside the block and closed before finishing restores the
    collector (GeneratorExit passes through the block)."""
    gc.enable()

    def producer() -> Iterator[int]:
        with collector_paused():
            yield 1
            yield 2

    values = producer()
    assert next(values) == 1
    assert not gc.isenabled()
    values.close()
    assert gc.isenabled()


def test_objects_made_in_the_block_end_in_the_oldest_generation() -> None:
    """When the collector was running, what the block allocated is moved to the oldest
    generation, so the next young collection does not walk it, and nothing stays
    frozen."""
    gc.enable()
    gc.collect()
    with collector_paused():
        made = [Sentinel() for _ in range(1000)]
        assert in_generation(made[0], 0)
    assert in_generation(made[0], 2) and in_generation(made[-1], 2)
    assert not in_generation(made[0], 0)
    assert gc.get_freeze_count() == 0
    assert gc.get_count()[0] < 100


def test_nothing_is_moved_when_the_collector_was_off() -> None:
    """With the collector already disabled the block changes no generation."""
    gc.disable()
    gc.collect()
    with collector_paused():
        made = Sentinel()
    assert in_generation(made, 0)
    assert not gc.isenabled()


def test_objects_stay_collectable_after_the_block() -> None:
    """Moving objects to the oldest generation keeps nothing alive: a reference cycle made
    in the block is freed by a full collection once it is unreachable."""
    gc.enable()
    freed = []

    class Node:
        def __init__(self) -> None:
            self.me = self

        def __del__(self) -> None:
            freed.append(True)

    with collector_paused():
        Node()
        assert freed == []
    gc.collect()
    assert freed == [True]


def test_a_freeze_made_before_the_block_survives_it() -> None:
    """Objects the caller froze before the block are still frozen after it."""
    gc.enable()
    gc.collect()
    gc.freeze()
    frozen = gc.get_freeze_count()
    assert frozen > 0
    with collector_paused():
        pass
    assert gc.get_freeze_count() == frozen
