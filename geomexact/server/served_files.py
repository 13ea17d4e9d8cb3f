"""The files a read of a served file opens, each confined to the served directory.

A reader opens more than the file it is named: a Triangle ``x.ele`` reads ``x.node``,
``x.neigh`` and ``x.poly`` beside it, a ``x.poly`` whose vertex count is 0 reads
``x.node``.  Before a served file is read, it and every such companion that exists is
resolved (symlinks followed) and refused when it lies outside the served directory
(:func:`confined_files`); the reader then runs in a sandbox folder holding links to the
checked files only (:func:`sandbox`), so it finds nothing else beside them."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from http import HTTPStatus
from pathlib import Path, PurePosixPath

import attrs

from geomexact.server.bounded import JobFailed

TRIANGLE_MESH_SUFFIXES = (".ele", ".node", ".neigh", ".poly")
"""The files of one Triangle mesh, by stem (what ``io.triangle.read_triangle`` opens)."""

TETGEN_MESH_SUFFIXES = (".ele", ".node", ".face")
"""The files of one TetGen mesh, by stem (what ``io.tetgen.read_tetgen`` opens)."""

MAX_FOLDER_DEPTH = 2
"""How deep under the served directory files are listed and served (folders)."""

NAME_MAX_BYTES = 255
"""The longest file or folder name (UTF-8 bytes) of common file systems."""

SHOWN_NAME_CHARS = 120
"""A requested name longer than this is shortened in messages."""

UNSERVED_SUFFIXES = (".xdmf", ".xmf")
"""Formats whose files name their data files by any path (XDMF's HDF5 and binary data
items): the server reads none of them, served or uploaded."""


@attrs.frozen
class ServedFile:
    """A file a read opens: its name under the served directory (``relative``, POSIX) and
    where it really is (``target``, resolved, inside the served directory)."""

    relative: PurePosixPath
    target: Path


def _stem_of(name: str, suffix: str) -> str:
    return name[: -len(suffix)] if name.lower().endswith(suffix) else name


def companion_names(name: str) -> tuple[str, ...]:
    """The other file names a read of the file ``name`` may open, by its extension:
    ``x.ele`` → ``x.ele``'s stem with ``.ele``, ``.node``, ``.neigh``, ``.poly`` and
    ``.face`` (Triangle's and TetGen's; those differing from ``name``), ``x.poly`` →
    ``x.node``, none for other formats."""
    lowered = name.lower()
    if lowered.endswith(".ele"):
        stem = _stem_of(name, ".ele")
        suffixes = dict.fromkeys(TRIANGLE_MESH_SUFFIXES + TETGEN_MESH_SUFFIXES)
        return tuple(stem + suffix for suffix in suffixes if stem + suffix != name)
    if lowered.endswith(".poly"):
        return (_stem_of(name, ".poly") + ".node",)
    return ()


def shown_name(text: str) -> str:
    """``text`` quoted for a message, its middle elided past :data:`SHOWN_NAME_CHARS`."""
    if len(text) > SHOWN_NAME_CHARS:
        half = SHOWN_NAME_CHARS // 2
        return f"{text[:half]!r}…{text[-half:]!r} ({len(text):,} characters)"
    return repr(text)


def relative_name(text: str) -> PurePosixPath | None:
    """``text`` as a plain relative name under the served directory, or None when it is
    absolute, climbs (``..``), names a hidden file or folder, lies deeper than
    :data:`MAX_FOLDER_DEPTH` folders or has a part longer than :data:`NAME_MAX_BYTES`
    (the index lists none of these)."""
    if not text or "\x00" in text:
        return None
    relative = PurePosixPath(text)
    if relative.is_absolute() or not 0 < len(relative.parts) <= MAX_FOLDER_DEPTH + 1:
        return None
    if any(part == ".." or part.startswith(".")
           or len(part.encode("utf-8", "surrogatepass")) > NAME_MAX_BYTES
           for part in relative.parts):
        return None
    return relative


def is_inside(path: Path, root: Path) -> bool:
    """True when ``path`` resolved (symlinks followed, also a dangling one's target) lies
    inside the resolved ``root``."""
    try:
        return path.resolve().is_relative_to(root)
    except (OSError, RuntimeError):  # a symlink loop
        return False


def confined_files(root: Path, text: str) -> tuple[ServedFile, ...]:
    """The served file ``text`` (relative to the resolved ``root``) and its existing
    companions, each resolved inside ``root``.  :class:`JobFailed` 404 when the file is not
    a file inside ``root``, 403 when a companion (even a dangling link) points outside."""
    relative = relative_name(text)
    missing = JobFailed(HTTPStatus.NOT_FOUND,
                        f"no file {shown_name(text)} in the served directory")
    if relative is None:
        raise missing
    if relative.name.lower().endswith(UNSERVED_SUFFIXES):
        raise JobFailed(HTTPStatus.FORBIDDEN,
                        f"{relative}: XDMF names its data files by path; the server does not "
                        "read it")
    path = root.joinpath(*relative.parts)
    try:
        if not is_inside(path, root) or not path.is_file():
            raise missing
        found = [ServedFile(relative, path.resolve())]
        for name in companion_names(relative.name):
            companion = path.with_name(name)
            if not os.path.lexists(companion):
                continue
            if not is_inside(companion, root):
                raise JobFailed(HTTPStatus.FORBIDDEN,
                                f"{relative}: its companion {name} lies outside the served "
                                "directory; the mesh is not read")
            if companion.is_file():
                found.append(ServedFile(relative.with_name(name), companion.resolve()))
    except OSError:  # a path the system refuses (too long for it, say): no such file here
        raise missing from None
    return tuple(found)


def is_servable(root: Path, path: Path) -> bool:
    """True when :func:`confined_files` accepts ``path`` (a path under the resolved
    ``root``): what the index may list."""
    try:
        confined_files(root, path.relative_to(root).as_posix())
    except (JobFailed, ValueError):
        return False
    return True


@contextmanager
def sandbox(files: tuple[ServedFile, ...]) -> Iterator[Path]:
    """A temporary folder holding, under each file's relative name, a link to its checked
    target; yields the folder (removed afterwards)."""
    with tempfile.TemporaryDirectory(prefix="geomexact-view-") as folder:
        base = Path(folder)
        for file in files:
            link = base.joinpath(*file.relative.parts)
            link.parent.mkdir(parents=True, exist_ok=True)
            link.symlink_to(file.target)
        yield base
