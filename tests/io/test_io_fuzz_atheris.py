"""A sampled atheris session over every reader (``fuzz_readers.py``): a few thousand
coverage-guided inputs in CI, many more with ``--runslow``.  A crash is any exception but
a FormatError, or a broken contract (``helpers.reader_fuzz``); libFuzzer then exits
non-zero and prints the input."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("atheris")

HERE = Path(__file__).resolve().parent
TESTS = HERE.parent


def _fuzz(tmp_path: Path, runs: int, seconds: int) -> None:
    environment = {**os.environ, "PYTHONPATH": str(TESTS)}
    completed = subprocess.run(
        [sys.executable, str(HERE / "fuzz_readers.py"), str(tmp_path / "corpus"),
         f"-runs={runs}", f"-max_total_time={seconds}", "-max_len=65536", "-seed=1",
         f"-artifact_prefix={tmp_path}/", "-timeout=30", "-rss_limit_mb=4096"],
        capture_output=True, text=True, env=environment, timeout=seconds + 120, check=False,
    )
    crashes = sorted(path.name for path in tmp_path.iterdir() if path.is_file())
    assert completed.returncode == 0 and not crashes, (
        crashes, completed.stderr[-4000:]
    )


def test_atheris_sampled_session(tmp_path: Path) -> None:
    _fuzz(tmp_path, runs=3000, seconds=60)


@pytest.mark.slow
def test_atheris_long_session(tmp_path: Path) -> None:
    _fuzz(tmp_path, runs=200_000, seconds=1800)
