"""The exit codes of the ``geomexact`` command, and the help text listing them."""

from __future__ import annotations

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_BUDGET = 3  # refine stopped by its default step budget (specs/refine.md)
EXIT_INTERRUPTED = 130  # what a shell reports for a command stopped by Ctrl-C (SIGINT)
EXIT_TERMINATED = 143  # what a shell reports for a command ended by SIGTERM
EXIT_BROKEN_PIPE = 141  # as a shell reports for SIGPIPE; also a stdout closed at start

EXIT_CODES_HELP = """\
exit codes:
  0  success
  1  check found violations, a trace diverged during replay, two traces differ (trace
     diff) or a property fails after some step (trace bisect)
  2  bad input or usage: unreadable or malformed file, wrong kind of input, refusal to
     overwrite an existing file (use --force), trace recorded on another mesh, bad option
  3  refine stopped at its default step budget (the refinement may not end; the partial
     result is written; --max-steps none lifts the budget)
  130, 143  stopped by Ctrl-C (SIGINT) or SIGTERM: no output of the command was written
  141  the report could not be printed: its reader went away (| head) or stdout was
     closed (>&-)
"""
