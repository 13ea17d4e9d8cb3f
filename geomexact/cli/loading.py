"""Reading a command's input files: the value, the format read and the reader's notes."""

from __future__ import annotations

import sys

import attrs

from geomexact import io
from geomexact.cli.errors import UsageProblem
from geomexact.cli.kinds import Value, kind_name
from geomexact.mesh2d.snapshot import Mesh2


@attrs.frozen
class Loaded:
    """A file read by :func:`io.read_with_notes`, with the format it was read as."""

    path: str
    format: str
    value: Value
    notes: tuple[str, ...]

    @property
    def kind(self) -> str:
        return kind_name(type(self.value))


def load(path: str, format: str | None, verbose: bool) -> Loaded:
    """Read ``path`` (``format`` or by its extension); with ``verbose`` print the reader's
    notes on stderr."""
    value, notes = io.read_with_notes(path, format=format)
    if verbose:
        for note in notes:
            print(f"geomexact: {path}: {note}", file=sys.stderr)
    return Loaded(path, format or io.detect_format(path), value, tuple(notes))


def load_mesh(path: str, format: str | None, verbose: bool, command: str) -> Mesh2:
    """:func:`load` a triangle mesh; any other kind is a :class:`UsageProblem` of
    ``command``."""
    loaded = load(path, format, verbose)
    if not isinstance(loaded.value, Mesh2):
        raise UsageProblem(
            f"{path}: is a {loaded.kind.replace('_', ' ')}, but {command} needs a triangle "
            "mesh (a Triangle .ele, OFF or PSLG text file of triangles, …)"
        )
    return loaded.value
