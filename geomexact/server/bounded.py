"""Running a job in a bounded child process: a job is a function that returns a page or
raises :class:`JobFailed`; :func:`run_bounded` runs it in a separate process killed after a
time limit."""

from __future__ import annotations

import multiprocessing
import multiprocessing.connection
import threading
import traceback
from collections.abc import Callable
from http import HTTPStatus
from typing import Any


class JobFailed(Exception):
    """A job's answer that is not a page: an HTTP status and a message for the user."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


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
                context.set_forkserver_preload(["geomexact.server", "geomexact.viz.viewer"])
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
