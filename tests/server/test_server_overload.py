"""``geomexact serve`` under more requests than it runs at once (issue 27, item 8): busy is
503 with ``Retry-After`` and a retry hint, never 500 nor a dropped connection, also when
the system refuses to start a job process (no descriptors left); connections past the
server's limit wait unaccepted.  Loads only on 127.0.0.1, bounded in count and time."""

from __future__ import annotations

import json
import re
import socket
import subprocess
import sys
import textwrap
import threading
from collections import Counter
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from helpers.server_client import (
    SQUARE_OFF,
    Log,
    address,
    raw_exchange,
    request,
    running,
    status_of,
    wait_until,
)

from geomexact.server import MeshServer, ServeOptions
from geomexact.server.bounded import RETRY_AFTER_SECONDS, running_jobs

SIMULTANEOUS = 50


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("overload")
    (root / "square.off").write_text(SQUARE_OFF)
    return root


def simultaneous_views(server: MeshServer, count: int) -> list[bytes]:
    """``count`` GET /view requests sent at once (one connection each); the raw answers."""
    host, port = address(server)
    data = f"GET /view?file=square.off HTTP/1.1\r\nHost: {host}:{port}\r\n\r\n".encode()
    start = threading.Barrier(count)

    def send(_: int) -> bytes:
        start.wait(30)
        try:
            return raw_exchange(host, port, data, timeout=60)
        except OSError as error:
            return f"no answer: {type(error).__name__}".encode()

    with ThreadPoolExecutor(count) as pool:
        return list(pool.map(send, range(count)))


def check_answers(answers: list[bytes]) -> Counter[int]:
    """Every answer is 200, or 503 with a ``Retry-After`` header and a retry hint in the
    page; the count of each status."""
    statuses: Counter[int] = Counter()
    for answer in answers:
        assert answer.startswith(b"HTTP/"), answer[:200]
        status = status_of(answer)
        statuses[status] += 1
        head, _, page = answer.partition(b"\r\n\r\n")
        if status == 503:
            assert re.search(rb"\r\nRetry-After: \d+\r\n", head), head
            assert b"try again" in page, page[:500]
        else:
            assert status == 200, answer[:1000]
    return statuses


@pytest.fixture()
def log() -> Iterator[Log]:
    log = Log()
    yield log
    assert "Traceback" not in log.getvalue(), log.getvalue()


def test_fifty_simultaneous_views_are_answered_or_told_busy(served: Path, log: Log) -> None:
    """50 simultaneous views, two viewing slots: two or more 200, the rest 503 with
    Retry-After and "try again", nothing else; the slots and job processes all free
    afterwards."""
    with running(ServeOptions(served, port=0), log) as server:
        statuses = check_answers(simultaneous_views(server, SIMULTANEOUS))
        assert statuses[200] >= 2 and sum(statuses.values()) == SIMULTANEOUS
        wait_until(lambda: server.view_slots.in_use == 0 and not running_jobs(), 15)


def test_fifty_simultaneous_view_jobs(served: Path, log: Log) -> None:
    """50 viewing slots: 50 job processes started at once, each view 200 (503 with
    Retry-After allowed, were the system short of something), never 500."""
    with running(ServeOptions(served, port=0, view_jobs=SIMULTANEOUS), log) as server:
        for _ in range(2):
            statuses = check_answers(simultaneous_views(server, SIMULTANEOUS))
            assert statuses[200] > 0
        wait_until(lambda: server.view_slots.in_use == 0 and not running_jobs(), 15)


def test_busy_answer_carries_retry_after(served: Path, log: Log) -> None:
    """With the only viewing slot taken, a view is 503 with Retry-After (seconds)."""
    with running(ServeOptions(served, port=0, view_jobs=1), log) as server:
        assert server.view_slots.try_acquire()
        try:
            (answer,) = simultaneous_views(server, 1)
        finally:
            server.view_slots.release()
        assert status_of(answer) == 503
        assert f"\r\nRetry-After: {RETRY_AFTER_SECONDS}\r\n".encode() in answer
        assert b"busy with 1 viewing job(s); try again in a few seconds" in answer


NO_DESCRIPTORS = textwrap.dedent("""
    import json, os, resource
    from geomexact.server import JobFailed, run_bounded

    def run():
        try:
            return run_bounded(str, (1,), 60)
        except JobFailed as failure:
            return [failure.status, failure.retry_after, failure.message]

    first = run()
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (128, hard))
    held = []
    try:
        while True:
            held.append(os.open(os.devnull, os.O_RDONLY))
    except OSError:
        pass
    tight = []
    for _ in range(24):  # one more descriptor free at each try
        tight.append(run())
        os.close(held.pop())
    for fd in held:
        os.close(fd)
    print(json.dumps({"first": first, "tight": tight, "after": run()}))
""")


def test_a_job_that_cannot_start_is_503_with_retry_after() -> None:
    """No descriptors left, then one more free at each try: the tries are 503 with
    retry_after and "try again" (never an exception) until there is room to start a job,
    then every one runs (a failed start leaks nothing; CPython's own start, failing between
    its steps, leaked two descriptors and a process waiting forever)."""
    pytest.importorskip("resource")
    done = subprocess.run([sys.executable, "-c", NO_DESCRIPTORS], capture_output=True,
                          text=True, timeout=240, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["first"] == "1" and report["after"] == "1"
    tight = report["tight"]
    refused = [answer for answer in tight if answer != "1"]
    assert refused and len(refused) < len(tight), tight
    assert all(answer == "1" for answer in tight[len(refused):]), tight
    for status, retry_after, message in refused:
        assert status == 503 and retry_after == RETRY_AFTER_SECONDS, message
        assert "cannot start a job now" in message and "try again" in message


def test_connections_past_the_limit_wait_unaccepted(served: Path, log: Log) -> None:
    """With max_connections=4 and four idle connections open, a fifth request is not
    accepted (the server holds four); once one idle connection closes, it is answered."""
    with running(ServeOptions(served, port=0, max_connections=4), log) as server:
        idle = [socket.create_connection(address(server), timeout=30) for _ in range(4)]
        try:
            wait_until(lambda: server.connection_slots.in_use == 4)
            answers: list[tuple[int, str]] = []
            waiting = threading.Thread(target=lambda: answers.append(
                request(server, "GET", "/", timeout=60)))
            waiting.start()
            waiting.join(1.0)
            assert not answers and server.connection_slots.in_use == 4
        finally:
            idle[0].close()
        waiting.join(60)
        assert answers and answers[0][0] == 200
        for connection in idle[1:]:
            connection.close()
        wait_until(lambda: server.connection_slots.in_use == 0)
