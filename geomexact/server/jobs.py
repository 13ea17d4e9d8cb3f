"""The server's jobs, run in a bounded child process (:mod:`~geomexact.server.bounded`):
:func:`upload_job` runs an action on uploaded files, :func:`view_job` shows a served file
or trace.  Each returns a viewer page or raises
:class:`~geomexact.server.bounded.JobFailed`."""

from __future__ import annotations

import os
import re
import tempfile
from http import HTTPStatus
from pathlib import Path
from typing import Any

from geomexact.server.actions import ACTIONS, available_actions
from geomexact.server.bounded import JobFailed
from geomexact.server.listing import listed_files

_SAFE_NAME = re.compile(r"[^A-Za-z0-9._-]+")
_MAIN_ORDER = (".ele", ".poly", ".off", ".pslg", ".node", ".txt")


def safe_name(name: str) -> str:
    """An uploaded file's name reduced to a plain file name (no directories)."""
    base = name.replace("\\", "/").rsplit("/", 1)[-1]
    cleaned = _SAFE_NAME.sub("_", base).lstrip(".")
    return cleaned or "upload"


def _main_file(names: list[str]) -> str:
    """The file that names the mesh among uploaded files (an .ele before its .node, …)."""
    for suffix in _MAIN_ORDER:
        for name in names:
            if name.lower().endswith(suffix):
                return name
    return names[0]


def _read(path: Path, root: Path) -> tuple[Any, list[str]]:
    """Read a file; problems name it relative to ``root`` (the served directory, or the
    upload's temporary folder, which the user never saw)."""
    from geomexact import io
    from geomexact.errors import GeomexactError

    prefix = f"{root}{os.sep}"
    try:
        value, notes = io.read_with_notes(path)
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, str(error).replace(prefix, "")) from None
    except (OSError, TypeError, ValueError) as error:
        shown = path.relative_to(root) if path.is_relative_to(root) else path.name
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"{shown}: {error}") from None
    return value, [note.replace(prefix, "") for note in notes]


def _exact_pslg_text(mesh: Any, name: str) -> str:
    from geomexact import io

    with tempfile.TemporaryDirectory() as folder:
        target = Path(folder) / name
        io.write(target, mesh, format="pslg", exact=True)
        return target.read_text(encoding="utf-8")


def upload_job(files: list[tuple[str, bytes]], form: dict[str, str]) -> str:
    """Read the uploaded files, run the chosen action, and return the viewer page of the
    result with its trace."""
    from geomexact.errors import GeomexactError
    from geomexact.viz.viewer import Download, viewer_html

    if not files:
        raise JobFailed(HTTPStatus.BAD_REQUEST, "choose a mesh file to upload")
    action_name = form.get("action") or available_actions()[0]
    action = ACTIONS.get(action_name)
    if action is None or not action.available():
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"unknown action {action_name!r}")
    with tempfile.TemporaryDirectory(prefix="geomexact-upload-") as folder:
        names = []
        for name, data in files:
            clean = safe_name(name)
            (Path(folder) / clean).write_bytes(data)
            names.append(clean)
        main = _main_file(names)
        value, notes = _read(Path(folder) / main, Path(folder))
    try:
        outcome = action.run(value, form)
        stem = main.rsplit(".", 1)[0]
        download = Download(f"{stem}.{action_name}.pslg",
                            _exact_pslg_text(outcome.result, f"{stem}.pslg"))
        return viewer_html(
            outcome.start,
            trace=outcome.trace,
            title=f"{main}: {action_name}",
            source=main,
            notes=[*outcome.report, *notes],
            links=(("← files", "/"), ("upload another", "/#upload")),
            download=download,
        )
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"{main}: {error}") from None


def _inside(directory: Path, relative: str) -> Path:
    root = directory.resolve()
    target = (root / relative).resolve()
    if not target.is_relative_to(root) or not target.is_file():
        raise JobFailed(HTTPStatus.NOT_FOUND, f"no file {relative!r} in the served directory")
    return target


def _trace_start_candidates(directory: Path, trace_path: Path) -> list[Path]:
    """Mesh and PSLG files beside the trace, those sharing the longest name prefix first."""
    name = trace_path.name
    files = [path for path in listed_files(directory) if path.parent == trace_path.parent]

    def shared(path: Path) -> int:
        count = 0
        for a, b in zip(path.name, name, strict=False):
            if a != b:
                break
            count += 1
        return count

    return sorted(files, key=lambda path: (-shared(path), path.name))


def view_job(directory: Path, file: str | None, trace: str | None) -> str:
    """The viewer page of a served file, or of a trace (its start found beside it by
    digest when ``file`` is None)."""
    from geomexact.errors import GeomexactError
    from geomexact.io.trace_file import read_trace
    from geomexact.viz.scene import trace_start
    from geomexact.viz.viewer import viewer_html

    links = (("← files", "/"),)
    if trace is None:
        if file is None:
            raise JobFailed(HTTPStatus.BAD_REQUEST, "name a file to view")
        path = _inside(directory, file)
        value, notes = _read(path, directory)
        return viewer_html(value, title=file, source=file, notes=notes, links=links)
    trace_path = _inside(directory, trace)
    try:
        run = read_trace(trace_path)
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, str(error)) from None
    candidates = ([_inside(directory, file)] if file is not None
                  else _trace_start_candidates(directory, trace_path))
    for candidate in candidates:
        try:
            value, notes = _read(candidate, directory.resolve())
            start = trace_start(value)
        except (JobFailed, TypeError):
            continue
        if start.digest == run.input_digest:
            shown = candidate.relative_to(directory.resolve()).as_posix()
            try:
                return viewer_html(value, trace=run, title=f"{shown} + {trace}", source=shown,
                                   trace_source=trace, notes=notes, links=links)
            except GeomexactError as error:
                raise JobFailed(HTTPStatus.BAD_REQUEST, f"{trace}: {error}") from None
    raise JobFailed(
        HTTPStatus.NOT_FOUND,
        f"{trace}: no mesh or PSLG in its directory is the input this trace was recorded on "
        f"(input digest {run.input_digest:032x})",
    )
