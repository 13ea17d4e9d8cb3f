"""The HTTP server: :class:`MeshServer` and its request handler (routes, checks of the
``Host``, ``Origin`` and ``Sec-Fetch-Site`` headers and of the upload's size, the two
pools of job slots), :func:`make_server` and :func:`serve`."""

from __future__ import annotations

import ipaddress
import re
import signal
import socket
import sys
import threading
import time
import traceback
import urllib.parse
from collections.abc import Callable
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, TextIO

from geomexact.server.bounded import RETRY_AFTER_SECONDS, ClientGone, JobFailed, run_bounded
from geomexact.server.form_data import parse_multipart
from geomexact.server.jobs import upload_job, view_job
from geomexact.server.options import ServeOptions
from geomexact.server.pages import error_page, index_page

LOOPBACK_NAMES = {"localhost", "127.0.0.1", "::1"}
LISTEN_BACKLOG = 1024  # connections waiting to be accepted (the kernel may cap it lower)
LINGER_SECONDS = 5.0  # how long an unread request body is drained after the answer
RESERVED_DESCRIPTORS = 64  # the process's own files, the log, the listening socket
JOB_DESCRIPTORS = 8  # what one running job holds (pipes to it, its status) at most
ACCEPT_WAIT_SECONDS = 0.25  # how often a full server checks whether it is shutting down
MAX_LOGGED_CHARS = 500
_DIGITS = re.compile(r"[0-9]+", re.ASCII)


def is_loopback(host: str) -> bool:
    """True for ``localhost`` and loopback addresses (127.0.0.0/8, ::1)."""
    if host in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def same_origin(origin: str, host: str) -> bool:
    """True when the ``Origin`` header ``origin`` names the plain-HTTP site the ``Host``
    header ``host`` names (names compared case-insensitively, port 80 when omitted)."""
    try:
        named = urllib.parse.urlsplit(origin.strip())
        served = urllib.parse.urlsplit(f"//{host.strip()}")
        named_port, served_port = named.port or 80, served.port or 80
    except ValueError:  # a port that is not a number
        return False
    return (named.scheme == "http" and named.hostname is not None
            and named.hostname == served.hostname and named_port == served_port
            and not named.path.strip("/") and not named.username)


class JobSlots:
    """At most ``size`` jobs (or connections) of one kind at once: :meth:`try_acquire`
    takes a slot or says there is none free (the request is answered "busy" then, never
    queued)."""

    def __init__(self, size: int) -> None:
        self.size = max(1, size)
        self._used = 0
        self._free = threading.Condition()

    @property
    def in_use(self) -> int:
        """How many slots are taken now."""
        return self._used

    def try_acquire(self, timeout: float = 0.0) -> bool:
        """Take a free slot (True), waiting at most ``timeout`` seconds for one; False
        when all stayed taken."""
        with self._free:
            if not self._free.wait_for(lambda: self._used < self.size, timeout):
                return False
            self._used += 1
            return True

    def release(self) -> None:
        """Give back a slot taken by :meth:`try_acquire`."""
        with self._free:
            if self._used == 0:
                raise ValueError("release() without try_acquire()")
            self._used -= 1
            self._free.notify()


def connection_limit(options: ServeOptions) -> int:
    """How many connections the server answers at once: ``options.max_connections``, fewer
    when the process's limit on open files would not hold them besides the jobs' (each
    connection is a thread and a descriptor; past the limit, starting a job fails)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows: no such limit
        return max(1, options.max_connections)
    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY:
        return max(1, options.max_connections)
    jobs = max(1, options.jobs) + max(1, options.view_jobs)
    room = soft - RESERVED_DESCRIPTORS - JOB_DESCRIPTORS * jobs
    return max(1, min(options.max_connections, room))


class MeshServer(ThreadingHTTPServer):
    """The HTTP server: its options, the slots of upload jobs and of viewing jobs (two
    pools: uploads never make viewing busy), at most :func:`connection_limit` connections
    answered at once (more are left in the listen queue until one ends), and its log
    (``log``, default standard error: one line per request and per client that went
    away)."""

    daemon_threads = True
    request_queue_size = LISTEN_BACKLOG

    def __init__(self, options: ServeOptions, log: TextIO | None = None) -> None:
        self.options = options
        self.upload_slots = JobSlots(options.jobs)
        self.view_slots = JobSlots(options.view_jobs)
        self.connection_slots = JobSlots(connection_limit(options))
        self.loopback = is_loopback(options.host)
        self.log = log
        self._log_lock = threading.Lock()
        if ":" in options.host:
            self.address_family = socket.AF_INET6
        super().__init__((options.host, options.port), _Handler)

    @property
    def url(self) -> str:
        host, port = self.server_address[:2]
        name = host.decode() if isinstance(host, bytes) else str(host)
        shown = f"[{name}]" if ":" in name else name
        return f"http://{shown}:{port}/"

    def get_request(self) -> tuple[socket.socket, Any]:
        """Accept a connection once fewer than the limit are being answered; while the
        server is full, ``OSError`` after :data:`ACCEPT_WAIT_SECONDS` (the serving loop
        then checks for shutdown and comes back)."""
        if not self.connection_slots.try_acquire(ACCEPT_WAIT_SECONDS):
            raise OSError("every connection slot is taken")
        try:
            return self.socket.accept()
        except BaseException:
            self.connection_slots.release()
            raise

    def shutdown_request(self, request: Any) -> None:
        """Close an accepted connection and free its slot (called once for each)."""
        try:
            super().shutdown_request(request)
        finally:
            self.connection_slots.release()

    def write_log(self, text: str) -> None:
        """Write ``text`` and a newline to the log (whole lines: threads share it)."""
        stream = self.log if self.log is not None else sys.stderr
        with self._log_lock:
            stream.write(f"geomexact serve: {text}\n")
            stream.flush()

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A client that went away (reset, broken pipe, timeout) is one log line; anything
        else is a bug, logged with its traceback."""
        error = sys.exc_info()[1]
        who = client_address[0] if isinstance(client_address, tuple) else str(client_address)
        if isinstance(error, ConnectionError | TimeoutError):
            self.write_log(f"{who} went away before its answer was sent "
                           f"({type(error).__name__})")
            return
        self.write_log(f"error while answering {who}:\n{traceback.format_exc().rstrip()}")


