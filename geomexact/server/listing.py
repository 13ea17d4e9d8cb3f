"""Listing the served directory: the mesh, PSLG and trace files that the index page shows
and among which a trace's start is looked for."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

from geomexact.server.served_files import MAX_FOLDER_DEPTH, is_servable

MAX_LISTED_FILES = 2000
TRACE_SUFFIXES = (".trace.jsonl", ".trace")


def is_trace(name: str) -> bool:
    """True for a trace file's name (:data:`TRACE_SUFFIXES`)."""
    return name.endswith(TRACE_SUFFIXES)


def listed_files(directory: Path) -> list[Path]:
    """The mesh, PSLG and trace files of ``directory`` and its subdirectories
    (:data:`~geomexact.server.served_files.MAX_FOLDER_DEPTH` levels, hidden names skipped,
    at most :data:`MAX_LISTED_FILES`), sorted.  A Triangle
    ``.node`` or ``.poly`` beside an ``.ele`` of the same stem is part of that mesh and not
    listed on its own.  Only what the server would read is listed: a file (or symlink)
    resolving outside ``directory``, or whose companions do
    (:func:`~geomexact.server.served_files.is_servable`), is not, nor is XDMF."""
    from geomexact import io
    from geomexact.errors import FormatError

    root = directory.resolve()
    found: list[Path] = []

    def walk(folder: Path, depth: int) -> Iterator[Path]:
        try:
            entries = sorted(os.scandir(folder), key=lambda entry: entry.name)
        except OSError:
            return
        for entry in entries:
            if entry.name.startswith("."):
                continue
            path = Path(entry.path)
            if entry.is_dir(follow_symlinks=False):
                if depth < MAX_FOLDER_DEPTH:
                    yield from walk(path, depth + 1)
            elif entry.is_file():
                yield path

    for path in walk(root, 0):
        if len(found) >= MAX_LISTED_FILES:
            break
        if not is_servable(root, path):
            continue
        if is_trace(path.name):
            found.append(path)
            continue
        try:
            io.detect_format(path)
        except FormatError:
            continue
        suffix = path.suffix.lower()
        if suffix in (".node", ".poly") and path.with_suffix(".ele").exists():
            continue
        found.append(path)
    return found
