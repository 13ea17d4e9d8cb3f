"""The :class:`Trace` value: the record of a run (its steps and the digest after each), and
:func:`trace_of`, which takes it from a transient.  Files: :mod:`geomexact.io.trace_file`;
replay: :mod:`geomexact.trace.playback`.  Specification: ``specs/trace.md``."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import attrs

from geomexact._version import __version__
from geomexact.trace.deferred import DeferredSequence
from geomexact.trace.protocols import Snapshot, Transient
from geomexact.trace.step import Step


def _steps(values: Iterable[Step]) -> Sequence[Step]:
    # a kernel's deferred steps stay deferred: made only when read
    return values if isinstance(values, DeferredSequence) else tuple(values)


def _digests(values: Iterable[int]) -> Sequence[int]:
    return values if isinstance(values, DeferredSequence) else tuple(values)


def _freeze(
    parameters: Mapping[str, Any] | Iterable[tuple[str, Any]] | None,
) -> tuple[tuple[str, Any], ...]:
    """Parameters as sorted (name, value) pairs, from a mapping or from such pairs (so
    that ``attrs.evolve`` and ``Trace(..., parameters=trace.parameters)`` work)."""
    pairs = parameters.items() if isinstance(parameters, Mapping) else parameters or ()
    return tuple(sorted(pairs))


@attrs.frozen(slots=True)
class Trace:
    """A run: the digest of the mesh it started from, its parameters (JSON values), its
    steps and the mesh digest after each step (``len(digests) == len(steps)``), the
    version that recorded it and the name of the input file it was recorded on (``""``:
    not known, e.g. a run on a value made in memory)."""

    input_digest: int
    steps: Sequence[Step] = attrs.field(converter=_steps)
    """A tuple, or a kernel's :class:`~geomexact.trace.deferred.DeferredSequence` (made
    on first read, equal to the tuple)."""
    digests: Sequence[int] = attrs.field(converter=_digests)
    parameters: tuple[tuple[str, Any], ...] = attrs.field(default=(), converter=_freeze)
    version: str = ""
    input_name: str = ""

    def __attrs_post_init__(self) -> None:
        if len(self.steps) != len(self.digests):
            raise ValueError(
                f"a trace needs one digest per step ({len(self.steps)} steps, "
                f"{len(self.digests)} digests)"
            )

    def __len__(self) -> int:
        return len(self.steps)

    @property
    def final_digest(self) -> int:
        """Digest of the mesh after the last step (the input digest for an empty trace)."""
        return self.digests[-1] if self.digests else self.input_digest

    def parameter(self, name: str, default: Any = None) -> Any:
        """The value of one run parameter."""
        return dict(self.parameters).get(name, default)


def trace_of(
    start: Snapshot, transient: Transient, parameters: Mapping[str, Any] | None = None
) -> Trace:
    """The trace recorded by ``transient`` since it was opened on ``start``."""
    return Trace(start.digest, transient.steps, transient.step_digests, parameters, __version__)
