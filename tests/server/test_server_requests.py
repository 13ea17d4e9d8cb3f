"""``geomexact serve`` answers every request with a status (issue 11, part 4): cross-site
state-changing requests are refused, an oversized or unsized upload gets its 4xx page
readable by the client, 40 uploads at once all get 200 or 503 (no reset), and a client
that goes away is one log line."""

from __future__ import annotations

import http.client
import re
import socket
import struct
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from helpers.server_client import (
    SQUARE_OFF,
    UNIT_SQUARE_PSLG,
    Log,
    address,
    alert,
    multipart,
    raw_exchange,
    request,
    running,
    status_of,
    wait_until,
)

from geomexact import server as serve
from geomexact.server import MeshServer, ServeOptions
from geomexact.server.bounded import running_jobs
from geomexact.server.http_server import LISTEN_BACKLOG, same_origin


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("requests")
    (root / "square.off").write_text(SQUARE_OFF)
    return root


@pytest.fixture()
def log() -> Log:
    return Log()


@pytest.fixture()
def server(served: Path, log: Log) -> Iterator[MeshServer]:
    with running(ServeOptions(served, port=0, max_upload_bytes=4000, time_limit=60, jobs=2,
                              view_jobs=2), log) as server:
        yield server


def square_upload(**headers: str) -> tuple[bytes, dict[str, str]]:
    body, content_type = multipart([("a.off", SQUARE_OFF.encode())], {"action": "triangulate"})
    return body, {"Content-Type": content_type, **headers}


# ---------------------------------------------------------------------------------------
# cross-site requests
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("headers", [
    {"Origin": "null"},
    {"Origin": "NULL"},
    {"Origin": "null", "Sec-Fetch-Site": "cross-site"},
    {"Origin": "null", "Sec-Fetch-Site": "none"},
    {"Sec-Fetch-Site": "cross-site"},
    {"Sec-Fetch-Site": "same-site"},
    {"Origin": "http://localhost:1"},
    {"Origin": "https://evil.example"},
    {"Origin": "SAME", "Sec-Fetch-Site": "cross-site"},
])
def test_cross_site_uploads_are_refused(server: MeshServer, headers: dict[str, str]) -> None:
    """POST with Origin null, another origin, or Sec-Fetch-Site other than same-origin /
    none (with or without an Origin): 403, and no job is run."""
    host, port = address(server)
    if headers.get("Origin") == "SAME":
        headers = {**headers, "Origin": f"http://{host}:{port}"}
    body, sent = square_upload(**headers)
    status, page = request(server, "POST", "/upload", body, sent)
    assert status == 403, page[:300]
    assert "not accepted" in alert(page)


@pytest.mark.parametrize("headers", [
    {},
    {"Origin": "SAME"},
    {"Origin": "SAME", "Sec-Fetch-Site": "same-origin"},
    {"Sec-Fetch-Site": "none"},
    # Chromium's own form under a strict referrer policy sends Origin: null; the
    # browser-set Sec-Fetch-Site (a page cannot forge it) says it is same-origin
    {"Origin": "null", "Sec-Fetch-Site": "same-origin"},
])
def test_same_origin_and_plain_uploads_are_accepted(server: MeshServer,
                                                    headers: dict[str, str]) -> None:
    """Same origin (the page's own form), or neither header (curl): the upload runs."""
    host, port = address(server)
    if headers.get("Origin") == "SAME":
        headers = {**headers, "Origin": f"http://{host}:{port}"}
    body, sent = square_upload(**headers)
    status, page = request(server, "POST", "/upload", body, sent)
    assert status == 200, page[:300]


@pytest.mark.parametrize(("origin", "host", "same"), [
    ("http://127.0.0.1:8765", "127.0.0.1:8765", True),
    ("http://LOCALHOST:8765", "localhost:8765", True),
    ("http://localhost", "localhost:80", True),
    ("http://[::1]:8765", "[::1]:8765", True),
    ("https://127.0.0.1:8765", "127.0.0.1:8765", False),
    ("http://127.0.0.1:8766", "127.0.0.1:8765", False),
    ("http://127.0.0.1:x", "127.0.0.1:8765", False),
    ("http://127.0.0.1:8765", "", False),
    ("http://user@127.0.0.1:8765", "127.0.0.1:8765", False),
])
def test_same_origin(origin: str, host: str, same: bool) -> None:
    """Scheme http, the same name and port (80 when omitted)."""
    assert same_origin(origin, host) is same


