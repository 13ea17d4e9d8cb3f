"""What the trace layer needs of a mesh type: a snapshot with a content digest that opens a
transient, and a transient that applies a :class:`~geomexact.trace.step.Step`, keeps the
digest current and seals into a snapshot.  ``geomexact.mesh2d`` (``Mesh2``/``Transient2``)
is one such pair; ``geomexact.mesh3d`` will be another.  Nothing here names either."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any, Protocol, TypeAlias, TypeVar

import attrs

from geomexact.errors import PreconditionError
from geomexact.trace.step import Step

T = TypeVar("T", contravariant=True)


class Transient(Protocol):
    """A batch builder: applies steps (recording each with the digest after it)."""

    @property
    def digest(self) -> int: ...

    @property
    def steps(self) -> list[Step]: ...

    @property
    def step_digests(self) -> list[int]: ...

    def apply(self, step: Step, /) -> None:
        """Apply ``step`` (raise ``ValueError`` when it cannot be applied)."""
        ...

    def seal(self) -> Snapshot: ...


class Snapshot(Protocol):
    """An immutable mesh value with a content digest, from which a transient opens."""

    @property
    def digest(self) -> int: ...

    def transient(self, *, batch: bool = False) -> Transient:
        """A transient on this snapshot; ``batch`` for a long run of steps (plain tables:
        :mod:`geomexact.trace.tables`)."""
        ...


class EngineReplay(Protocol):
    """A snapshot whose mesh type has a faster engine that replays steps (the compiled
    kernel of 2D refinement): the mesh after ``steps`` with every digest checked, or None
    when the engine cannot replay them (then the reference ops replay them)."""

    def replayed_by_engine(self, steps: Sequence[Step], digests: Sequence[int],
                           /) -> Snapshot | None: ...


class CellSnapshot(Snapshot, Protocol):
    """A snapshot that lists its cells (triangles, tetrahedra), canonical and sorted."""

    def cells(self) -> Sequence[tuple[int, ...]]: ...


OperationTable: TypeAlias = Mapping[str, Callable[[T, Step], None]]
"""Step name -> how to apply it to a transient of one mesh type (``geomexact.mesh2d.ops.
OPERATIONS``; a kind's whole table is its :class:`MeshKind`'s ``operations``)."""


@attrs.frozen(slots=True)
class MeshKind:
    """What a snapshot type reaches only through the modules built on it: the transient
    that opens on it (``transient(snapshot, batch=...)``), the whole step table, and the
    accelerations beside the reference (a compiled replay of long traces: the mesh after
    the steps with every digest checked, or None; a compiled digest of a mesh given in
    bulk, its vertices by id and its canonical cell rows, or None).  The package of a
    mesh kind binds it (:func:`bind_kind`) at import, from above the snapshot, transient
    and ops modules, so that none of them imports a module built on it."""

    transient: Callable[..., Any]
    operations: OperationTable[Any]
    replay_engine: Callable[[Any, Sequence[Step], Sequence[int]], Any] | None = None
    bulk_digest: Callable[[Sequence[Any], Any], int | None] | None = None


_KINDS: dict[type, MeshKind] = {}


def bind_kind(snapshot_type: type, kind: MeshKind) -> None:
    """Bind ``kind`` to ``snapshot_type`` (its package does, once, at import)."""
    _KINDS[snapshot_type] = kind


def kind_of(snapshot_type: type) -> MeshKind:
    """The :class:`MeshKind` bound to ``snapshot_type``."""
    try:
        return _KINDS[snapshot_type]
    except KeyError:
        raise RuntimeError(f"{snapshot_type.__name__} has no bound mesh kind (its package "
                           "binds one at import)") from None


def apply_from(table: OperationTable[T], transient: T, step: Step) -> None:
    """Apply ``step`` to ``transient`` by its entry in ``table`` (the entry records it);
    :class:`~geomexact.errors.PreconditionError` for a step the table does not know."""
    run = table.get(step.op)
    if run is None:
        raise PreconditionError(step.op, f"unknown step {step.op!r} (known: "
                                f"{', '.join(sorted(table))})")
    run(transient, step)
