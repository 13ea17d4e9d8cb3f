"""Progress on stderr for long commands: a one-line bar, shown by default when stderr is a
terminal (``--progress`` / ``--no-progress``)."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TextIO


class ProgressBar:
    """A one-line progress bar on ``stream`` (redrawn at most ten times a second)."""

    def __init__(self, stream: TextIO, label: str) -> None:
        self.stream = stream
        self.label = label
        self.started = time.perf_counter()
        self.last = 0.0

    def __call__(self, done: int, total: int, stage: str | None = None) -> None:
        """Show ``done`` of ``total``; with ``stage``, the stage's name instead of a rate
        (a command made of stages: each one is drawn, however short)."""
        now = time.perf_counter()
        if stage is None and done < total and now - self.last < 0.1:
            return
        self.last = now
        width = 30
        filled = width * done // total if total else width
        rate = done / (now - self.started) if now > self.started else 0.0
        shown = (f"{min(done + 1, total)}/{total} {stage}" if stage is not None
                 else f"{done}/{total} ({rate:,.0f}/s)")
        self.stream.write(f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] "
                          f"{shown:<40}")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def add_progress_flags(sub: argparse.ArgumentParser) -> None:
    """``--progress`` / ``--no-progress`` (``args.progress``: True, False or None)."""
    group = sub.add_mutually_exclusive_group()
    group.add_argument("--progress", dest="progress", action="store_true", default=None,
                       help="show a progress bar on stderr (default: when it is a terminal)")
    group.add_argument("--no-progress", dest="progress", action="store_false")


def progress_bar(args: argparse.Namespace, label: str) -> ProgressBar | None:
    """A bar on stderr when ``args.progress`` asks for one (or, unset, when stderr is a
    terminal), else None."""
    show = args.progress if args.progress is not None else sys.stderr.isatty()
    return ProgressBar(sys.stderr, label) if show else None