# ---------------------------------------------------------------------------------------
# sizes: answered before the body, and the answer reaches the client
# ---------------------------------------------------------------------------------------
def test_oversized_upload_gets_a_readable_413(server: MeshServer) -> None:
    """A body far above the limit, sent whole by http.client before it reads: the client
    reads the 413 page (no broken pipe, no reset), with Connection: close."""
    body, content_type = multipart([("big.pslg", b"v 0 0\n" * 400_000)],
                                   {"action": "triangulate"})
    connection = http.client.HTTPConnection(*address(server), timeout=60)
    try:
        connection.request("POST", "/upload", body=body, headers={"Content-Type": content_type})
        response = connection.getresponse()
        page = response.read().decode("utf-8")
    finally:
        connection.close()
    assert response.status == 413
    assert response.getheader("Connection") == "close"
    assert f"{len(body):,} bytes" in alert(page) and "at most 4,000" in alert(page)


def test_413_is_sent_before_the_body(server: MeshServer) -> None:
    """A client that waits for the answer before sending its body gets the 413 at once."""
    host, port = address(server)
    answer = raw_exchange(host, port, (
        f"POST /upload HTTP/1.1\r\nHost: {host}:{port}\r\nContent-Type: multipart/form-data; "
        "boundary=x\r\nContent-Length: 50000000\r\nExpect: 100-continue\r\n\r\n").encode(),
        timeout=20)
    assert status_of(answer) == 413


@pytest.mark.parametrize(("headers", "expected"), [
    ("", 411),
    ("Transfer-Encoding: chunked\r\n", 411),
    ("Content-Length: abc\r\n", 400),
    ("Content-Length: -5\r\n", 400),
    ("Content-Length: \u00b2\r\n", 400),
    ("Content-Length: 10\r\nContent-Length: 12\r\n", 400),
])
def test_uploads_need_a_valid_length(server: MeshServer, headers: str, expected: int) -> None:
    """No Content-Length (or a chunked body): 411; one that is not a length: 400."""
    host, port = address(server)
    head = (f"POST /upload HTTP/1.1\r\nHost: {host}:{port}\r\n"
            f"Content-Type: multipart/form-data; boundary=x\r\n{headers}\r\n")
    answer = raw_exchange(host, port, head.encode("utf-8") + b"5\r\nhello\r\n0\r\n\r\n",
                          timeout=20)
    assert status_of(answer) == expected


# ---------------------------------------------------------------------------------------
# many clients, and clients that leave
# ---------------------------------------------------------------------------------------
def test_forty_uploads_at_once_all_get_a_status(server: MeshServer, log: Log) -> None:
    """40 concurrent uploads with 2 job slots: each is answered 200 or 503 busy, none is
    reset; the log has no traceback."""
    assert LISTEN_BACKLOG >= 128
    body, headers = square_upload()

    def send(_: int) -> int | str:
        try:
            return request(server, "POST", "/upload", body, headers, timeout=60)[0]
        except OSError as error:
            return type(error).__name__

    with ThreadPoolExecutor(40) as pool:
        statuses = list(pool.map(send, range(40)))
    assert set(statuses) <= {200, 503}, statuses
    assert 200 in statuses
    assert "Traceback" not in log.getvalue()


def reset_on_close(connection: socket.socket) -> None:
    """Close with a TCP reset (SO_LINGER 0), as a killed browser tab does."""
    connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))


@pytest.mark.skipif("refine" not in serve.available_actions(),
                    reason="needs geomexact.mesh2d.refinement.api (a long job)")
@pytest.mark.parametrize("reset", [True, False], ids=["reset", "close"])
def test_a_client_that_leaves_gets_its_job_stopped(served: Path, reset: bool) -> None:
    """A client that disconnects (a reset, or a plain close) while its job runs: the job's
    process is killed and its slot released at once, not at the time limit (60 s; the
    guard waits 15 s); the server logs one line naming the client, no traceback, and
    keeps answering."""
    log = Log()
    with running(ServeOptions(served, port=0, time_limit=60), log) as server:
        host, port = address(server)
        body, content_type = multipart([("sq.pslg", UNIT_SQUARE_PSLG)], {
            "action": "refine", "criterion": "max_area", "value": "1e-12"})
        connection = socket.create_connection((host, port), timeout=30)
        try:
            connection.sendall(f"POST /upload HTTP/1.1\r\nHost: {host}:{port}\r\n"
                               f"Content-Type: {content_type}\r\n"
                               f"Content-Length: {len(body)}\r\n\r\n".encode() + body)
            wait_until(lambda: server.upload_slots.in_use == 1 and len(running_jobs()) == 1)
            (pid,) = running_jobs()
            if reset:
                reset_on_close(connection)
        finally:
            connection.close()
        wait_until(lambda: server.upload_slots.in_use == 0 and not running_jobs(), 15)
        wait_until(lambda: not Path(f"/proc/{pid}").exists(), 15)
        wait_until(lambda: "went away" in log.getvalue())
        assert request(server, "GET", "/")[0] == 200
    gone = [line for line in log.lines() if "went away" in line]
    assert len(gone) == 1, log.getvalue()
    assert re.fullmatch(r"geomexact serve: 127\.0\.0\.1 went away during its job "
                        r"\(POST /upload\); the job was stopped", gone[0]), gone
    assert "Traceback" not in log.getvalue()