class _Handler(BaseHTTPRequestHandler):
    server: MeshServer
    server_version = "geomexact"
    timeout = 60  # seconds a client may take to send its request
    # an unparsable request line is answered with a status line too (the default, HTTP/0.9,
    # answers a bare body)
    default_request_version = "HTTP/1.0"

    def log_message(self, format: str, *args: Any) -> None:
        message = format % args
        if len(message) > MAX_LOGGED_CHARS:  # a 10,000-character path stays one short line
            message = f"{message[:MAX_LOGGED_CHARS]}… ({len(message):,} characters)"
        self.server.write_log(f"{self.address_string()} {message}")

    # -- responses ---------------------------------------------------------------------
    def _send(self, status: int, text: str, content_type: str = "text/html",
              retry_after: int | None = None) -> None:
        data = text.encode("utf-8")
        self.send_response(status)
        if retry_after is not None:
            self.send_header("Retry-After", str(retry_after))
        self.send_header("Content-Type", f"{content_type}; charset=utf-8")
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Referrer-Policy", "same-origin")
        self.send_header("Content-Security-Policy", "frame-ancestors 'none'")
        self.send_header("Connection", "close")  # one request per connection (HTTP/1.0)
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(data)

    def _fail(self, status: int, message: str, retry_after: int | None = None) -> None:
        self._send(status, error_page(status, message, self.server.options),
                   retry_after=retry_after)

    def _busy(self, slots: JobSlots, kind: str) -> None:
        self._fail(HTTPStatus.SERVICE_UNAVAILABLE,
                   f"the server is busy with {slots.size} {kind} job(s); try again in a few "
                   "seconds", retry_after=RETRY_AFTER_SECONDS)

    def _run(self, slots: JobSlots, job: Callable[..., str], args: tuple[Any, ...]) -> None:
        """Run ``job`` in a slot already taken from ``slots``; release it; answer (nothing
        when the client went away: its job was stopped)."""
        options = self.server.options
        try:
            page = run_bounded(job, args, options.time_limit, options.memory_limit_bytes,
                               client=self.connection)
        except ClientGone:
            self.close_connection = True
            self.server.write_log(f"{self.address_string()} went away during its job "
                                  f"({self.command} {self.path[:100]}); the job was stopped")
            return
        except JobFailed as failure:
            self._fail(failure.status, failure.message, failure.retry_after)
            return
        finally:
            slots.release()
        self._send(HTTPStatus.OK, page)

    def _discard_unread_body(self) -> None:
        """After an answer sent without reading the request's body: stop sending, then
        read and drop what the client still sends (at most :data:`LINGER_SECONDS`), so
        that closing does not reset the connection before the client reads the answer."""
        try:
            self.wfile.flush()
            self.connection.shutdown(socket.SHUT_WR)
            deadline = time.monotonic() + LINGER_SECONDS
            while (left := deadline - time.monotonic()) > 0:
                self.connection.settimeout(left)
                if not self.connection.recv(1 << 16):
                    break
        except OSError:
            pass  # the client closed first: nothing more to do

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

    def _cross_site(self) -> str | None:
        """Why this (state-changing) request is refused as coming from another site, or
        None: its ``Origin``, when present, is this server as the browser named it
        (``Host``), and its ``Sec-Fetch-Site``, when present, is ``same-origin`` or
        ``none``.  ``Origin: null`` is accepted only with ``Sec-Fetch-Site: same-origin``
        (a browser's own form under a strict referrer policy; a page cannot set that
        header).  A request with neither header (curl, scripts) is accepted."""
        origin = self.headers.get("Origin")
        site = self.headers.get("Sec-Fetch-Site")
        if origin is not None:
            if origin.strip().lower() == "null":
                if site is not None and site.strip().lower() == "same-origin":
                    return None
                return "a request from an opaque origin (Origin: null) is not accepted"
            if not same_origin(origin, self.headers.get("Host", "")):
                return f"requests from {origin} are not accepted"
        if site is not None and site.strip().lower() not in ("same-origin", "none"):
            return f"a {site} request (Sec-Fetch-Site) is not accepted"
        return None

    def _body_length(self) -> tuple[int, str] | int:
        """The body's declared length, or the (status, message) that refuses it: 411
        without a Content-Length (chunked bodies included), 400 for an invalid one, 413
        above ``max_upload_bytes``."""
        if self.headers.get("Transfer-Encoding") is not None:
            return (HTTPStatus.LENGTH_REQUIRED,
                    "send the upload with a Content-Length (no Transfer-Encoding)")
        values = self.headers.get_all("Content-Length") or []
        if not values:
            return HTTPStatus.LENGTH_REQUIRED, "an upload needs a Content-Length"
        if len(set(values)) != 1 or not _DIGITS.fullmatch(values[0].strip()):
            return HTTPStatus.BAD_REQUEST, "the upload's Content-Length is not a length"
        length = int(values[0].strip())
        limit = self.server.options.max_upload_bytes
        if length > limit:
            return (HTTPStatus.REQUEST_ENTITY_TOO_LARGE,
                    f"the upload has {length:,} bytes; this server takes at most {limit:,} "
                    "(start it with a larger --max-upload-mb)")
        return length

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
            slots = self.server.view_slots
            if not slots.try_acquire():
                self._busy(slots, "viewing")
                return
            self._run(slots, view_job, (options.directory.resolve(), file, trace))
        else:
            self._fail(HTTPStatus.NOT_FOUND, f"no page {parsed.path!r}")

    def do_POST(self) -> None:
        body_read = False
        try:
            body_read = self._post()
        finally:
            if not body_read and (self.headers.get("Content-Length", "0").strip() != "0"
                                  or self.headers.get("Transfer-Encoding") is not None):
                self._discard_unread_body()

    def _post(self) -> bool:
        """Answer a POST; True once its body has been read (else the caller drops it)."""
        if not self._host_allowed():
            return False
        refusal = self._cross_site()
        if refusal is not None:
            self._fail(HTTPStatus.FORBIDDEN, refusal)
            return False
        parsed = urllib.parse.urlsplit(self.path)
        if parsed.path != "/upload":
            self._fail(HTTPStatus.NOT_FOUND, f"no page {parsed.path!r}")
            return False
        length = self._body_length()
        if isinstance(length, tuple):
            self._fail(*length)
            return False
        content_type = self.headers.get("Content-Type", "")
        if not content_type.startswith("multipart/form-data"):
            self._fail(HTTPStatus.BAD_REQUEST, "the upload must be multipart/form-data")
            return False
        slots = self.server.upload_slots
        if not slots.try_acquire():  # before reading: a busy server holds no bodies
            self._busy(slots, "upload")
            return False
        try:
            body = self.rfile.read(length)
            if len(body) != length:
                raise JobFailed(HTTPStatus.BAD_REQUEST, "the upload ended early")
            files, fields = parse_multipart(content_type, body)
        except JobFailed as failure:
            slots.release()
            self._fail(failure.status, failure.message)
            return True
        except BaseException:
            slots.release()
            raise
        del body  # the files are what the job needs; hold one copy only
        self._run(slots, upload_job, (files, fields))
        return True


def make_server(options: ServeOptions, *, log: TextIO | None = None) -> MeshServer:
    """A bound server (call ``serve_forever()``; ``port=0`` picks a free port) logging to
    ``log`` (default: standard error)."""
    if not options.directory.is_dir():
        raise NotADirectoryError(f"{options.directory}: not a directory")
    try:
        return MeshServer(options, log)
    except OSError as error:  # e.g. the port is taken: name the address
        raise OSError(error.errno, error.strerror or str(error),
                      f"{options.host}:{options.port}") from error


def _terminate(signum: int, frame: object) -> None:
    raise KeyboardInterrupt


def serve(options: ServeOptions, *, announce: Callable[[str], None] | None = None) -> None:
    """Run the server until interrupted: Ctrl-C (SIGINT) or, from the main thread, SIGTERM
    (``KeyboardInterrupt`` propagates after the server has closed).  A SIGINT that the
    process was started with ignored (a background job of a non-interactive shell, as
    POSIX shells start ``command &``) stays ignored, as for any program; SIGTERM still
    stops the server."""
    server = make_server(options)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _terminate)
    if announce is not None:
        announce(server.url)
    try:
        server.serve_forever(poll_interval=0.25)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        server.server_close()

