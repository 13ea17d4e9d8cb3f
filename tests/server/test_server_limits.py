"""``geomexact serve`` bounds its jobs (issue 11, part 4): viewing has its own slots (two
running uploads never make it busy), and a job past its memory cap is stopped and answered
with a page (past its time limit: ``test_serve.py::test_run_time_is_bounded``)."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest
from helpers.server_client import (
    SQUARE_OFF,
    UNIT_SQUARE_PSLG,
    Log,
    alert,
    request,
    running,
    upload,
    wait_until,
)

from geomexact import server as serve
from geomexact.server import ServeOptions
from geomexact.server.options import DEFAULT_MEMORY_LIMIT_BYTES, DEFAULT_VIEW_JOBS

needs_refine = pytest.mark.skipif("refine" not in serve.available_actions(),
                                  reason="needs geomexact.mesh2d.refinement.api (long jobs)")
ENDLESS = {"action": "refine", "criterion": "max_area", "value": "1e-12",
           "method": "centroid", "max_steps": "5000000"}


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("limits")
    (root / "square.off").write_text(SQUARE_OFF)
    return root


@needs_refine
def test_viewing_works_while_uploads_fill_their_slots(served: Path) -> None:
    """Two long uploads take both upload slots: viewing still answers 200, a third upload
    is told busy (503), and the long ones end with the time-limit page."""
    log = Log()
    with running(ServeOptions(served, port=0, time_limit=4, jobs=2, view_jobs=2), log
                 ) as server:
        answers: list[tuple[int, str]] = []
        uploads = [threading.Thread(
            target=lambda: answers.append(upload(server, [("sq.pslg", UNIT_SQUARE_PSLG)],
                                                 **ENDLESS)))
            for _ in range(2)]
        for thread in uploads:
            thread.start()
        try:
            wait_until(lambda: server.upload_slots.in_use == 2)
            status, page = request(server, "GET", "/view?file=square.off")
            assert status == 200, alert(page)
            status, page = request(server, "GET", "/")
            assert status == 200
            status, page = upload(server, [("a.off", SQUARE_OFF.encode())],
                                  action="triangulate")
            assert status == 503 and "busy with 2 upload job(s)" in alert(page)
        finally:
            for thread in uploads:
                thread.join(60)
        assert [status for status, _ in answers] == [503, 503]
        assert all("time limit of 4 s" in alert(page) for _, page in answers)
    assert "Traceback" not in log.getvalue()


@needs_refine
def test_a_job_past_its_memory_cap_gets_a_page(served: Path) -> None:
    """A refinement that would grow without end, under a 250 MB cap (and a time limit far
    away): stopped when it runs out, 507 with a page naming the cap; the server goes on."""
    pytest.importorskip("resource")
    log = Log()
    with running(ServeOptions(served, port=0, time_limit=120,
                              memory_limit_bytes=250 * 1024 * 1024), log) as server:
        status, page = upload(server, [("sq.pslg", UNIT_SQUARE_PSLG)], **ENDLESS)
        assert status == 507, alert(page)
        assert "ran out of memory" in alert(page) and "at most 250 MB" in alert(page)
        assert 'action="/upload"' in page  # the page offers the form again
        assert request(server, "GET", "/view?file=square.off")[0] == 200
    assert "Traceback" not in log.getvalue()


def test_memory_cap_in_the_job_process() -> None:
    """run_bounded caps the child's address space: a job allocating past it gets 507."""
    pytest.importorskip("resource")
    with pytest.raises(serve.JobFailed) as caught:
        serve.run_bounded(bytearray, (1 << 31,), 30, memory_limit=512 * 1024 * 1024)
    assert caught.value.status == 507 and "at most 512 MB" in caught.value.message
    assert len(serve.run_bounded(str, (b"x" * (1 << 20),), 30,
                                 memory_limit=512 * 1024 * 1024)) > 1 << 20


def test_a_failed_allocation_that_raised_nothing_is_the_memory_cap_too() -> None:
    """Under the cap, a C extension that fails an allocation without raising MemoryError
    (CPython then raises SystemError "... returned NULL without setting an exception")
    gets the out-of-memory page; without a cap it is an internal error."""
    pytest.importorskip("resource")
    raising = ("(_ for _ in ()).throw(SystemError("
               "'<f> returned NULL without setting an exception'))",)
    with pytest.raises(serve.JobFailed) as caught:
        serve.run_bounded(eval, raising, 30, memory_limit=512 * 1024 * 1024)
    assert caught.value.status == 507 and "at most 512 MB" in caught.value.message
    with pytest.raises(serve.JobFailed) as caught:
        serve.run_bounded(eval, raising, 30)
    assert caught.value.status == 500 and "SystemError" in caught.value.message


def test_serve_cli_limits_are_the_servers(tmp_path: Path) -> None:
    """The CLI's defaults for the new limits agree with ServeOptions', and reach it."""
    from geomexact.cli.parser import build_parser

    args = build_parser().parse_args(["serve", str(tmp_path)])
    assert args.view_jobs == DEFAULT_VIEW_JOBS
    assert args.memory_limit_mb * 1024 * 1024 == DEFAULT_MEMORY_LIMIT_BYTES
    assert ServeOptions(tmp_path).memory_limit_bytes == DEFAULT_MEMORY_LIMIT_BYTES
