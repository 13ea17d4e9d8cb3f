"""The client side of the server tests: running a :class:`MeshServer` in a thread, HTTP
requests (``http.client``, or raw bytes on a socket for what a library would not send),
multipart bodies and the pages' alert text."""

from __future__ import annotations

import http.client
import io
import re
import socket
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from geomexact.server import MeshServer, ServeOptions, make_server

SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"
UNIT_SQUARE_PSLG = b"v 0 0\nv 1 0\nv 1 1\nv 0 1\ns 0 1\ns 1 2\ns 2 3\ns 3 0\n"


class Log(io.StringIO):
    """A server's log, kept in memory (the server writes whole lines under a lock)."""

    def lines(self) -> list[str]:
        return self.getvalue().splitlines()


@contextmanager
def running(options: ServeOptions, log: Log | None = None) -> Iterator[MeshServer]:
    """A server for ``options`` answering in a thread; shut down afterwards."""
    server = make_server(options, log=log)
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05},
                              daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)


def address(server: MeshServer) -> tuple[str, int]:
    host, port = server.server_address[:2]
    return str(host), int(port)


def request(server: MeshServer, method: str, path: str, body: bytes | None = None,
            headers: dict[str, str] | None = None, timeout: float = 90) -> tuple[int, str]:
    """The status and page of one request (http.client)."""
    connection = http.client.HTTPConnection(*address(server), timeout=timeout)
    try:
        connection.request(method, path, body=body, headers=headers or {})
        response = connection.getresponse()
        return response.status, response.read().decode("utf-8")
    finally:
        connection.close()


def multipart(files: list[tuple[str, bytes]], fields: dict[str, str]) -> tuple[bytes, str]:
    """A ``multipart/form-data`` body of ``files`` (input ``files``) and ``fields``, and
    its Content-Type."""
    boundary = uuid.uuid4().hex
    parts = []
    for name, data in files:
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="files"; '
                     f'filename="{name}"\r\nContent-Type: application/octet-stream\r\n\r\n'
                     .encode() + data + b"\r\n")
    for key, value in fields.items():
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="{key}"\r\n\r\n'
                     f"{value}\r\n".encode())
    parts.append(f"--{boundary}--\r\n".encode())
    return b"".join(parts), f"multipart/form-data; boundary={boundary}"


def upload(server: MeshServer, files: list[tuple[str, bytes]],
           headers: dict[str, str] | None = None, **fields: str) -> tuple[int, str]:
    """POST /upload of ``files`` with the form ``fields``."""
    body, content_type = multipart(files, fields)
    return request(server, "POST", "/upload", body,
                   {"Content-Type": content_type, **(headers or {})})


def raw_exchange(host: str, port: int, data: bytes, *, timeout: float = 60,
                 before_reading: Callable[[socket.socket], None] | None = None) -> bytes:
    """Send ``data`` as it is, then read the whole answer (the server closes)."""
    with socket.create_connection((host, port), timeout=timeout) as connection:
        connection.sendall(data)
        if before_reading is not None:
            before_reading(connection)
        chunks = []
        while chunk := connection.recv(1 << 16):
            chunks.append(chunk)
    return b"".join(chunks)


def status_of(answer: bytes) -> int:
    """The status code of a raw HTTP answer."""
    match = re.match(rb"HTTP/1\.[01] (\d{3}) ", answer)
    assert match is not None, answer[:200]
    return int(match.group(1))


def alert(page: str) -> str:
    """The text of an error page's alert."""
    match = re.search(r'role="alert">(.*?)</p>', page, re.S)
    assert match is not None, page[:500]
    return match.group(1)


def wait_until(condition: Callable[[], bool], seconds: float = 30) -> None:
    """Poll ``condition`` until it holds (AssertionError after ``seconds``)."""
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out waiting"
        time.sleep(0.02)
