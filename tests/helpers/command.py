"""Running the ``geomexact`` command inside a test: its exit code and what it printed."""

from __future__ import annotations

import pytest

from geomexact.cli import main


def run(capsys: pytest.CaptureFixture[str], *argv: object) -> tuple[int, str, str]:
    """``geomexact ARGV...`` (each word as text): (exit code, stdout, stderr)."""
    code = main([str(word) for word in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err
