"""The HTTP server: :class:`MeshServer` and its request handler (routes, checks of the
``Host`` and ``Origin`` headers and of the upload's size), :func:`make_server` and
:func:`serve`."""

from __future__ import annotations

import email.parser
import email.policy
import ipaddress
import socket
import sys
import threading
import urllib.parse
from collections.abc import Callable
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

from geomexact.server.bounded import JobFailed, run_bounded
from geomexact.server.jobs import upload_job, view_job
from geomexact.server.options import ServeOptions
from geomexact.server.pages import error_page, index_page

LOOPBACK_NAMES = {"localhost", "127.0.0.1", "::1"}


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

