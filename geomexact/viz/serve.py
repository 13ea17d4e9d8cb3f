"""``geomexact serve``: a small local HTTP server for looking at meshes.

It lists the mesh files of a directory and opens each in the viewer (with a trace, the
step slider), and it refines uploaded meshes: the upload form sends a mesh file, the server
runs the library on it (never a shell) and answers with the viewer of the result and its
trace.  It is meant for one person on their own machine:

- it listens on the loopback interface unless ``host`` names another; on loopback it
  answers only requests whose ``Host`` is a loopback name (no DNS rebinding), and it
  refuses uploads posted from other sites (``Origin``);
- a request body is at most ``max_upload_bytes``; every piece of library work (reading a
  file, triangulating, refining, building a page) runs in a separate process that is
  killed after ``time_limit`` seconds; at most ``jobs`` such processes run at once (more
  requests get "busy");
- a bad file gets a page naming the file, the line and the problem.

Actions offered for uploads are in :data:`ACTIONS`: ``triangulate`` always, ``refine``
when :mod:`geomexact.refine` is installed.  Specification: ``specs/viewer.md``.
"""

from __future__ import annotations

import email.parser
import email.policy
import html
import ipaddress
import multiprocessing
import multiprocessing.connection
import os
import re
import socket
import sys
import tempfile
import threading
import traceback
import urllib.parse
from collections.abc import Callable, Iterator
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import attrs

DEFAULT_PORT = 8765
DEFAULT_MAX_UPLOAD_BYTES = 16 * 1024 * 1024
DEFAULT_TIME_LIMIT = 60.0
DEFAULT_JOBS = 2
MAX_LISTED_FILES = 2000
TRACE_SUFFIXES = (".trace.jsonl", ".trace")
LOOPBACK_NAMES = {"localhost", "127.0.0.1", "::1"}

INDEX_CSP = (
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; form-action 'self'; "
    "base-uri 'none'"
)
"""The policy of the server's own pages (in a meta element; the viewer pages carry theirs).
Every response also has the header ``Content-Security-Policy: frame-ancestors 'none'``
(a directive that only works as a header): no other site can frame these pages."""


@attrs.frozen
class ServeOptions:
    """How the server runs (see the module docstring)."""

    directory: Path
    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    max_upload_bytes: int = DEFAULT_MAX_UPLOAD_BYTES
    time_limit: float = DEFAULT_TIME_LIMIT
    jobs: int = DEFAULT_JOBS


