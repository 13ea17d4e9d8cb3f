"""Running a job in a bounded child process: a job is a function that returns a page or
raises :class:`JobFailed`; :func:`run_bounded` runs it in a separate process with a cap on
its memory (its address space), killed after a time limit."""

from __future__ import annotations

import multiprocessing
import multiprocessing.connection
import signal
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


def _megabytes(size: int) -> str:
    return f"{size / (1024 * 1024):,.0f} MB"


def out_of_memory_message(memory_limit: int | None) -> str:
    """What the page says when a job runs out of memory."""
    if memory_limit is None:
        return "the job ran out of memory"
    return (f"the job ran out of memory: it may use at most {_megabytes(memory_limit)} "
            "(ask for less work, or start the server with a larger --memory-limit-mb)")


_NULL_WITHOUT_EXCEPTION = "returned NULL without setting an exception"


def limit_memory(memory_limit: int) -> None:
    """Cap this process's address space at ``memory_limit`` bytes (``RLIMIT_AS``; never
    above the hard limit); an allocation beyond it fails (``MemoryError``)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows: no such limit
        return
    _, hard = resource.getrlimit(resource.RLIMIT_AS)
    soft = memory_limit if hard == resource.RLIM_INFINITY else min(memory_limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def _child(connection: multiprocessing.connection.Connection, job: Callable[..., str],
           args: tuple[Any, ...], memory_limit: int | None) -> None:
    if memory_limit is not None:
        limit_memory(memory_limit)
    try:
        connection.send(("ok", job(*args)))
    except JobFailed as failure:
        connection.send(("failed", failure.status, failure.message))
    except MemoryError:
        connection.send(("failed", HTTPStatus.INSUFFICIENT_STORAGE,
                         out_of_memory_message(memory_limit)))
    except SystemError as error:
        if memory_limit is not None and _NULL_WITHOUT_EXCEPTION in str(error):
            # under the cap, a C extension (GMP's allocator in gmpy2, for one) can fail
            # an allocation without raising MemoryError: it is the cap all the same
            connection.send(("failed", HTTPStatus.INSUFFICIENT_STORAGE,
                             out_of_memory_message(memory_limit)))
        else:
            connection.send(("failed", HTTPStatus.INTERNAL_SERVER_ERROR,
                             f"internal error: SystemError: {error}"))
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


def _ended_message(exitcode: int | None, memory_limit: int | None) -> str:
    if exitcode is not None and exitcode < 0:
        try:
            how = f"it was stopped by {signal.Signals(-exitcode).name}"
        except ValueError:
            how = f"it was stopped by signal {-exitcode}"
    else:
        how = f"exit status {exitcode}"
    hint = ("; it most likely ran out of memory: it may use at most "
            f"{_megabytes(memory_limit)} (ask for less work, or start the server with a "
            "larger --memory-limit-mb)" if memory_limit is not None else "")
    return f"the job's process ended without an answer ({how}){hint}"


def run_bounded(job: Callable[..., str], args: tuple[Any, ...], time_limit: float,
                memory_limit: int | None = None) -> str:
    """``job(*args)`` in a separate process whose address space is capped at
    ``memory_limit`` bytes (None: no cap), killed after ``time_limit`` seconds
    (:class:`JobFailed` 503 then).  A job's :class:`JobFailed` is re-raised here; running
    out of memory is 507, and so is a process that ends without an answer under a memory
    cap (the likely cause; 500 without one)."""
    context: Any = _context()
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(sender, job, args, memory_limit),
                              daemon=True)
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
            process.join(5)
            status = (HTTPStatus.INSUFFICIENT_STORAGE if memory_limit is not None
                      else HTTPStatus.INTERNAL_SERVER_ERROR)
            raise JobFailed(status, _ended_message(process.exitcode, memory_limit)) from None
    finally:
        receiver.close()
        if process.is_alive():
            process.kill()
        process.join(5)
    if answer[0] == "ok":
        return str(answer[1])
    raise JobFailed(int(answer[1]), str(answer[2]))
