"""Errors raised by geomexact.  All derive from :class:`GeomexactError`; each also subclasses
the matching builtin so callers may catch ``ValueError`` or ``KeyError`` as usual.

Errors carry structured details as attributes, and their message says what is wrong and
where, in the words of the user's input (file, line, vertex ids, step number).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import attrs


class GeomexactError(Exception):
    """Base class of every error geomexact raises on purpose."""


class RationalParseError(GeomexactError, ValueError):
    """Text (or a value) that is not an exact finite number."""

    def __init__(self, text: str, problem: str) -> None:
        super().__init__(f"cannot read {text!r} as a number: {problem}")
        self.text = text
        self.problem = problem


class FormatError(GeomexactError, ValueError):
    """A file that does not follow its format; names the file, the line and the problem."""

    def __init__(self, path: str, line: int | None, problem: str) -> None:
        where = f"{path}:{line}" if line is not None else path
        super().__init__(f"{where}: {problem}")
        self.path = path
        self.line = line
        self.problem = problem


class UnsupportedValueError(GeomexactError, TypeError):
    """A value of a kind the chosen file format cannot hold (e.g. a PSLG written as OFF)."""


class OverwriteError(GeomexactError, FileExistsError):
    """A writer refused to replace an existing file (pass ``overwrite=True`` / ``--force``)."""

    def __init__(self, path: str) -> None:
        super().__init__(f"{path} exists; refusing to overwrite it (use --force to replace it)")
        self.path = path


class InputOverwriteError(GeomexactError, FileExistsError):
    """An output would replace a file that the same command read (its input or one of the
    input's companions): refused even with ``overwrite=True`` / ``--force``."""

    def __init__(self, path: str, source: str) -> None:
        same = "" if path == source else f" (read as {source})"
        super().__init__(f"{path} is an input of this command{same}; refusing to replace it, "
                         "even with --force: give the output another name")
        self.path = path
        self.source = source


class PreconditionError(GeomexactError, ValueError):
    """An operation's precondition does not hold (e.g. flipping a constrained edge)."""

    def __init__(self, op: str, problem: str, **details: Any) -> None:
        super().__init__(f"{op}: {problem}")
        self.op = op
        self.problem = problem
        self.details = details


@attrs.frozen(slots=True)
class Violation:
    """One broken invariant of a mesh (2D or 3D): ``kind`` (a stable identifier), a
    readable ``message`` and the ids of the elements involved."""

    kind: str
    message: str
    elements: tuple[int, ...] = ()

    def __str__(self) -> str:
        return f"{self.kind}: {self.message}"


class InvalidMeshError(GeomexactError, ValueError):
    """A mesh violating the snapshot invariants; ``violations`` lists every one found."""

    def __init__(self, violations: Sequence[object]) -> None:
        shown = "; ".join(str(v) for v in list(violations)[:5])
        more = f" (and {len(violations) - 5} more)" if len(violations) > 5 else ""
        super().__init__(f"invalid mesh: {shown}{more}")
        self.violations = tuple(violations)


class DoubleRangeError(GeomexactError, OverflowError):
    """A number whose nearest double would be infinite, where a double is required
    (``value``: the exact number)."""

    def __init__(self, message: str, value: object) -> None:
        super().__init__(message)
        self.value = value


class TraceError(GeomexactError, ValueError):
    """A trace that does not belong to the mesh it is replayed on (``step`` is None), or
    that diverges at step number ``step`` (1-based): ``expected`` is the digest the trace
    recorded after it and ``found`` the one the replay gave (both None when the step could
    not be applied at all)."""

    def __init__(self, message: str, step: int | None = None, *,
                 expected: int | None = None, found: int | None = None) -> None:
        super().__init__(message)
        self.step = step
        self.expected = expected
        self.found = found


class TransientSealedError(GeomexactError, RuntimeError):
    """A write to a transient builder after it was sealed into a snapshot."""


class SegmentError(PreconditionError):
    """Input segments that cross each other or pass through a vertex, when splitting them
    is not allowed.  ``pairs`` lists the offending pairs: ((u, v), (a, b)) for two
    segments that meet, ((u, v), w) for a segment through vertex w."""

    def __init__(self, pairs: list[tuple[tuple[int, int], object]]) -> None:
        shown = "; ".join(
            f"segments {first} and {second} meet" if isinstance(second, tuple)
            else f"segment {first} passes through vertex {second}"
            for first, second in pairs[:20]
        )
        more = f" (and {len(pairs) - 20} more)" if len(pairs) > 20 else ""
        super().__init__(
            "triangulate",
            "segments cross or pass through vertices (pass split_segments=True / "
            f"--split-segments to split them there): {shown or 'segments meet'}{more}",
            pairs=tuple(pairs),
        )
        self.pairs = tuple(pairs)


class PolyllaError(GeomexactError, RuntimeError):
    """An invariant of the Polylla construction failed (e.g. on a triangulation that is
    not a valid mesh): raised instead of returning a wrong polygon mesh."""


class ConvexDecompositionError(GeomexactError, RuntimeError):
    """The decomposition produced a polygon that is not convex (``polygons``: their
    vertex tuples).  Raised instead of returning such a mesh."""

    def __init__(self, polygons: Sequence[tuple[int, ...]]) -> None:
        shown = ", ".join(str(polygon) for polygon in polygons[:3])
        super().__init__(f"{len(polygons)} polygon(s) are not convex after the "
                         f"decomposition: {shown}")
        self.polygons = tuple(polygons)


class GeomexactDeprecationWarning(DeprecationWarning):
    """An old name or argument still accepted, to be removed in a later release: the
    message names what replaces it."""


def warn_deprecated(old: str, new: str, *, stacklevel: int) -> None:
    """Warn (:class:`GeomexactDeprecationWarning`) that ``old`` is deprecated in favour of
    ``new``; ``stacklevel`` as :func:`warnings.warn`'s, counted from the caller."""
    import warnings

    warnings.warn(f"{old} is deprecated and will be removed in a later release: use {new}",
                  GeomexactDeprecationWarning, stacklevel=stacklevel + 1)


class MissingDependencyError(GeomexactError, ImportError):
    """An optional package that a feature needs is not installed; names the package and
    the extra that installs it (``pip install 'geomexact[extra]'``)."""

    def __init__(self, package: str, feature: str, extra: str) -> None:
        super().__init__(
            f"{feature} need(s) the {package} package, which is not installed: "
            f"pip install 'geomexact[{extra}]'"
        )
        self.package = package
        self.extra = extra


_NULL_WITHOUT_EXCEPTION = "returned NULL without setting an exception"


def is_allocation_failure(error: BaseException) -> bool:
    """True for a MemoryError, and for the SystemError a C extension (GMP's allocator in
    gmpy2, for one) raises when an allocation fails under an address-space cap without
    setting MemoryError."""
    return isinstance(error, MemoryError) or (
        isinstance(error, SystemError) and _NULL_WITHOUT_EXCEPTION in str(error))