class JobFailed(Exception):
    """A job's answer that is not a page: an HTTP status and a message for the user."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


# ---------------------------------------------------------------------------------------
# actions on uploaded meshes (run in the worker process)
# ---------------------------------------------------------------------------------------
@attrs.frozen
class Outcome:
    """What an action made: the trace's start (a mesh, or a PSLG for a triangulation
    trace), the trace, the final mesh and report lines for the page."""

    start: Any
    trace: Any
    result: Any
    report: tuple[str, ...]


@attrs.frozen
class Action:
    """An upload action: a label for the form, whether it is usable here, and the
    function ``run(value, form) -> Outcome`` (``form``: the form's text fields)."""

    label: str
    available: Callable[[], bool]
    run: Callable[[Any, dict[str, str]], Outcome]


def _triangulate(value: Any, form: dict[str, str]) -> Outcome:
    from geomexact.delaunay import make_delaunay, triangulate
    from geomexact.mesh2d import Mesh2
    from geomexact.pslg import PSLG

    if isinstance(value, Mesh2):
        mesh, trace = make_delaunay(value)
        return Outcome(value, trace, mesh, (f"Lawson flips: {len(trace)} steps",))
    if isinstance(value, PSLG):
        construction = triangulate(
            value,
            keep_convex_hull=form.get("keep_convex_hull") == "on",
            split_segments=form.get("split_segments") == "on",
            merge_duplicates=form.get("merge_duplicates") == "on",
        )
        kind = "constrained Delaunay" if value.segments else "Delaunay"
        return Outcome(value, construction.trace, construction.mesh,
                       (f"{kind} triangulation: {len(construction.trace)} steps",))
    raise JobFailed(HTTPStatus.BAD_REQUEST, "a polygon mesh cannot be triangulated")


CRITERIA = ("max_area", "min_angle", "average_area_factor", "max_edge_length")
MAX_STEPS_LIMIT = 5_000_000


def _refine_available() -> bool:
    import importlib.util

    return importlib.util.find_spec("geomexact.refine") is not None


def _refine(value: Any, form: dict[str, str]) -> Outcome:
    from geomexact import criteria
    from geomexact.delaunay import triangulate
    from geomexact.errors import GeomexactError
    from geomexact.mesh2d import Mesh2
    from geomexact.pslg import PSLG
    from geomexact.refine import refine

    report: list[str] = []
    if isinstance(value, PSLG):
        construction = triangulate(value)
        mesh = construction.mesh
        report.append(f"constrained Delaunay triangulation first: {mesh.triangle_count} "
                      "triangles")
    elif isinstance(value, Mesh2):
        mesh = value
    else:
        raise JobFailed(HTTPStatus.BAD_REQUEST, "a polygon mesh cannot be refined")
    kind = form.get("criterion", "max_area")
    text = form.get("value", "").strip()
    if kind not in CRITERIA:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"unknown criterion {kind!r}")
    if not text:
        raise JobFailed(HTTPStatus.BAD_REQUEST, "give the criterion a value")
    makers = {
        "max_area": criteria.MaxArea,
        "min_angle": criteria.MinAngle,
        "average_area_factor": criteria.AverageAreaFactor,
        "max_edge_length": criteria.MaxEdgeLength,
    }
    try:
        criterion = makers[kind](text)
    except (GeomexactError, ValueError, TypeError) as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"{kind.replace('_', ' ')}: {error}") from None
    steps_text = form.get("max_steps", "").strip()
    max_steps = None
    if steps_text:
        if not steps_text.isdigit() or int(steps_text) > MAX_STEPS_LIMIT:
            raise JobFailed(HTTPStatus.BAD_REQUEST,
                            f"max steps must be an integer from 0 to {MAX_STEPS_LIMIT}")
        max_steps = int(steps_text)
    method = form.get("method", "centroid")
    try:
        result = refine(mesh, criterion, method=method, max_steps=max_steps)  # type: ignore[arg-type]
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, str(error)) from None
    report.append(f"Lepp-{method} refinement ({kind.replace('_', ' ')} {text}): "
                  f"{len(result.trace)} steps, {result.status}")
    return Outcome(mesh, result.trace, result.mesh, tuple(report))


ACTIONS: dict[str, Action] = {
    "refine": Action("refine (Lepp)", _refine_available, _refine),
    "triangulate": Action("triangulate (constrained Delaunay / Lawson flips)",
                          lambda: True, _triangulate),
}
"""Upload actions by name; the first available one is the form's default."""


def available_actions() -> list[str]:
    """Names of the actions usable in this installation."""
    return [name for name, action in ACTIONS.items() if action.available()]


# ---------------------------------------------------------------------------------------
# jobs (functions run in the worker process; they return a page or raise JobFailed)
# ---------------------------------------------------------------------------------------
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


def _is_trace(name: str) -> bool:
    return name.endswith(TRACE_SUFFIXES)


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
    from geomexact.trace import read_trace
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


def _child(connection: multiprocessing.connection.Connection, job: Callable[..., str],
           args: tuple[Any, ...]) -> None:
    try:
        connection.send(("ok", job(*args)))
    except JobFailed as failure:
        connection.send(("failed", failure.status, failure.message))
    except MemoryError:
        connection.send(("failed", HTTPStatus.INSUFFICIENT_STORAGE, "the job ran out of memory"))
    except BaseException as error:  # report, never hang the parent
        detail = "".join(traceback.format_exception_only(type(error), error)).strip()
        connection.send(("failed", HTTPStatus.INTERNAL_SERVER_ERROR, f"internal error: {detail}"))
    finally:
        connection.close()


