"""Errors raised by geomexact.  All derive from :class:`GeomexactError`; each also subclasses
the matching builtin so callers may catch ``ValueError`` or ``KeyError`` as usual.

Errors carry structured details as attributes, and their message says what is wrong and
where, in the words of the user's input (file, line, vertex ids, step number).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any


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


class PreconditionError(GeomexactError, ValueError):
    """An operation's precondition does not hold (e.g. flipping a constrained edge)."""

    def __init__(self, op: str, problem: str, **details: Any) -> None:
        super().__init__(f"{op}: {problem}")
        self.op = op
        self.problem = problem
        self.details = details


class InvalidMeshError(GeomexactError, ValueError):
    """A mesh violating the snapshot invariants; ``violations`` lists every one found."""

    def __init__(self, violations: Sequence[object]) -> None:
        shown = "; ".join(str(v) for v in list(violations)[:5])
        more = f" (and {len(violations) - 5} more)" if len(violations) > 5 else ""
        super().__init__(f"invalid mesh: {shown}{more}")
        self.violations = tuple(violations)


class TraceError(GeomexactError, ValueError):
    """A trace that does not belong to the mesh it is replayed on (``step`` is None), or
    that diverges at step number ``step`` (1-based)."""

    def __init__(self, message: str, step: int | None = None) -> None:
        super().__init__(message)
        self.step = step


class TransientSealedError(GeomexactError, RuntimeError):
    """A write to a transient builder after it was sealed into a snapshot."""
