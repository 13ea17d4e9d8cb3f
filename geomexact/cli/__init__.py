"""The ``geomexact`` command: parses arguments, calls the library, prints.

Commands: ``info``, ``check``, ``convert``, ``replay``, ``trace`` (``show``, ``diff``,
``bisect``), ``triangulate``, ``polylla``, ``refine``, ``cuboid``, ``census``, ``octree``,
``view``, ``serve``, ``demo`` (see ``docs/cli.md``), one module each.
Exit codes: 0 success; 1 a check failed or a trace diverged; 2 bad input or usage.  Every
error geomexact raises on purpose (:class:`~geomexact.errors.GeomexactError`) and every
``OSError`` is reported as one line ``geomexact: error: …`` on stderr, never as a
traceback.  With ``--json`` a command prints exactly one JSON object on stdout.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from collections.abc import Sequence
from typing import NoReturn

from geomexact.cli.errors import (
    StdoutClosed,
    Terminated,
    UsageProblem,
    os_error_text,
    print_error,
    stand_in_for_closed_streams,
)
from geomexact.cli.exit_codes import (
    EXIT_BAD_INPUT,
    EXIT_BROKEN_PIPE,
    EXIT_BUDGET,
    EXIT_CODES_HELP,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_TERMINATED,
)
from geomexact.cli.parser import build_parser, triangle_switch_hint

__all__ = [
    "EXIT_BAD_INPUT",
    "EXIT_BROKEN_PIPE",
    "EXIT_BUDGET",
    "EXIT_CODES_HELP",
    "EXIT_FAILED",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_TERMINATED",
    "UsageProblem",
    "build_parser",
    "main",
    "run",
]


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that flushing it at exit raises nothing more."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # stdout without a file descriptor (e.g. captured)
        pass


def main(argv: Sequence[str] | None = None, *, cap_memory: bool = False) -> int:
    """Run the ``geomexact`` command with ``argv`` (default: ``sys.argv[1:]``); return the
    exit code.  With ``cap_memory`` (the console script) the process may grow by at most
    the command's memory budget (``--max-memory``), so that any larger allocation is a
    one-line error instead of swapping or the kernel's out-of-memory killer."""
    words = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(words)  # only the command named is loaded
    try:
        args = parser.parse_args(words)
        args.argv = ["geomexact", *words]
    except SystemExit as stop:  # --help, --version and usage errors
        code = stop.code if isinstance(stop.code, int) else EXIT_BAD_INPUT
        hint = triangle_switch_hint(words) if code == EXIT_BAD_INPUT else None
        if hint is not None:
            print(hint, file=sys.stderr)
        return code
    from geomexact.cli.memory import budget_of, cap_address_space, command_budget, size_text
    from geomexact.errors import GeomexactError, is_allocation_failure
    from geomexact.io.files import output_set

    budget = budget_of(getattr(args, "max_memory", None))
    if cap_memory and hasattr(args, "max_memory"):  # (serve bounds each job instead)
        cap_address_space(budget)
    try:
        with command_budget(budget), output_set():  # the outputs appear together, or none
            return int(args.run(args))
    except (GeomexactError, UsageProblem) as error:
        print_error(str(error))
    except MemoryError:
        print_error(f"out of memory: the command needed more than the "
                    f"{size_text(budget.limit)} it may use ({budget.source}); nothing was "
                    f"written: ask for less, or {budget.more()}")
    except SystemError as error:  # an allocation failed in a C extension (GMP under a cap)
        if not is_allocation_failure(error):
            raise
        print_error(f"out of memory in a compiled routine ({size_text(budget.limit)} "
                    f"allowed, {budget.source}); nothing was written")
    except StdoutClosed:
        print_error("standard output is closed (>&-): the command cannot print its report; "
                    "nothing was written (send it to /dev/null to discard it)")
        return EXIT_BROKEN_PIPE
    except BrokenPipeError:
        _silence_stdout()  # the reader went away (e.g. `| head`): stop quietly, as SIGPIPE
        return EXIT_BROKEN_PIPE
    except OSError as error:
        print_error(os_error_text(error))
    except KeyboardInterrupt:
        print_error("interrupted")
        return EXIT_INTERRUPTED
    except Terminated:
        print_error("terminated (SIGTERM)")
        return EXIT_TERMINATED
    return EXIT_BAD_INPUT


def _terminate(signum: int, frame: object) -> None:
    raise Terminated


def run() -> NoReturn:
    """The console script (and ``python -m geomexact``): :func:`main`, then end the
    process at once, once stdout and stderr are flushed: the objects of a large mesh are
    not freed one by one when the process ends anyway (a second or more on a mesh of
    10^5 tetrahedra).  SIGTERM ends a command as Ctrl-C does: nothing half-written."""
    signal.signal(signal.SIGTERM, _terminate)
    stand_in_for_closed_streams()
    code = main(cap_memory=True)
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        code = EXIT_BROKEN_PIPE
    except (OSError, ValueError):
        pass
    with contextlib.suppress(OSError, ValueError):
        sys.stderr.flush()
    os._exit(code)