_CONTEXT_LOCK = threading.Lock()
_CONTEXT: multiprocessing.context.BaseContext | None = None


def _context() -> multiprocessing.context.BaseContext:
    """Worker processes: forked from a fork server that has imported geomexact (fast to
    start, no threads inherited); spawned where there is no fork server."""
    global _CONTEXT
    with _CONTEXT_LOCK:
        if _CONTEXT is None:
            if "forkserver" in multiprocessing.get_all_start_methods():
                context = multiprocessing.get_context("forkserver")
                context.set_forkserver_preload(["geomexact.viz.serve", "geomexact.viz.viewer"])
                _CONTEXT = context
            else:  # pragma: no cover - Windows and macOS default
                _CONTEXT = multiprocessing.get_context("spawn")
        return _CONTEXT


def run_bounded(job: Callable[..., str], args: tuple[Any, ...], time_limit: float) -> str:
    """``job(*args)`` in a separate process, killed after ``time_limit`` seconds
    (:class:`JobFailed` 503 then); a job's :class:`JobFailed` is re-raised here."""
    context: Any = _context()
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(sender, job, args), daemon=True)
    process.start()
    sender.close()
    try:
        if not receiver.poll(time_limit):
            raise JobFailed(
                HTTPStatus.SERVICE_UNAVAILABLE,
                f"the job took longer than the server's time limit of {time_limit:g} s and was "
                "stopped (ask for less work, or start the server with a larger --time-limit)",
            )
        try:
            answer = receiver.recv()
        except EOFError:
            raise JobFailed(HTTPStatus.INTERNAL_SERVER_ERROR,
                            "the job's process ended without an answer") from None
    finally:
        receiver.close()
        if process.is_alive():
            process.kill()
        process.join(5)
    if answer[0] == "ok":
        return str(answer[1])
    raise JobFailed(int(answer[1]), str(answer[2]))


# ---------------------------------------------------------------------------------------
# pages
# ---------------------------------------------------------------------------------------
PAGE_CSS = """
body { font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, Arial, sans-serif;
       color: #14213d; margin: 0 auto; max-width: 60rem; padding: 1rem 1.5rem 3rem; }
h1 { font-size: 1.4rem; } h2 { font-size: 1.1rem; margin-top: 2rem; }
table { border-collapse: collapse; width: 100%; }
th, td { text-align: left; padding: 0.25rem 0.6rem; border-bottom: 1px solid #e3e8ef; }
td.size { text-align: right; font-variant-numeric: tabular-nums; color: #5b6b82; }
code { font-size: 0.9em; } a { color: #1f5fbf; }
form { display: grid; grid-template-columns: max-content 1fr; gap: 0.5rem 1rem;
       align-items: center; background: #f6f8fb; padding: 1rem; border-radius: 6px; }
form .wide { grid-column: 1 / -1; }
.error { background: #fdecea; border: 1px solid #f3b8b3; color: #b3261e; padding: 0.7rem 1rem;
         border-radius: 6px; white-space: pre-wrap; }
.hint { color: #5b6b82; font-size: 0.9em; }
"""


def _page(title: str, body: str) -> str:
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<meta http-equiv=\"Content-Security-Policy\" content=\"{INDEX_CSP}\">\n"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
        f"<title>{html.escape(title)}</title>\n<link rel=\"icon\" href=\"data:,\">\n"
        f"<style>{PAGE_CSS}</style>\n</head>\n<body>\n{body}\n</body>\n</html>\n"
    )


