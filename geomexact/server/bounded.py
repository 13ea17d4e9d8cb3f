"""Running a job in a bounded child process: a job is a function that returns a page or
raises :class:`JobFailed`; :func:`run_bounded` runs it in a separate process with a cap on
its memory (its address space), killed after a time limit or when the client it answers
closes its connection (:class:`ClientGone`)."""

from __future__ import annotations

import errno
import math
import multiprocessing
import multiprocessing.connection
import os
import signal
import socket
import threading
import time
import traceback
from collections.abc import Callable
from http import HTTPStatus
from typing import Any

from geomexact.errors import is_allocation_failure

RETRY_AFTER_SECONDS = 2
"""What a "busy" answer (503) tells the client to wait before trying again."""


class JobFailed(Exception):
    """A job's answer that is not a page: an HTTP status and a message for the user;
    ``retry_after`` (seconds) when trying again later may succeed (the server was busy)."""

    def __init__(self, status: int, message: str, retry_after: int | None = None) -> None:
        super().__init__(message)
        self.status = status
        self.message = message
        self.retry_after = retry_after


class ClientGone(Exception):
    """The client closed its connection while its job ran: the job was stopped and there
    is no one to answer."""


def _megabytes(size: int) -> str:
    return f"{size / (1024 * 1024):,.0f} MB"


def out_of_memory_message(memory_limit: int | None) -> str:
    """What the page says when a job runs out of memory."""
    if memory_limit is None:
        return "the job ran out of memory"
    return (f"the job ran out of memory: it may use at most {_megabytes(memory_limit)} "
            "(ask for less work, or start the server with a larger --memory-limit-mb)")


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


def _internal_error(error: BaseException) -> str:
    """The page's message for a job's unexpected ``error``: its kind only (its text may
    name the server's files); the traceback goes to the server's standard error."""
    traceback.print_exception(error)
    return (f"internal error: {type(error).__name__} (a bug in geomexact; the server's "
            "standard error has the details)")


def limit_cpu(seconds: float) -> None:
    """Cap this process's CPU time at ``seconds`` (``RLIMIT_CPU``, rounded up; never above
    the hard limit): past it the kernel stops the process (SIGXCPU)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows: no such limit
        return
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    soft = math.ceil(seconds)
    if hard != resource.RLIM_INFINITY:
        soft = min(soft, hard)
    resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))


def _child(connection: multiprocessing.connection.Connection, job: Callable[..., str],
           args: tuple[Any, ...], memory_limit: int | None, cpu_limit: float) -> None:
    if memory_limit is not None:
        limit_memory(memory_limit)
    # the parent kills the job at its time limit; should the parent lose track of it (the
    # fork server that reports its exit gone), the kernel still stops it
    limit_cpu(cpu_limit)
    try:
        connection.send(("ok", job(*args)))
    except JobFailed as failure:
        connection.send(("failed", failure.status, failure.message))
    except MemoryError:
        connection.send(("failed", HTTPStatus.INSUFFICIENT_STORAGE,
                         out_of_memory_message(memory_limit)))
    except SystemError as error:
        if memory_limit is not None and is_allocation_failure(error):
            # under the cap, a C extension (GMP's allocator in gmpy2, for one) can fail
            # an allocation without raising MemoryError: it is the cap all the same
            connection.send(("failed", HTTPStatus.INSUFFICIENT_STORAGE,
                             out_of_memory_message(memory_limit)))
        else:
            connection.send(("failed", HTTPStatus.INTERNAL_SERVER_ERROR,
                             _internal_error(error)))
    except BaseException as error:  # report, never hang the parent
        connection.send(("failed", HTTPStatus.INTERNAL_SERVER_ERROR, _internal_error(error)))
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


_START_LOCK = threading.Lock()
START_ATTEMPTS = 4
START_DESCRIPTORS = 16  # what starting a job opens at most at once, with room to spare
START_RETRY_SECONDS = 0.1
_RUNNING_LOCK = threading.Lock()
_RUNNING: set[int] = set()


def running_jobs() -> frozenset[int]:
    """The process ids of the jobs running now (started and not yet ended)."""
    with _RUNNING_LOCK:
        return frozenset(_RUNNING)


def _cannot_start(error: BaseException) -> JobFailed:
    reason = (error.strerror or type(error).__name__ if isinstance(error, OSError)
              else "the process starter stopped")
    return JobFailed(
        HTTPStatus.SERVICE_UNAVAILABLE,
        f"the server cannot start a job now ({reason}); try again in a few seconds",
        retry_after=RETRY_AFTER_SECONDS,
    )


def _free_descriptors() -> int | None:
    """How many more files this process may open now (None: unknown here)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows: no such limit
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY:
        return None
    try:
        open_now = len(os.listdir("/dev/fd")) - 1  # less the one the listing used
    except FileNotFoundError:  # pragma: no cover - no /dev/fd to count them
        return None
    except OSError:  # not even one descriptor left to list them
        return 0
    return soft - open_now


