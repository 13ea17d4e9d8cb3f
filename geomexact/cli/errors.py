"""The errors a command reports as one line ``geomexact: error: …`` on stderr (exit 2), in
the words of the command line."""

from __future__ import annotations

import errno
import io
import os
import re
import sys


class Terminated(BaseException):
    """The command received SIGTERM: it stops as on Ctrl-C (its outputs are discarded)."""


class StdoutClosed(OSError):
    """The command was started with its standard output closed (``>&-``) and has something
    to print: it fails (exit 141, as for a reader gone away), its outputs discarded."""


class _ClosedStdout(io.TextIOBase):
    """Stands for a standard output closed at start: writing raises :class:`StdoutClosed`."""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        raise StdoutClosed(errno.EBADF, "standard output is closed")


def stand_in_for_closed_streams() -> None:
    """Give the standard streams closed at start (Python then sets ``sys.stdout`` or
    ``sys.stderr`` to None and ``print`` writes nothing) a stand-in: printing on a closed
    stdout raises :class:`StdoutClosed`, and a closed stderr discards what it is given."""
    if sys.stdout is None:
        sys.stdout = _ClosedStdout()
        _hold_descriptor(1)
    if sys.stderr is None:
        sys.stderr = io.StringIO()
        _hold_descriptor(2)


def _hold_descriptor(fd: int) -> None:
    """Open /dev/null on the free descriptor ``fd``."""
    # else a file the command opens would get it, and what a subprocess or a C library
    # writes on its stdout or stderr would land in that file
    try:
        os.fstat(fd)
    except OSError:
        null = os.open(os.devnull, os.O_WRONLY)
        if null != fd:
            os.dup2(null, fd)
            os.close(null)


class UsageProblem(Exception):
    """A command given the wrong kind of input (e.g. ``polylla`` on a polygon mesh): exit 2."""


OPTION_WORDING: tuple[tuple[str, str], ...] = (
    ("pass format=", "use --format F (for an input) or --to F (for an output)"),
    ("pass split_segments=True / --split-segments", "use --split-segments"),
    ("pass merge_duplicates=True", "use --merge-duplicates"),
    ("pass split_segments=True", "use --split-segments"),
    ("pass method='centroid' or method='quasi'", "use --method centroid or --method quasi"),
    ("a step limit max_steps=N", "a step limit --max-steps N"),
    ("pass delaunay=True to allow flips", "drop --no-delaunay to allow flips"),
    ("overwrite=True", "--force"),
)
"""The library's hints that name a Python parameter (``pass format=``), each with the
command-line wording that replaces it in a command's message.  ``tests/cli`` checks that
every such hint in the library has one."""

_ENGINE = re.compile(r"\bengine '(auto|compiled|python|reference)'")


def cli_wording(message: str) -> str:
    """``message`` with each hint naming a Python parameter (:data:`OPTION_WORDING`,
    ``engine 'x'``) replaced by the command-line option that does the same."""
    for library, command in OPTION_WORDING:
        message = message.replace(library, command)
    return _ENGINE.sub(r"--engine \1", message)


def print_error(message: str) -> None:
    """Print ``geomexact: error: message`` on stderr (in the command line's words)."""
    print(f"geomexact: error: {cli_wording(message)}", file=sys.stderr)


def print_warning(message: str) -> None:
    """Print ``geomexact: warning: message`` on stderr."""
    print(f"geomexact: warning: {message}", file=sys.stderr)


def os_error_text(error: OSError) -> str:
    """``error`` as ``file: reason`` when it names a file, else as its own text."""
    if error.filename is not None and error.strerror:
        return f"{error.filename}: {error.strerror}"
    return str(error)