def listed_files(directory: Path) -> list[Path]:
    """The mesh, PSLG and trace files of ``directory`` and its subdirectories (two levels,
    hidden names skipped, at most :data:`MAX_LISTED_FILES`), sorted.  A Triangle
    ``.node`` or ``.poly`` beside an ``.ele`` of the same stem is part of that mesh and not
    listed on its own."""
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
                if depth < 2:
                    yield from walk(path, depth + 1)
            elif entry.is_file():
                yield path

    for path in walk(root, 0):
        if len(found) >= MAX_LISTED_FILES:
            break
        if _is_trace(path.name):
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


def _size(path: Path) -> str:
    try:
        size = float(path.stat().st_size)
    except OSError:
        return "-"
    for unit in ("B", "kB", "MB", "GB"):
        if size < 1024 or unit == "GB":
            return f"{size:.0f} {unit}" if unit == "B" else f"{size:.1f} {unit}"
        size /= 1024
    return "-"  # pragma: no cover


def _upload_form(options: ServeOptions) -> str:
    actions = available_actions()
    choices = "".join(
        f'<option value="{name}">{html.escape(ACTIONS[name].label)}</option>' for name in actions
    )
    criteria = "".join(
        f'<option value="{name}">{name.replace("_", " ")}</option>' for name in CRITERIA
    )
    refine_fields = ""
    if "refine" in actions:
        refine_fields = f"""
<label for="criterion">criterion (refine)</label>
<span><select id="criterion" name="criterion">{criteria}</select>
<input id="value" name="value" value="0.001" size="10" aria-label="criterion value">
<span class="hint">an area, an angle in degrees (&lt; 60), a factor or a length;
exact numbers such as 1/300</span></span>
<label for="method">method (refine)</label>
<select id="method" name="method"><option value="centroid">Lepp-centroid</option>
<option value="bisection">Lepp-bisection</option>
<option value="quasi">Lepp quasi-Delaunay</option></select>
<label for="max_steps">max steps (refine)</label>
<input id="max_steps" name="max_steps" value="200000" size="10" inputmode="numeric">"""
    limit_mb = options.max_upload_bytes / (1024 * 1024)
    return f"""
<h2 id="upload">Upload a mesh</h2>
<form method="post" action="/upload" enctype="multipart/form-data">
<label for="files">file(s)</label>
<span><input id="files" name="files" type="file" multiple required>
<span class="hint">OFF, PSLG text, Triangle .poly / .node, or .ele with its .node (choose
both); at most {limit_mb:g} MB</span></span>
<label for="action">action</label>
<select id="action" name="action">{choices}</select>{refine_fields}
<span class="wide"><button type="submit">Run</button>
<span class="hint">runs in a separate process for at most {options.time_limit:g} s</span></span>
</form>"""


def index_page(options: ServeOptions) -> str:
    """The start page: the files of the directory and the upload form."""
    from geomexact import io

    root = options.directory.resolve()
    rows = []
    traces = []
    for path in listed_files(root):
        relative = path.relative_to(root).as_posix()
        quoted = urllib.parse.quote(relative)
        if _is_trace(path.name):
            traces.append(
                f'<tr><td><a href="/view?trace={quoted}">{html.escape(relative)}</a></td>'
                f'<td>trace: opens with its input, step by step</td>'
                f'<td class="size">{_size(path)}</td></tr>'
            )
            continue
        format_name = io.detect_format(path)
        rows.append(
            f'<tr><td><a href="/view?file={quoted}">{html.escape(relative)}</a></td>'
            f"<td>{html.escape(format_name)}</td><td class=\"size\">{_size(path)}</td></tr>"
        )
    listing = ("<table><thead><tr><th>file</th><th>format</th><th>size</th></tr></thead>"
               f"<tbody>{''.join(rows + traces)}</tbody></table>"
               if rows or traces else
               '<p class="hint">No mesh files here (OFF, Triangle .ele/.node/.poly, '
               "PSLG text, meshio formats, traces).</p>")
    body = f"""<h1>geomexact · {html.escape(str(root))}</h1>
<p class="hint">Click a file to open it in the viewer.  <a href="/viewer">Open the viewer
empty</a> to look at files from this computer without uploading them.</p>
{listing}
{_upload_form(options)}"""
    return _page(f"geomexact · {root.name}", body)