def _start(process: Any) -> None:
    """Start ``process``; a failure to start (descriptors, processes or memory exhausted)
    is :class:`JobFailed` 503 with a retry hint.

    Starts are serialized: the fork server answers one request at a time anyway, and a
    request that fails half-way (an OS limit on descriptors hit between connecting to it
    and sending it the job's descriptors) makes CPython's fork server exit, which failed
    every other start in flight with ``EOFError``.  One at a time, a failure costs only its
    own request; the fork server gone, the start is tried again (a new one is launched
    once the old one has exited)."""
    for attempt in range(1, START_ATTEMPTS + 1):
        try:
            with _START_LOCK:
                # CPython's start leaks two descriptors, and leaves the new process
                # waiting for its data forever, when the limit is hit between its steps:
                # start only with room for all of them
                free = _free_descriptors()
                if free is not None and free < START_DESCRIPTORS:
                    raise OSError(errno.EMFILE, os.strerror(errno.EMFILE))
                process.start()
            return
        except (ConnectionError, EOFError) as error:  # the fork server went away
            if attempt == START_ATTEMPTS:
                raise _cannot_start(error) from None
            time.sleep(START_RETRY_SECONDS * attempt)
        except OSError as error:
            raise _cannot_start(error) from None


def _client_closed(client: socket.socket) -> bool:
    """True when the peer of ``client`` (readable now) has closed the connection; False
    when it sent more bytes (left unread)."""
    try:
        return not client.recv(1, socket.MSG_PEEK | socket.MSG_DONTWAIT)
    except (BlockingIOError, InterruptedError):
        return False
    except OSError:  # reset
        return True


def _wait_for_answer(receiver: multiprocessing.connection.Connection, time_limit: float,
                     client: socket.socket | None) -> None:
    """Return once the child's answer (or its end) can be read; :class:`JobFailed` 503
    past ``time_limit`` seconds, :class:`ClientGone` when ``client`` closes first."""
    deadline = time.monotonic() + time_limit
    watched: list[Any] = [receiver] if client is None else [receiver, client]
    while True:
        left = deadline - time.monotonic()
        ready = multiprocessing.connection.wait(watched, max(left, 0.0))
        if receiver in ready:
            return
        if not ready:
            raise JobFailed(
                HTTPStatus.SERVICE_UNAVAILABLE,
                f"the job took longer than the server's time limit of {time_limit:g} s and was "
                "stopped (ask for less work, or start the server with a larger --time-limit)",
            )
        assert client is not None
        if _client_closed(client):
            raise ClientGone
        watched = [receiver]  # it sent more than its request: only its closing matters


def run_bounded(job: Callable[..., str], args: tuple[Any, ...], time_limit: float,
                memory_limit: int | None = None, *,
                client: socket.socket | None = None) -> str:
    """``job(*args)`` in a separate process whose address space is capped at
    ``memory_limit`` bytes (None: no cap), killed after ``time_limit`` seconds
    (:class:`JobFailed` 503 then) or as soon as the peer of ``client`` (the connection the
    answer is for) closes it (:class:`ClientGone` then).  A job's :class:`JobFailed` is
    re-raised here; running out of memory is 507, and so is a process that ends without an
    answer under a memory cap (the likely cause; 500 without one).  A process that cannot
    be started now (an OS limit) is 503 with ``retry_after``."""
    context: Any = _context()
    try:
        receiver, sender = context.Pipe(duplex=False)
    except OSError as error:  # no descriptors left
        raise _cannot_start(error) from None
    # CPU time: the wall-clock limit with room for threads; only a backstop
    process = context.Process(target=_child, daemon=True,
                              args=(sender, job, args, memory_limit, 2 * time_limit + 5))
    try:
        _start(process)
    except BaseException:
        receiver.close()
        raise
    finally:
        sender.close()
    pid = process.pid
    with _RUNNING_LOCK:
        _RUNNING.add(pid)
    try:
        _wait_for_answer(receiver, time_limit, client)
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
        with _RUNNING_LOCK:
            _RUNNING.discard(pid)
        if process.exitcode is not None:
            process.close()  # its descriptors now, not when it is collected
    if answer[0] == "ok":
        return str(answer[1])
    raise JobFailed(int(answer[1]), str(answer[2]))
