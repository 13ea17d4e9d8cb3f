"""Replaying a trace: :func:`replay`, :func:`replay_iter` and :func:`first_divergence`, for
any mesh type whose snapshot opens a transient that applies steps
(:mod:`geomexact.trace.protocols`).  Every step's digest is checked on the way."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TypeVar

from geomexact.errors import TraceError
from geomexact.kernel.collector import collector_paused
from geomexact.trace.protocols import Snapshot, Transient
from geomexact.trace.record import Trace

S = TypeVar("S", bound=Snapshot)


def replay_iter(start: S, trace: Trace, until: int | None = None) -> Iterator[S]:
    """Yield the mesh after each of the first ``until`` steps (all when None), checking
    every digest.  Raises :class:`TraceError` when ``start`` is not the trace's input or a
    step's result differs from the recorded digest."""
    check_start(start, trace)
    count = _count(trace, until)
    mesh = start
    for index in range(count):
        transient = mesh.transient()
        apply_checked(transient, trace, index)
        mesh = transient.seal()  # type: ignore[assignment]
        yield mesh


BATCH_STEPS = 256
"""From this many steps on, a replay edits plain tables (``transient(batch=True)``): the
O(n) copy in and out is then cheaper than the steps' persistent writes."""


def replay(start: S, trace: Trace, until: int | None = None) -> S:
    """The mesh after the first ``until`` steps of ``trace`` (all when None), replayed on
    ``start`` in one batch and checked step by step against the recorded digests (with
    the cyclic collector paused, as the engines that record traces run).  A long replay
    goes to the mesh type's engine when it has one (:class:`~geomexact.trace.protocols.
    EngineReplay`: the same checks, compiled); where that engine cannot go on, the
    reference ops replay the whole trace and name the step that fails."""
    check_start(start, trace)
    count = _count(trace, until)
    with collector_paused():
        engine = getattr(start, "replayed_by_engine", None)
        if engine is not None and count >= BATCH_STEPS:
            fast = engine(trace.steps[:count], trace.digests[:count])
            if fast is not None:
                return fast  # type: ignore[no-any-return]
        transient = start.transient(batch=count >= BATCH_STEPS)
        for index in range(count):
            apply_checked(transient, trace, index)
        return transient.seal()  # type: ignore[return-value]


def check_start(start: Snapshot, trace: Trace) -> None:
    """Raise :class:`TraceError` unless ``start`` is the mesh ``trace`` was recorded on."""
    if start.digest != trace.input_digest:
        raise TraceError(
            f"this trace was recorded on a mesh with digest {trace.input_digest:032x}, "
            f"but the given mesh has digest {start.digest:032x}: it is not the trace's input"
        )


def _count(trace: Trace, until: int | None) -> int:
    if until is None:
        return len(trace.steps)
    if not 0 <= until <= len(trace.steps):
        raise TraceError(f"--until {until} is outside 0..{len(trace.steps)}")
    return until


def apply_checked(transient: Transient, trace: Trace, index: int) -> None:
    """Apply step ``index`` (0-based) of ``trace`` to ``transient`` and check the digest
    after it; :class:`TraceError` names the step when it cannot be applied or diverges."""
    step = trace.steps[index]
    try:
        transient.apply(step)
    except ValueError as error:
        raise TraceError(
            f"step {index + 1} ({step}) cannot be applied: {error}", index + 1
        ) from error
    if transient.digest != trace.digests[index]:
        raise TraceError(
            f"step {index + 1} ({step}) gave digest {transient.digest:032x}, "
            f"the trace recorded {trace.digests[index]:032x}",
            index + 1, expected=trace.digests[index], found=transient.digest,
        )


def first_divergence(a: Trace, b: Trace) -> int | None:
    """Index (0-based) of the first step at which the two traces differ in step or digest;
    0 when their inputs differ; the shorter length when one is a prefix of the other; None
    when they are identical."""
    if a.input_digest != b.input_digest:
        return 0
    for index, (step_a, step_b, digest_a, digest_b) in enumerate(
        zip(a.steps, b.steps, a.digests, b.digests, strict=False)
    ):
        if step_a != step_b or digest_a != digest_b:
            return index
    if len(a) != len(b):
        return min(len(a), len(b))
    return None
