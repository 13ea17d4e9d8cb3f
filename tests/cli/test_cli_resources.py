"""Nothing that eats the machine (issue 27, item 6): under an address-space limit of 2 GB
(``ulimit -v``), each runaway the issue found ends with exit 2 (refused before the work,
or out of memory) or 3 (stopped at the budget with a valid partial result) and one line
on stderr, never a traceback or a signal, and nothing half-written."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from geomexact import io, validate
from geomexact.cli import main

LIMIT = 2 << 30
SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"

pytestmark = pytest.mark.skipif(not Path("/proc/self/status").exists(),
                                reason="address-space limits and /proc: Linux")


def _limited(size: int) -> Callable[[], None]:
    def start() -> None:
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (size, size))

    return start


def _geomexact(folder: Path, *argv: str) -> subprocess.CompletedProcess[str]:
    """``python -m geomexact ARGV`` in ``folder`` under the 2 GB limit (bounded in time:
    a runaway must not hang the suite)."""
    return subprocess.run([sys.executable, "-m", "geomexact", *argv], cwd=folder,
                          capture_output=True, text=True, timeout=300,
                          preexec_fn=_limited(LIMIT))


def _one_line(result: subprocess.CompletedProcess[str], code: int) -> str:
    assert result.returncode == code, result.stderr
    assert "Traceback" not in result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    return lines[0]


@pytest.fixture()
def folder(tmp_path: Path) -> Path:
    (tmp_path / "sq.off").write_text(SQUARE_OFF)
    return tmp_path


def _nothing_written(folder: Path, *inputs: str) -> None:
    assert sorted(os.listdir(folder)) == sorted(inputs)


@pytest.mark.parametrize("criterion", [["--max-area", "1e-30"], ["--factor", "1e-30"],
                                       ["--max-edge", "1e-9"]],
                         ids=["max-area", "factor", "max-edge"])
def test_refine_runaways_are_refused_up_front(folder: Path, criterion: list[str]) -> None:
    """They showed a budget of 2 x 10^14 steps and died in a MemoryError traceback."""
    result = _geomexact(folder, "refine", "sq.off", *criterion, "-o", "out.off",
                        "--trace", "out.trace")
    line = _one_line(result, 2)
    assert "needs about" in line and "(ulimit -v)" in line  # the 2 GB limit binds
    _nothing_written(folder, "sq.off")


@pytest.mark.parametrize("options", [["--level", "16"], ["--grid", "100000", "100000", "100000"],
                                     ["--max-edge", "1e-9"]],
                         ids=["level-16", "grid-1e5", "max-edge"])
def test_octree_runaways_are_refused_up_front(folder: Path, options: list[str]) -> None:
    """They had no guard at all."""
    result = _geomexact(folder, "octree", *options, "-o", "out.ele")
    line = _one_line(result, 2)
    assert "an octree of" in line and "needs about" in line
    _nothing_written(folder, "sq.off")


def test_a_large_triangulation_is_refused_up_front(folder: Path) -> None:
    """10^7 points segfaulted under ulimit -v 3000000; a million is refused by the same
    estimate (reading and triangulating them needs more than the 2 GB left)."""
    with (folder / "many.node").open("w") as handle:
        count = 1_000_000
        handle.write(f"{count} 2 0 0\n")
        handle.writelines(f"{i} {i % 1000}.{i // 1000:06d} {i // 1000}\n" for i in range(count))
    result = _geomexact(folder, "triangulate", "many.node", "-o", "many.1.ele")
    line = _one_line(result, 2)
    assert "needs about" in line
    _nothing_written(folder, "sq.off", "many.node")


def test_a_file_too_large_to_read_is_refused_before_reading(folder: Path) -> None:
    """info on a large OFF under the cap was a MemoryError traceback with exit 1."""
    row = "0.123456789012345678 0.987654321098765432 0\n"
    with (folder / "big.off").open("w") as handle:
        count = 1_600_000  # 70 MB: its reading is estimated beyond what 2 GB leaves
        handle.write(f"OFF\n{count} 0 0\n")
        for _ in range(count // 10_000):
            handle.write(row * 10_000)
    line = _one_line(_geomexact(folder, "info", "big.off"), 2)
    assert line.startswith("geomexact: error: reading big.off") and "needs about" in line


def test_an_allocation_beyond_the_budget_is_one_line(folder: Path) -> None:
    """A run the estimates let through but whose process reaches the budget: exit 2, one
    line, nothing written (the address-space cap is the command's budget)."""
    result = _geomexact(folder, "refine", "sq.off", "--max-area", "1e-4", "-o", "out.off",
                        "--max-memory", "4M")
    line = _one_line(result, 2)
    assert "out of memory" in line or "needs about" in line
    _nothing_written(folder, "sq.off")


def test_the_memory_budget_stops_a_refinement_with_its_partial_result(
        capsys: pytest.CaptureFixture[str], folder: Path) -> None:
    """A criterion with no size estimate (a minimum angle) on 6,000 triangles: the budget
    becomes a step limit; exit 3, the partial result written and valid."""
    points = [(f"{(i * 7919) % 3001 / 3001}", f"{(i * 104729) % 2999 / 2999}")
              for i in range(3000)]
    (folder / "p.node").write_text(f"{len(points)} 2 0 0\n" + "".join(
        f"{i} {x} {y}\n" for i, (x, y) in enumerate(points)))
    assert main(["triangulate", str(folder / "p.node"), "-o", str(folder / "p.off")]) == 0
    capsys.readouterr()
    code = main(["refine", str(folder / "p.off"), "--min-angle", "30", "--method", "centroid",
                 "-o", str(folder / "r.off"), "--max-memory", "9M", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 3, err
    assert "refine stopped at its memory budget" in err
    result = io.read(folder / "r.off")
    assert validate(result) == []
