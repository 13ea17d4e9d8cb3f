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
from geomexact.server.read_failures import failure_message, without_prefixes
from geomexact.server.served_files import UNSERVED_SUFFIXES, confined_files, sandbox

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


def _read(path: Path, name: str, prefixes: tuple[str, ...]) -> tuple[Any, list[str]]:
    """Read the file ``path`` (shown as ``name``); a problem is a :class:`JobFailed` 400
    that names files without ``prefixes`` (folders the user never named) and shows none
    of their text (:func:`~geomexact.server.read_failures.failure_message`)."""
    from geomexact import io

    try:
        value, notes = io.read_with_notes(path)
    except MemoryError:
        raise
    except Exception as error:  # any reader's failure, meshio's included
        raise JobFailed(HTTPStatus.BAD_REQUEST, failure_message(error, name, prefixes)) from None
    return value, [without_prefixes(note, prefixes) for note in notes]


def _read_served(root: Path, relative: str) -> tuple[Any, list[str]]:
    """Read the served file ``relative`` under the resolved ``root``, with every file the
    read opens confined to ``root`` (:mod:`~geomexact.server.served_files`)."""
    files = confined_files(root, relative)
    with sandbox(files) as folder:
        main = files[0].relative
        return _read(folder.joinpath(*main.parts), main.as_posix(),
                     (f"{folder}{os.sep}", f"{root}{os.sep}"))


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
        if main.lower().endswith(UNSERVED_SUFFIXES):
            raise JobFailed(HTTPStatus.BAD_REQUEST,
                            f"{main}: XDMF names its data files by path; the server does not "
                            "read it")
        value, notes = _read(Path(folder) / main, main, (f"{folder}{os.sep}",))
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


def _page_of(value: Any, notes: list[str], name: str, links: tuple[tuple[str, str], ...]
             ) -> str:
    """The viewer page of a read file: the 3D viewer for a tetrahedral mesh, else the 2D
    one."""
    from geomexact.mesh3d.snapshot import Mesh3

    if isinstance(value, Mesh3):
        from geomexact.viz.scene3d import viewer_html_3d

        return viewer_html_3d(value, title=name)
    from geomexact.viz.viewer import viewer_html

    return viewer_html(value, title=name, source=name, notes=notes, links=links)


def _trace_page(value: Any, run: Any, notes: list[str], candidate: str, trace: str,
                links: tuple[tuple[str, str], ...]) -> str | None:
    """The viewer page of ``run`` on the read file ``candidate``, or None when that file is
    not the trace's input."""
    from geomexact.errors import GeomexactError
    from geomexact.mesh3d.snapshot import Mesh3
    from geomexact.viz.scene import trace_start

    try:
        start = value if isinstance(value, Mesh3) else trace_start(value)
    except TypeError:  # a value no trace starts from
        return None
    if start.digest != run.input_digest:
        return None
    title = f"{candidate} + {trace}"
    try:
        if isinstance(value, Mesh3):
            from geomexact.viz.scene3d import viewer_html_3d

            return viewer_html_3d(value, run, title=title)
        from geomexact.viz.viewer import viewer_html

        return viewer_html(value, trace=run, title=title, source=candidate,
                           trace_source=trace, notes=notes, links=links)
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"{trace}: {error}") from None


def view_job(directory: Path, file: str | None, trace: str | None) -> str:
    """The viewer page of a served file (the 3D viewer for a tetrahedral mesh), or of a
    trace (its start found beside it by digest when ``file`` is None)."""
    from geomexact.io.trace_file import read_trace

    root = directory.resolve()
    links = (("← files", "/"),)
    if trace is None:
        if file is None:
            raise JobFailed(HTTPStatus.BAD_REQUEST, "name a file to view")
        value, notes = _read_served(root, file)
        return _page_of(value, notes, file, links)
    trace_file = confined_files(root, trace)[0]
    try:
        run = read_trace(trace_file.target)
    except Exception as error:  # the trace reader's failure
        raise JobFailed(HTTPStatus.BAD_REQUEST,
                        failure_message(error, trace, (f"{root}{os.sep}",))) from None
    candidates = ([file] if file is not None else
                  [path.relative_to(root).as_posix() for path in
                   _trace_start_candidates(root, root.joinpath(*trace_file.relative.parts))])
    for candidate in candidates:
        try:
            value, notes = _read_served(root, candidate)
        except JobFailed:
            if file is not None:
                raise
            continue
        page = _trace_page(value, run, notes, candidate, trace, links)
        if page is not None:
            return page
    raise JobFailed(
        HTTPStatus.NOT_FOUND,
        f"{trace}: no mesh or PSLG in its directory is the input this trace was recorded on "
        f"(input digest {run.input_digest:032x})",
    )
