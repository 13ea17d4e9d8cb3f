"""Values derived from an immutable value, made on first use and kept.

A snapshot built from a kernel's arrays defers its persistent tables, and a tetrahedral
snapshot its sorted cell array, until someone reads them.  :class:`Derived` is the one
mechanism for that: each snapshot owns one (never passed on by ``attrs.evolve``, never
shared, never compared), and each named value in it is made once by the function the
reader passes and is never replaced.  The snapshot's own fields never change.

>>> cache = Derived()
>>> cache.get("square", lambda: 7 * 7)
49
>>> cache.get("square", lambda: 0)  # made once: the first value stays
49
>>> cache.known("square"), cache.known("cube")
(True, False)
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["Derived"]

T = TypeVar("T")


class Derived:
    """Write-once named values derived from the value that owns this: :meth:`get` makes a
    missing one by ``make()`` (under a lock, so two threads make it once) and keeps it."""

    __slots__ = ("_lock", "_values")

    def __init__(self) -> None:
        self._values: dict[str, Any] = {}
        self._lock = threading.RLock()  # a make may read another value

    def get(self, name: str, make: Callable[[], T]) -> T:
        """The value ``name``, made by ``make()`` the first time."""
        try:
            value: T = self._values[name]
            return value
        except KeyError:
            pass
        with self._lock:
            if name not in self._values:
                self._values[name] = make()
            value = self._values[name]
        return value

    def known(self, name: str) -> bool:
        """True once ``name`` has been made."""
        return name in self._values

    def __getstate__(self) -> dict[str, Any]:
        return dict(self._values)

    def __setstate__(self, values: dict[str, Any]) -> None:
        self._values = dict(values)
        self._lock = threading.RLock()

    def __repr__(self) -> str:
        return f"Derived({sorted(self._values)})"
