"""The tables a transient edits: a persistent map's mutation (O(1) to open and to seal,
each write copies a path of the trie: right for a few steps on a large mesh) or, in
*batch* mode, a plain dict (O(n) to open and to seal, each write a tenth of the cost:
right for a long run of steps, such as replaying a trace).  Both take the same reads and
writes (``t[k] = v``, ``del t[k]``, ``get``, ``in``, ``len``)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any, Protocol, TypeVar, overload

import immutables

__all__ = ["EditableTable", "open_table", "sealed_table", "table_snapshot"]

K = TypeVar("K")
V = TypeVar("V")
T = TypeVar("T")


class EditableTable(Protocol[K, V]):
    """What a transient does with a table: a dict and a map's mutation both offer it."""

    def __getitem__(self, key: K, /) -> V: ...

    def __setitem__(self, key: K, value: V, /) -> None: ...

    def __delitem__(self, key: K, /) -> None: ...

    def __contains__(self, key: object, /) -> bool: ...

    def __len__(self) -> int: ...

    def __iter__(self) -> Iterator[K]: ...

    @overload
    def get(self, key: K, /) -> V | None: ...

    @overload
    def get(self, key: K, default: T, /) -> V | T: ...

    def pop(self, key: K, /, *default: Any) -> V: ...


def open_table(table: immutables.Map[K, V], batch: bool) -> EditableTable[K, V]:
    """An editable table holding ``table``: a dict copy in batch mode, else its
    mutation."""
    if batch:
        return dict(table.items())
    return table.mutate()  # type: ignore[return-value]


def sealed_table(table: EditableTable[K, V]) -> immutables.Map[K, V]:
    """The persistent map of an editable table (which is then not to be edited)."""
    if isinstance(table, dict):
        return immutables.Map(table)
    return table.finish()  # type: ignore[attr-defined,no-any-return]


def table_snapshot(table: EditableTable[K, V]) -> tuple[immutables.Map[K, V],
                                                        EditableTable[K, V]]:
    """(the table's current content as a persistent map, the table to go on editing):
    O(1) for a mutation (finished and reopened), O(n) for a dict (copied)."""
    if isinstance(table, dict):
        return immutables.Map(table), table
    snapshot: immutables.Map[K, V] = table.finish()  # type: ignore[attr-defined]
    return snapshot, snapshot.mutate()  # type: ignore[return-value]
