"""What the transients of every mesh kind share: the vertex table, the digest kept
current, the steps recorded with the digest after each, and no edit once sealed.  A mesh
package's transient subclasses :class:`RecordingTransient`, opens these slots on its
snapshot in its ``__init__`` and names its snapshot type in ``snapshot_type``."""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar, Generic, TypeVar

import immutables

from geomexact.errors import PreconditionError, TransientSealedError
from geomexact.kernel import digest as _digest
from geomexact.kernel.numbers import Rational
from geomexact.trace.protocols import apply_from, kind_of
from geomexact.trace.step import Step
from geomexact.trace.tables import EditableTable, open_table

__all__ = ["MAX_VERTICES", "RecordingTransient"]

P = TypeVar("P")

MAX_VERTICES = 1 << 32
"""Vertex ids stay below this (the compiled kernels pack two ids in 64 bits)."""


class RecordingTransient(Generic[P]):
    """A transient's vertex table (id -> point ``P``), digest and step record; a
    subclass's ``__init__`` opens them on its snapshot."""

    __slots__ = ("_digest", "_sealed", "_vertices", "step_digests", "steps")

    snapshot_type: ClassVar[type]
    """The snapshot type whose bound kind (:func:`~geomexact.trace.protocols.kind_of`)
    holds the step table :meth:`apply` uses."""

    _vertices: EditableTable[int, P]
    _digest: int
    _sealed: bool
    steps: list[Step]
    step_digests: list[int]

    def _open_record(self, vertices: immutables.Map[int, P], digest: int, batch: bool) -> None:
        """Open the vertex table on a snapshot's ``vertices`` (``batch``: a plain dict,
        :func:`~geomexact.trace.tables.open_table`), its ``digest``, and no steps yet
        (each subclass's ``__init__`` starts with this, then opens its own tables)."""
        self._vertices = open_table(vertices, batch)
        self._digest = digest
        self._sealed = False
        self.steps = []
        self.step_digests = []

    @property
    def digest(self) -> int:
        return self._digest

    @property
    def vertex_count(self) -> int:
        return len(self._vertices)

    def point(self, vertex: int) -> P:
        """The point of ``vertex``; :class:`PreconditionError` when there is none (a step
        naming a vertex the mesh does not have)."""
        try:
            return self._vertices[vertex]
        except KeyError:
            raise PreconditionError("vertex", f"vertex {vertex} does not exist") from None

    def _append_vertex(self, point: P, coordinates: Sequence[Rational]) -> int:
        """Append the vertex at ``point`` (in no cell yet), its hash of ``coordinates``
        added to the digest; its id."""
        self._check_open()
        vertex = len(self._vertices)
        if vertex >= MAX_VERTICES:
            raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
        self._vertices[vertex] = point
        self._digest = _digest.combine(self._digest, _digest.vertex_hash(vertex, coordinates))
        return vertex

    def _check_open(self) -> None:
        if self._sealed:
            raise TransientSealedError("this transient was sealed; start a new one")

    def record(self, step: Step) -> None:
        """Append ``step`` (just completed) and the digest after it to the run's record; a
        sealed transient refuses it, also for a step that edited nothing."""
        self._check_open()
        self.steps.append(step)
        self.step_digests.append(self._digest)

    def apply(self, step: Step, /) -> None:
        """Apply ``step`` through the step table of :attr:`snapshot_type`'s kind (the
        entry records it); :class:`PreconditionError` when it cannot."""
        apply_from(kind_of(self.snapshot_type).operations, self, step)