def error_page(status: int, message: str, options: ServeOptions | None) -> str:
    """A page naming the problem, with the upload form again."""
    phrase = HTTPStatus(status).phrase
    form = _upload_form(options) if options is not None else ""
    body = (f"<h1>{status} {html.escape(phrase)}</h1>"
            f'<p class="error" role="alert">{html.escape(message)}</p>'
            f'<p><a href="/">← files</a></p>{form}')
    return _page(f"geomexact · {phrase}", body)


# ---------------------------------------------------------------------------------------
# HTTP
# ---------------------------------------------------------------------------------------
def is_loopback(host: str) -> bool:
    """True for ``localhost`` and loopback addresses (127.0.0.0/8, ::1)."""
    if host in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def parse_multipart(content_type: str, body: bytes) -> tuple[list[tuple[str, bytes]],
                                                             dict[str, str]]:
    """The uploaded files (name, bytes) and text fields of a ``multipart/form-data``
    body."""
    head = f"Content-Type: {content_type}\r\nMIME-Version: 1.0\r\n\r\n".encode("latin-1")
    message = email.parser.BytesParser(policy=email.policy.HTTP).parsebytes(head + body)
    if not message.is_multipart():
        raise JobFailed(HTTPStatus.BAD_REQUEST, "the upload is not multipart/form-data")
    files: list[tuple[str, bytes]] = []
    fields: dict[str, str] = {}
    for part in message.iter_parts():
        name = part.get_param("name", header="content-disposition")
        if not isinstance(name, str):
            continue
        filename = part.get_filename()
        payload = part.get_payload(decode=True)
        data = payload if isinstance(payload, bytes) else b""
        if filename is not None:
            if filename or data:
                files.append((filename or "upload", data))
        else:
            fields[name] = data.decode("utf-8", "replace")
    return files, fields


class MeshServer(ThreadingHTTPServer):
    """The HTTP server: its options, and a limit on concurrent jobs."""

    daemon_threads = True

    def __init__(self, options: ServeOptions) -> None:
        self.options = options
        self.job_slots = threading.BoundedSemaphore(max(1, options.jobs))
        self.loopback = is_loopback(options.host)
        if ":" in options.host:
            self.address_family = socket.AF_INET6
        super().__init__((options.host, options.port), _Handler)

    @property
    def url(self) -> str:
        host, port = self.server_address[:2]
        name = host.decode() if isinstance(host, bytes) else str(host)
        shown = f"[{name}]" if ":" in name else name
        return f"http://{shown}:{port}/"


