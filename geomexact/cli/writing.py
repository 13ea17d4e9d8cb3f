"""Writing a command's output files: refusing what cannot be written before anything is,
and saying what a format rounded or dropped."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from geomexact import io
from geomexact.cli.errors import UsageProblem
from geomexact.cli.kinds import Writable, held_kinds, kind_name
from geomexact.cli.summaries import summary_of
from geomexact.errors import FormatError, OverwriteError
from geomexact.io.files import refuse_inputs, staged_path
from geomexact.io.registry import NumberStyle, WriteReport
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.conversion import from_tetrahedral
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

# the exact properties a command reports that rounding can break
_RECHECKED = ("vertices", "triangles", "is_delaunay", "polygons", "nonconvex", "cells")


def warn(message: str) -> None:
    """Print ``geomexact: warning: message`` on stderr."""
    print(f"geomexact: warning: {message}", file=sys.stderr)


_INPUT_ONLY_SUFFIXES = (".poly", ".node", ".pslg")
"""Inputs whose result is a mesh of another format: the suggestion names an ``.ele``."""


def numbered_output(input_path: str) -> str:
    """Triangle's name for the result of ``input_path``: ``x.off`` -> ``x.1.off``,
    ``x.1.ele`` -> ``x.2.ele``, ``x.poly`` -> ``x.1.ele``."""
    path = Path(input_path)
    suffix = path.suffix
    stem = path.name[:len(path.name) - len(suffix)] if suffix else path.name
    base, _, number = stem.rpartition(".")
    stem = f"{base}.{int(number) + 1}" if base and number.isdigit() else f"{stem}.1"
    return stem + (".ele" if suffix.lower() in _INPUT_ONLY_SUFFIXES or not suffix else suffix)


def note_unwritten(input_path: str, what: str) -> None:
    """Say on stderr that a command given no ``-o`` wrote no ``what`` (geomexact never
    writes a file it was not asked for, where Triangle writes ``x.1.*`` beside its input),
    and the ``-o`` that would have."""
    print(f"geomexact: note: no -o given: the {what} was not written (to write it: "
          f"-o {numbered_output(input_path)})", file=sys.stderr)


def write_output(args: argparse.Namespace, path: str | None, value: Writable,
                 what: str) -> list[Path]:
    """Write ``value`` to the command's ``-o`` ``path`` (with its ``--to``, ``--force`` and
    ``--numbers``), or say that no ``-o`` was given (:func:`note_unwritten`): the paths
    written."""
    if path:
        return write(path, value, args.to, overwrite=args.force, numbers=args.numbers)
    note_unwritten(args.input, what)
    return []


def write(
    path: str | Path,
    value: Writable,
    format: str | None,
    *,
    overwrite: bool,
    numbers: NumberStyle = "decimal",
) -> list[Path]:
    """:func:`io.write` (``value`` any kind a format holds, a :class:`MixedMesh3` or a
    :class:`MixedMeshData` too), refusing first (exit 2) a format that cannot hold it; then
    a warning on stderr for what the format dropped, for every rounded number, and for
    each reported property that no longer holds on the file as written."""
    name = format or io.detect_format(path)
    kinds = io.FORMATS[name].kinds
    if not isinstance(value, kinds):
        kind = kind_name(type(value)).replace("_", " ")
        raise UsageProblem(f"{path}: the {name} format holds a {held_kinds(kinds)}, not a "
                           f"{kind}")
    report = io.write_with_report(path, value, format=name, overwrite=overwrite,
                                  numbers=numbers)
    if report.dropped:
        if name == "meshio":
            warn(f"{path}: {Path(path).suffix or 'these'} files cannot hold "
                 f"{_listed(report.dropped)}; they were not written (.vtu, .vtk and .msh "
                 "keep them)")
        else:
            warn(f"{path}: the {name} format cannot hold {_listed(report.dropped)}; "
                 "they were not written")
    if name == "off" and numbers == "exact" and _has_fractions(report.paths):
        warn(f"{path}: holds exact fractions (p/q), which geomexact reads back but other "
             "programs' OFF readers (meshio, MeshLab, Geomview) refuse; for exact output "
             "write .pslg or .ele, for other programs drop --exact (decimals, rounded only "
             "where a number has none)")
    if report.rounded:
        rounding = _rounding(report, name, numbers)
        problems = recheck(value, report, name)
        broken = [problem for problem in problems if problem.startswith(_BROKEN)]
        if broken and numbers != "float":  # the output set is discarded: nothing written
            raise UsageProblem(
                f"{path}: {rounding}, and the rounded mesh is not the mesh: {broken[0]}; "
                "nothing was written (write .pslg, .ele or .off with --exact to keep the "
                "exact values, or give --float to write the rounded mesh all the same)")
        warn(f"{path}: {rounding}")
        for problem in problems:
            warn(f"{path}: {problem}")
    return list(report.paths)


def _has_fractions(paths: Sequence[Path]) -> bool:
    """True when a written file holds a ``/`` (a number written as p/q), read in chunks."""
    for path in paths:
        with open(staged_path(path), "rb") as stream:
            while chunk := stream.read(1 << 20):
                if b"/" in chunk:
                    return True
    return False


_BROKEN = ("the rounded file does not read back", "vertices is", "triangles is",
           "polygons is", "cells is")
"""How :func:`recheck` begins a sentence about a rounding that changed the mesh itself
(vertices merged, cells lost): a refusal, not a warning."""


def _listed(parts: Sequence[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


def _rounding(report: WriteReport, name: str, numbers: NumberStyle) -> str:
    count = f"{report.rounded} number{'s' if report.rounded != 1 else ''}"
    if name == "meshio":
        return f"the format stores doubles: {count} rounded to the nearest double"
    if numbers == "float":
        return f"{count} rounded to the nearest double (--float)"
    return (f"{count} with no finite decimal expansion rounded to the nearest double "
            "(--exact writes them exactly as p/q)")


def recheck(value: Writable, report: WriteReport, name: str) -> list[str]:
    """The reported properties of ``value`` that the file as written (rounded) no longer
    has, one sentence each; the file is read back to find out."""
    try:  # inside the command's output set: the staged file, not yet in place
        written = io.read(staged_path(report.paths[0]), format=name)
    except FormatError as error:
        where = f" (line {error.line})" if error.line is not None else ""
        return [f"the rounded file does not read back{where}: {error.problem}"]
    mixed = value.mesh if isinstance(value, MixedMeshData) else value
    if isinstance(mixed, MixedMesh3) and isinstance(written, Mesh3):
        written = from_tetrahedral(written)  # a file of tetrahedra reads as a Mesh3
    before, after = summary_of(value), summary_of(written)
    return [
        f"{key} is {_shown(before[key])} in the mesh but {_shown(after.get(key))} in the "
        "rounded file"
        for key in _RECHECKED
        if key in before and before[key] != after.get(key)
    ]


def _shown(value: object) -> str:
    return "true" if value is True else "false" if value is False else str(value)


def distinct_outputs(outputs: Sequence[tuple[str, str | None, str | None]]) -> None:
    """Refuse (exit 2, before anything is written) an output that is a file the command
    read, and two outputs that would be the same file: ``outputs`` are (option, path or
    None, format) triples, the format a mesh format name, None (by the extension) or
    ``"file"`` (one plain file: a trace, a picture); a multi-file format's companions
    count (``x.ele`` also writes ``x.node``)."""
    claimed: dict[Path, str] = {}
    for option, path, format in outputs:
        if not path:
            continue
        files = io.output_paths(path, format) if format != "file" else (Path(path),)
        refuse_inputs(files)  # an input, or a companion of one, even with --force
        for file in files:
            resolved = file.resolve()
            if resolved in claimed and claimed[resolved] != option:
                raise UsageProblem(
                    f"{path}: {claimed[resolved]} and {option} would both write {file}; "
                    "give them different paths"
                )
            claimed.setdefault(resolved, option)


def refuse_existing(outputs: Sequence[tuple[str, str | None, str | None]], *,
                    force: bool) -> None:
    """Without ``force``, refuse (:class:`~geomexact.errors.OverwriteError`) an output
    that exists, companions included, before the input is even read: ``outputs`` are
    (option, path or None, format) triples as for :func:`distinct_outputs`."""
    if force:
        return
    for _, path, format in outputs:
        if not path:
            continue
        files = io.output_paths(path, format) if format != "file" else (Path(path),)
        for file in files:
            if file.exists():
                raise OverwriteError(str(file))


def check_outputs(
    outputs: Sequence[tuple[str, str | None, str | None]], value_type: type, *, force: bool
) -> None:
    """Refuse, before anything is written, outputs that cannot all be written: ``outputs``
    are (option, path or None, format) triples as for :func:`distinct_outputs` (the mesh
    outputs all of one ``value_type``; ``"file"``: a plain file such as a trace).  Each
    mesh format must hold ``value_type`` (:class:`UsageProblem`) and, without ``force``,
    none of the files an output would write may exist
    (:class:`~geomexact.errors.OverwriteError`, companions included)."""
    distinct_outputs(outputs)
    for option, path, format in outputs:
        if not path or format == "file":
            continue
        name = format or io.detect_format(path)
        kinds = io.FORMATS[name].kinds
        if not issubclass(value_type, kinds):
            kind = kind_name(value_type).replace("_", " ")
            raise UsageProblem(f"{path} ({option}): the {name} format holds a "
                               f"{held_kinds(kinds)}, not a {kind}")
    refuse_existing(outputs, force=force)
