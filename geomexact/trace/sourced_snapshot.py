"""What the snapshots whose tables may come from arrays share (``Mesh2``, ``Mesh3``): a
snapshot is given either its persistent tables or a source of arrays (a kernel's or a
bulk builder's), and then builds the tables from the source on first use, once, kept in
its :class:`~geomexact.kernel.derived.Derived` under ``"tables"``."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Generic, Protocol, TypeVar

import immutables

from geomexact.kernel import digest as _digest
from geomexact.kernel.derived import Derived

__all__ = ["SourcedSnapshot", "TableArrays"]

P = TypeVar("P")
P_co = TypeVar("P_co", covariant=True)
T = TypeVar("T", bound=tuple[immutables.Map[int, Any], Any, Any])
T_co = TypeVar("T_co", covariant=True)


class TableArrays(Protocol[P_co, T_co]):
    """A snapshot's source: the point of each vertex id 0..n-1 and the tables built from
    the arrays (the vertex table first)."""

    @property
    def points(self) -> Sequence[P_co]: ...

    def tables(self) -> T_co: ...


class SourcedSnapshot(Generic[P, T]):
    """The reads of a snapshot (an attrs class with the fields ``_vertices``, ``_source``,
    ``_derived`` and ``digest``) whose tables are None when it was given a source:
    vertices with points ``P``, the tables ``T`` built from the source."""

    __slots__ = ()

    _vertices: immutables.Map[int, P] | None
    _source: TableArrays[P, T] | None
    _derived: Derived
    digest: int

    @property
    def vertices(self) -> immutables.Map[int, P]:
        """id -> point."""
        table = self._vertices
        return self._built()[0] if table is None else table

    def _built(self) -> T:
        """The tables built from the source (once, then kept)."""
        source = self._source
        assert source is not None, "a snapshot without tables has a source"
        return self._derived.get("tables", source.tables)

    @property
    def vertex_count(self) -> int:
        """Number of vertices (ids are 0..vertex_count-1)."""
        if self._vertices is None and self._source is not None:
            return len(self._source.points)
        return len(self.vertices)

    @property
    def digest_text(self) -> str:
        """The digest as 32 hexadecimal digits."""
        return _digest.digest_text(self.digest)

    def point(self, vertex: int) -> P:
        """The exact point of ``vertex`` (``KeyError`` if there is none)."""
        return self.vertices[vertex]

    def point_list(self) -> list[P]:
        """The points of vertices 0..n-1, in id order (from the source's arrays while the
        tables are not built; ``KeyError`` when a table has a gap)."""
        if self._vertices is None and self._source is not None:
            return list(self._source.points)
        vertices = self.vertices
        return [vertices[index] for index in range(len(vertices))]
