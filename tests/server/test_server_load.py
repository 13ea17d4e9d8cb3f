"""A bounded load test of ``geomexact serve`` on loopback (issue 11, part 4): 200
concurrent requests of every kind against the real command, each answered with a status,
no traceback in its log, its memory bounded."""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from helpers.server_client import SQUARE_OFF, multipart, raw_exchange, status_of

REQUESTS = 200
RSS_GROWTH_LIMIT_KB = 32 * 1024
UPLOAD_LIMIT_MB = 0.05


def rss_kb(pid: int) -> int:
    """The resident set size of process ``pid`` now (kB)."""
    status = Path(f"/proc/{pid}/status").read_text()
    match = re.search(r"^VmRSS:\s+(\d+) kB", status, re.M)
    assert match is not None
    return int(match.group(1))


@pytest.fixture()
def command_server(tmp_path: Path) -> Iterator[tuple[int, int, Path]]:
    """`geomexact serve DIR --port 0` as its own process: (pid, port, log file)."""
    if not Path("/proc/self/status").exists():
        pytest.skip("measures memory through /proc")
    root = tmp_path / "served"
    root.mkdir()
    (root / "square.off").write_text(SQUARE_OFF)
    (root / "bad.off").write_text("OFF\n3 1 0\n0 0 0\n")
    log_path = tmp_path / "serve.log"
    with log_path.open("w") as log:
        process = subprocess.Popen(
            [sys.executable, "-m", "geomexact", "serve", str(root), "--port", "0",
             "--jobs", "2", "--view-jobs", "2", "--time-limit", "30",
             "--max-upload-mb", str(UPLOAD_LIMIT_MB)],
            stdout=subprocess.PIPE, stderr=log, text=True)
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
        assert match is not None, line + log_path.read_text()
        yield process.pid, int(match.group(1)), log_path
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        if process.stdout is not None:
            process.stdout.close()


def kinds(port: int) -> list[tuple[str, bytes]]:
    """One raw request of every kind: pages, views, uploads (good and bad), bad requests,
    oversized bodies and cross-site posts."""
    host = f"Host: 127.0.0.1:{port}\r\n"
    body, content_type = multipart([("a.off", SQUARE_OFF.encode())], {"action": "triangulate"})
    bad_body, _ = multipart([("b.off", b"OFF\n3 1 0\n")], {"action": "triangulate"})
    big_body, big_type = multipart([("big.pslg", b"v 0 0\n" * 50_000)],
                                   {"action": "triangulate"})

    def post(data: bytes, kind: str = content_type, extra: str = "") -> bytes:
        return (f"POST /upload HTTP/1.1\r\n{host}Content-Type: {kind}\r\n"
                f"Content-Length: {len(data)}\r\n{extra}\r\n").encode() + data

    def get(path: str, extra: str = "") -> bytes:
        return f"GET {path} HTTP/1.1\r\n{host}{extra}\r\n".encode()

    return [
        ("index", get("/")),
        ("view", get("/view?file=square.off")),
        ("view of a bad file", get("/view?file=bad.off")),
        ("view outside", get("/view?file=../../etc/passwd")),
        ("upload", post(body)),
        ("bad upload", post(bad_body)),
        ("oversize", post(big_body, big_type)),
        ("cross-site null", post(body, extra="Origin: null\r\n")),
        ("cross-site fetch", post(body, extra="Sec-Fetch-Site: cross-site\r\n")),
        ("no length", f"POST /upload HTTP/1.1\r\n{host}Content-Type: {content_type}\r\n\r\n"
                      .encode()),
        ("garbage", b"\x16\x03\x01 not http at all\r\n\r\n"),
        ("not found", get("/nothing")),
        ("foreign host", b"GET / HTTP/1.1\r\nHost: evil.example\r\n\r\n"),
    ]


def answer_all(port: int, requests: list[tuple[str, bytes]]) -> list[tuple[str, int | str]]:
    """Send every request at once (one connection each); each one's status or error."""
    start = threading.Barrier(len(requests))

    def send(item: tuple[str, bytes]) -> tuple[str, int | str]:
        kind, data = item
        start.wait(30)
        try:
            return kind, status_of(raw_exchange("127.0.0.1", port, data, timeout=60))
        except (OSError, AssertionError) as error:
            return kind, type(error).__name__

    with ThreadPoolExecutor(len(requests)) as pool:
        return list(pool.map(send, requests))


def test_two_hundred_mixed_requests(command_server: tuple[int, int, Path]) -> None:
    """200 concurrent requests (13 kinds, round robin): every one answered with an HTTP
    status of its kind, no traceback in the server's log, and the server's RSS grows by
    less than 32 MB over the run (measured: 1-2 MB)."""
    pid, port, log_path = command_server
    every_kind = kinds(port)
    warm = dict(answer_all(port, every_kind))  # first use: imports, the fork server
    assert all(isinstance(status, int) for status in warm.values()), str(warm)
    before = rss_kb(pid)
    requests = [every_kind[index % len(every_kind)] for index in range(REQUESTS)]
    started = time.monotonic()
    answers = answer_all(port, requests)
    elapsed = time.monotonic() - started
    time.sleep(0.5)  # the handler threads finish closing
    after = rss_kb(pid)

    expected: dict[str, Callable[[int], bool]] = {
        "index": lambda status: status == 200,
        "view": lambda status: status in (200, 503),
        "view of a bad file": lambda status: status in (400, 503),
        "view outside": lambda status: status in (404, 503),
        "upload": lambda status: status in (200, 503),
        "bad upload": lambda status: status in (400, 503),
        "oversize": lambda status: status == 413,
        "cross-site null": lambda status: status == 403,
        "cross-site fetch": lambda status: status == 403,
        "no length": lambda status: status == 411,
        "garbage": lambda status: status == 400,
        "not found": lambda status: status == 404,
        "foreign host": lambda status: status == 403,
    }
    wrong = [(kind, status) for kind, status in answers
             if not isinstance(status, int) or not expected[kind](status)]
    assert not wrong, (wrong, Counter(status for _, status in answers))
    log = log_path.read_text()
    assert "Traceback" not in log, log[-3000:]
    assert after - before < RSS_GROWTH_LIMIT_KB, (before, after)
    assert elapsed < 120
