"""The kill suite (issue 27, item 1): a command killed at a random moment (SIGKILL,
Ctrl-C, SIGTERM) while it rewrites its outputs with --force leaves them all old or all
new, never a mix; Ctrl-C and SIGTERM leave no temporary behind, and what SIGKILL leaves
goes with the next write in that folder; a full disk (a 1 MB tmpfs) keeps the old set
and names the file.  Before: 12 of 39 trials left new and old files mixed, and 11 of 31
kills left .tmp files.

A fixed, seeded sample runs in CI; ``--runslow`` runs a few dozen kills per command."""

from __future__ import annotations

import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from geomexact.io.files import STAGING_PREFIX

SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"

# (the first run's options, the rewrite's options), each rewrite taking about a second
COMMANDS = {
    "refine": (["refine", "sq.off", "--max-area", "0.01", "-o", "out.ele", "--trace",
                "out.trace"],
               ["refine", "sq.off", "--max-area", "0.0002", "-o", "out.ele", "--trace",
                "out.trace"]),
    "octree-start": (["octree", "--level", "2", "-o", "o.ele", "--start", "st.ele",
                      "--trace", "st.trace"],
                     ["octree", "--level", "5", "--refine-sphere", "0.5", "0.5", "0.5",
                      "0.3", "-o", "o.ele", "--start", "st.ele", "--trace", "st.trace"]),
    "census": (["census", "--patterns", "1-50", "--workers", "1", "-o", "c.csv",
                "--no-parquet"],
               ["census", "--patterns", "1-3000", "--workers", "1", "-o", "c.csv",
                "--no-parquet"]),
    "convert": (["convert", "small.off", "out.ele"], ["convert", "big.off", "out.ele"]),
}
SIGNALS = (signal.SIGKILL, signal.SIGINT, signal.SIGTERM)


def _command(folder: Path, argv: list[str], *extra: str) -> subprocess.Popen[bytes]:
    def default_sigint() -> None:  # as a terminal's Ctrl-C finds it (not a background job)
        signal.signal(signal.SIGINT, signal.SIG_DFL)

    return subprocess.Popen([sys.executable, "-m", "geomexact", *argv, *extra], cwd=folder,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            preexec_fn=default_sigint)


def _files(folder: Path) -> dict[str, bytes]:
    """The outputs (every file but the inputs), by name."""
    return {name: (folder / name).read_bytes() for name in sorted(os.listdir(folder))
            if (folder / name).is_file() and name not in ("sq.off", "small.off", "big.off")}


def _staging(folder: Path) -> list[str]:
    return [name for name in os.listdir(folder) if name.startswith(STAGING_PREFIX)]


def _prepare(folder: Path) -> None:
    (folder / "sq.off").write_text(SQUARE_OFF)
    (folder / "small.off").write_text(SQUARE_OFF)
    rows = 160
    points = [f"{x / rows} {y / rows} 0" for y in range(rows + 1) for x in range(rows + 1)]
    faces = []
    for y in range(rows):
        for x in range(rows):
            a = y * (rows + 1) + x
            faces += [f"3 {a} {a + 1} {a + rows + 2}", f"3 {a} {a + rows + 2} {a + rows + 1}"]
    (folder / "big.off").write_text(f"OFF\n{len(points)} {len(faces)} 0\n"
                                    + "\n".join(points + faces) + "\n")


def _sets(folder: Path, name: str) -> tuple[dict[str, bytes], dict[str, bytes], float]:
    """The old and the new output sets of ``name`` (each written whole), and how long
    the rewrite takes."""
    first, second = COMMANDS[name]
    assert subprocess.run([sys.executable, "-m", "geomexact", *first], cwd=folder,
                          capture_output=True, timeout=300).returncode == 0
    old = _files(folder)
    started = time.monotonic()
    done = subprocess.run([sys.executable, "-m", "geomexact", *second, "--force"],
                          cwd=folder, capture_output=True, timeout=300)
    seconds = time.monotonic() - started
    assert done.returncode == 0, done.stderr
    new = _files(folder)
    assert old != new and set(old) <= set(new) | set(old)
    return old, new, seconds


