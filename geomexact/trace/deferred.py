"""A run's steps or digests kept in a compiled kernel's compact records and made into
Python values only when they are read (:class:`DeferredSequence`).

A kernel records each step as a few machine integers; making the ``Step`` objects and
the digest ints of a long run costs a large share of its time and memory, and most runs
(a refinement whose trace is not written) never read them.  A deferred sequence knows its
length at once and makes every item on first use, once; it then behaves as the tuple of
those items (equality — with a list of the same items too —, hashing, slicing,
pickling)."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Generic, TypeVar, overload

__all__ = ["DeferredSequence", "deferred_trace"]

T = TypeVar("T")


class DeferredSequence(Sequence[T], Generic[T]):
    """An immutable sequence of ``length`` items that ``make()`` returns (called once, on
    first use); ``item(i)``, when given, makes one item without the others (the last
    digest of a trace, read by itself)."""

    __slots__ = ("_item", "_items", "_length", "_lock", "_make")

    def __init__(self, length: int, make: Callable[[], Sequence[T]],
                 item: Callable[[int], T] | None = None) -> None:
        self._length = length
        self._make: Callable[[], Sequence[T]] | None = make
        self._item = item
        self._items: tuple[T, ...] | None = None
        self._lock = threading.Lock()

    def items(self) -> tuple[T, ...]:
        """The items as a tuple (made on the first call)."""
        items = self._items
        if items is None:
            with self._lock:
                if self._items is None:
                    assert self._make is not None
                    made = tuple(self._make())
                    if len(made) != self._length:
                        raise ValueError(f"a deferred sequence of {self._length} items "
                                         f"made {len(made)}")
                    self._items, self._make = made, None
                items = self._items
        return items

    @property
    def made(self) -> bool:
        """Whether the items exist yet."""
        return self._items is not None

    def __len__(self) -> int:
        return self._length

    @overload
    def __getitem__(self, index: int) -> T: ...

    @overload
    def __getitem__(self, index: slice) -> tuple[T, ...]: ...

    def __getitem__(self, index: int | slice) -> T | tuple[T, ...]:
        if isinstance(index, int) and self._items is None and self._item is not None:
            position = index + self._length if index < 0 else index
            if not 0 <= position < self._length:
                raise IndexError("deferred sequence index out of range")
            return self._item(position)
        return self.items()[index]

    def __iter__(self) -> Iterator[T]:
        return iter(self.items())

    def __eq__(self, other: object) -> bool:
        # equal to another deferred sequence, a tuple or a list of the same items (the
        # steps an engine hands over as a list compare equal to a kernel's deferred ones)
        if isinstance(other, DeferredSequence):
            return self.items() == other.items()
        if isinstance(other, (tuple, list)):
            return self.items() == tuple(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self.items())

    def __add__(self, other: Sequence[T]) -> tuple[T, ...]:
        return self.items() + tuple(other)

    def __radd__(self, other: Sequence[T]) -> tuple[T, ...]:
        return tuple(other) + self.items()

    def __reduce__(self) -> tuple[Any, ...]:
        return (tuple, (self.items(),))  # a pickled trace holds a plain tuple

    def __repr__(self) -> str:
        return repr(self.items())


def deferred_trace(kernel: Any) -> tuple[DeferredSequence[Any], DeferredSequence[int]]:
    """The steps and digests of a compiled kernel that sealed its run, deferred: the
    kernel offers ``step_count``, ``steps()``, ``digests()`` and ``digest_at(i)``."""
    count = kernel.step_count
    return (DeferredSequence(count, kernel.steps),
            DeferredSequence(count, kernel.digests, kernel.digest_at))
