"""Walking a trace back and forth: :class:`Stepper` keeps the mesh at its position and
checkpoints along the way, so ``goto(k)`` replays only from the nearest checkpoint at or
before k; every step's digest is checked as in :func:`~geomexact.trace.playback.replay`.
:func:`first_failing_step` finds, by binary search over positions, the first step after
which a property fails (``geomexact trace bisect``).  Specification: ``specs/trace.md``."""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable
from math import isqrt
from typing import Generic, TypeVar

import attrs

from geomexact.errors import TraceError
from geomexact.trace.playback import BATCH_STEPS, apply_checked, check_start
from geomexact.trace.protocols import CellSnapshot
from geomexact.trace.record import Trace
from geomexact.trace.step import Step

__all__ = ["Change", "FailingStep", "Stepper", "first_failing_step"]

S = TypeVar("S", bound=CellSnapshot)


@attrs.frozen(slots=True)
class Change:
    """What one step did: the cells it ``removed`` and ``added`` (canonical, sorted)."""

    removed: tuple[tuple[int, ...], ...]
    added: tuple[tuple[int, ...], ...]


def cell_change(before: CellSnapshot, after: CellSnapshot) -> Change:
    """The cells of ``before`` not in ``after``, and those of ``after`` not in ``before``."""
    old, new = set(before.cells()), set(after.cells())
    return Change(tuple(sorted(old - new)), tuple(sorted(new - old)))


class Stepper(Generic[S]):
    """The meshes of ``trace`` replayed on ``start``, one position at a time.

    Position k is the mesh after the first k steps (0: ``start``).  A checkpoint (the mesh
    itself: snapshots share structure, so it costs only what changed) is kept every
    ``spacing`` positions (default about the square root of the trace's length), and at
    every position visited by :meth:`goto`, so going back is cheap.  Raises
    :class:`TraceError` when ``start`` is not the trace's input or a step diverges."""

    def __init__(self, start: S, trace: Trace, *, spacing: int | None = None) -> None:
        check_start(start, trace)
        self.trace = trace
        self.spacing = spacing or max(1, isqrt(len(trace)))
        self._checkpoints: dict[int, S] = {0: start}
        self._positions = [0]
        self._position = 0
        self._mesh = start
        self.applied = 0
        """Steps applied so far (replay work, for measuring)."""

    @property
    def position(self) -> int:
        return self._position

    @property
    def mesh(self) -> S:
        """The mesh after the first :attr:`position` steps."""
        return self._mesh

    def __len__(self) -> int:
        return len(self.trace)

    def step_at(self, k: int) -> Step:
        """Step k (1-based: the step that leads from position k - 1 to position k)."""
        if not 1 <= k <= len(self.trace):
            raise TraceError(f"step {k} is outside 1..{len(self.trace)}")
        return self.trace.steps[k - 1]

    def _remember(self, position: int, mesh: S) -> None:
        if position not in self._checkpoints:
            self._checkpoints[position] = mesh
            self._positions.insert(bisect_right(self._positions, position), position)

    def goto(self, k: int) -> S:
        """Move to position k (0 .. len) and return the mesh there."""
        if not 0 <= k <= len(self.trace):
            raise TraceError(f"position {k} is outside 0..{len(self.trace)}")
        if k == self._position:
            return self._mesh
        if k < self._position or k - self._position > self.spacing:
            base = self._positions[bisect_right(self._positions, k) - 1]
            mesh, position = self._checkpoints[base], base
            if base < self._position <= k:  # the current mesh is nearer
                mesh, position = self._mesh, self._position
        else:
            mesh, position = self._mesh, self._position
        transient = mesh.transient(batch=k - position >= BATCH_STEPS)
        while position < k:
            apply_checked(transient, self.trace, position)
            position += 1
            self.applied += 1
            if position % self.spacing == 0 and position < k:
                snapshot: S = transient.seal()  # type: ignore[assignment]
                self._remember(position, snapshot)
                transient = snapshot.transient(batch=k - position >= BATCH_STEPS)
        self._mesh = transient.seal()  # type: ignore[assignment]
        self._position = k
        self._remember(k, self._mesh)
        return self._mesh

    def step(self) -> S:
        """Apply the next step and return the mesh after it."""
        if self._position >= len(self.trace):
            raise TraceError(f"at the end of the trace ({len(self.trace)} steps)")
        return self.goto(self._position + 1)

    def back(self) -> S:
        """Go back one step and return the mesh there."""
        if self._position == 0:
            raise TraceError("at the start of the trace")
        return self.goto(self._position - 1)

    def mesh_at(self, k: int) -> S:
        """The mesh at position k (moves there)."""
        return self.goto(k)

    @property
    def changed(self) -> Change:
        """The cells the last step (the one leading to :attr:`position`) removed and
        added; empty at position 0."""
        if self._position == 0:
            return Change((), ())
        here = self._position
        after = self._mesh
        before = self.goto(here - 1)
        self.goto(here)
        return cell_change(before, after)


@attrs.frozen(slots=True)
class FailingStep:
    """The result of :func:`first_failing_step`: ``step`` (1-based) is the first step after
    which the check fails (None: it never does), ``checks`` how many times the check ran
    (O(log n)), ``failed_at_start`` when the check already fails on the input."""

    step: int | None
    checks: int
    failed_at_start: bool = False


def first_failing_step(stepper: Stepper[S], check: Callable[[S], bool]) -> FailingStep:
    """The first step after which ``check(mesh)`` is False, by binary search over
    positions: O(log n) checks and meshes.  The property is assumed to stay failed once
    it fails (otherwise the step found is *a* step where it turns from passing to
    failing, the first such one when there is only one)."""
    checks = 0

    def passes(position: int) -> bool:
        nonlocal checks
        checks += 1
        return check(stepper.goto(position))

    total = len(stepper)
    if not passes(0):
        return FailingStep(None, checks, failed_at_start=True)
    if passes(total):
        return FailingStep(None, checks)
    low, high = 0, total  # passes at low, fails at high
    while high - low > 1:
        middle = (low + high) // 2
        if passes(middle):
            low = middle
        else:
            high = middle
    return FailingStep(high, checks)