def _restore(folder: Path, files: dict[str, bytes]) -> None:
    for name in _files(folder):
        (folder / name).unlink()
    for name, data in files.items():
        (folder / name).write_bytes(data)


def _kills(folder: Path, name: str, trials: int, seed: int) -> list[str]:
    """Kill the rewrite ``trials`` times at random moments; after each, the outputs are
    the old set or the new set.  Returns how each trial ended."""
    old, new, seconds = _sets(folder, name)
    chooser = random.Random(seed)
    outcomes = []
    for _ in range(trials):
        _restore(folder, old)
        stop = chooser.choice(SIGNALS)
        process = _command(folder, COMMANDS[name][1], "--force")
        time.sleep(chooser.uniform(0.05, seconds * 1.1))
        process.send_signal(stop)
        _, err = process.communicate(timeout=120)
        after = _files(folder)
        assert after in (old, new), (name, stop, sorted(after), err)
        outcomes.append(f"{stop.name}:{'new' if after == new else 'old'}")
        if stop != signal.SIGKILL or after == new:
            assert _staging(folder) == [], (name, stop)
    # what a SIGKILL left goes with the next write in the folder
    ended = subprocess.run([sys.executable, "-m", "geomexact", *COMMANDS[name][1], "--force"],
                           cwd=folder, capture_output=True, timeout=300)
    assert ended.returncode == 0 and _files(folder) == new and _staging(folder) == []
    return outcomes


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_a_killed_rewrite_leaves_all_old_or_all_new(tmp_path: Path, name: str) -> None:
    """Three kills per command (a fixed sample: seeded)."""
    _prepare(tmp_path)
    outcomes = _kills(tmp_path, name, trials=3, seed=27)
    assert len(outcomes) == 3


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_a_few_dozen_kills_leave_all_old_or_all_new(tmp_path: Path, name: str) -> None:
    """Twelve kills per command, at moments spread over the whole run."""
    _prepare(tmp_path)
    outcomes = _kills(tmp_path, name, trials=12, seed=2027)
    assert {outcome.split(":")[1] for outcome in outcomes} <= {"old", "new"}


@pytest.fixture()
def tiny_disk(tmp_path: Path) -> Path:
    """A 1 MB tmpfs (root and a kernel that lets us mount: else skipped)."""
    mount = tmp_path / "disk"
    mount.mkdir()
    if shutil.which("mount") is None or os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mount)],
                          capture_output=True)
    if made.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {made.stderr.decode().strip()}")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], capture_output=True)


def test_a_full_disk_keeps_the_old_set_and_names_the_file(tiny_disk: Path) -> None:
    """The issue's case: refine over an earlier result on a 1 MB disk exits 2 naming the
    output, and the earlier result still reads back as itself (it read as a valid,
    wrong mesh of 33,025 vertices and 1,024 triangles)."""
    (tiny_disk / "sq.off").write_text(SQUARE_OFF)
    first = subprocess.run([sys.executable, "-m", "geomexact", "refine", "sq.off",
                            "--max-area", "0.002", "-o", "out.ele"], cwd=tiny_disk,
                           capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    old = _files(tiny_disk)
    full = subprocess.run([sys.executable, "-m", "geomexact", "refine", "sq.off",
                           "--max-area", "0.00002", "-o", "out.ele", "--force"],
                          cwd=tiny_disk, capture_output=True, text=True, timeout=300)
    assert full.returncode == 2
    assert "No space left on device" in full.stderr and "out." in full.stderr
    assert STAGING_PREFIX not in full.stderr and "Traceback" not in full.stderr
    assert _files(tiny_disk) == old and _staging(tiny_disk) == []
    check = subprocess.run([sys.executable, "-m", "geomexact", "check", "out.ele"],
                           cwd=tiny_disk, capture_output=True, text=True, timeout=300)
    assert check.returncode == 0 and "valid" in check.stdout