class _Handler(BaseHTTPRequestHandler):
    server: MeshServer
    server_version = "geomexact"
    timeout = 60  # seconds a client may take to send its request

    def log_message(self, format: str, *args: Any) -> None:
        sys.stderr.write(f"geomexact serve: {self.address_string()} {format % args}\n")

    # -- responses ---------------------------------------------------------------------
    def _send(self, status: int, text: str, content_type: str = "text/html") -> None:
        data = text.encode("utf-8")
        self.send_response(status)
        self.send_header("Content-Type", f"{content_type}; charset=utf-8")
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Referrer-Policy", "no-referrer")
        self.send_header("Content-Security-Policy", "frame-ancestors 'none'")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(data)

    def _fail(self, status: int, message: str) -> None:
        self._send(status, error_page(status, message, self.server.options))

    def _job(self, job: Callable[..., str], args: tuple[Any, ...]) -> None:
        if not self.server.job_slots.acquire(blocking=False):
            self._fail(HTTPStatus.SERVICE_UNAVAILABLE,
                       f"the server is busy with {self.server.options.jobs} job(s); "
                       "try again when one has finished")
            return
        try:
            page = run_bounded(job, args, self.server.options.time_limit)
        except JobFailed as failure:
            self._fail(failure.status, failure.message)
            return
        finally:
            self.server.job_slots.release()
        self._send(HTTPStatus.OK, page)

    # -- checks --------------------------------------------------------------------------
    def _host_allowed(self) -> bool:
        if not self.server.loopback:
            return True
        host = self.headers.get("Host", "")
        if host.startswith("["):  # [IPv6]:port
            name = host[1:host.find("]")] if "]" in host else host
        else:
            name = host.split(":", 1)[0]
        if is_loopback(name.lower()):
            return True
        self._fail(HTTPStatus.FORBIDDEN,
                   f"this server answers only loopback names, not Host {host!r}")
        return False

    # -- routes ------------------------------------------------------------------------
    def do_HEAD(self) -> None:
        self.do_GET()

    def do_GET(self) -> None:
        if not self._host_allowed():
            return
        parsed = urllib.parse.urlsplit(self.path)
        query = urllib.parse.parse_qs(parsed.query)
        options = self.server.options
        if parsed.path in ("/", "/index.html"):
            self._send(HTTPStatus.OK, index_page(options))
        elif parsed.path == "/viewer":
            from geomexact.viz.viewer import empty_viewer_html

            self._send(HTTPStatus.OK, empty_viewer_html(links=(("← files", "/"),)))
        elif parsed.path == "/view":
            file = query.get("file", [None])[0]
            trace = query.get("trace", [None])[0]
            self._job(view_job, (options.directory.resolve(), file, trace))
        else:
            self._fail(HTTPStatus.NOT_FOUND, f"no page {parsed.path!r}")

    def do_POST(self) -> None:
        if not self._host_allowed():
            return
        parsed = urllib.parse.urlsplit(self.path)
        if parsed.path != "/upload":
            self._fail(HTTPStatus.NOT_FOUND, f"no page {parsed.path!r}")
            return
        origin = self.headers.get("Origin")
        if origin and origin != "null":
            origin_host = urllib.parse.urlsplit(origin).netloc
            if origin_host != self.headers.get("Host", ""):
                self._fail(HTTPStatus.FORBIDDEN, f"uploads from {origin} are not accepted")
                return
        length_text = self.headers.get("Content-Length")
        if length_text is None or not length_text.isdigit():
            self._fail(HTTPStatus.LENGTH_REQUIRED, "an upload needs a Content-Length")
            return
        length = int(length_text)
        limit = self.server.options.max_upload_bytes
        if length > limit:
            self.close_connection = True
            self._fail(HTTPStatus.REQUEST_ENTITY_TOO_LARGE,
                       f"the upload has {length:,} bytes; this server takes at most {limit:,} "
                       "(start it with a larger --max-upload-mb)")
            return
        body = self.rfile.read(length)
        if len(body) != length:
            self._fail(HTTPStatus.BAD_REQUEST, "the upload ended early")
            return
        content_type = self.headers.get("Content-Type", "")
        if not content_type.startswith("multipart/form-data"):
            self._fail(HTTPStatus.BAD_REQUEST, "the upload must be multipart/form-data")
            return
        try:
            files, fields = parse_multipart(content_type, body)
        except JobFailed as failure:
            self._fail(failure.status, failure.message)
            return
        self._job(upload_job, (files, fields))


def make_server(options: ServeOptions) -> MeshServer:
    """A bound server (call ``serve_forever()``; ``port=0`` picks a free port)."""
    if not options.directory.is_dir():
        raise NotADirectoryError(f"{options.directory}: not a directory")
    try:
        return MeshServer(options)
    except OSError as error:  # e.g. the port is taken: name the address
        raise OSError(error.errno, error.strerror or str(error),
                      f"{options.host}:{options.port}") from error


def serve(options: ServeOptions, *, announce: Callable[[str], None] | None = None) -> None:
    """Run the server until interrupted (``KeyboardInterrupt`` propagates after the
    server has closed)."""
    server = make_server(options)
    if announce is not None:
        announce(server.url)
    try:
        server.serve_forever(poll_interval=0.25)
    finally:
        server.server_close()

