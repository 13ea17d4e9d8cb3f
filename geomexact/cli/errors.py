"""The errors a command reports as one line ``geomexact: error: …`` on stderr (exit 2)."""

from __future__ import annotations

import sys


class UsageProblem(Exception):
    """A command given the wrong kind of input (e.g. ``check`` on a PSLG): exit 2."""


def print_error(message: str) -> None:
    """Print ``geomexact: error: message`` on stderr."""
    print(f"geomexact: error: {message}", file=sys.stderr)


def os_error_text(error: OSError) -> str:
    """``error`` as ``file: reason`` when it names a file, else as its own text."""
    if error.filename is not None and error.strerror:
        return f"{error.filename}: {error.strerror}"
    return str(error)
