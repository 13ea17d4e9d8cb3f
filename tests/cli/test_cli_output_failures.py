"""Outputs that cannot be delivered (issue 27, item 9): a closed stdout (``>&-``) is one
line on stderr and exit 141, never a traceback; a folder that cannot be written, or a
target that is a directory, is an error naming the output, never the staging folder."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from geomexact.cli import EXIT_BROKEN_PIPE, main
from geomexact.io.files import STAGING_PREFIX

SQUARE_OFF = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"
CLOSED = ("geomexact: error: standard output is closed (>&-): the command cannot print its "
          "report; nothing was written (send it to /dev/null to discard it)\n")


def _shell(folder: Path, script: str, *argv: str) -> subprocess.CompletedProcess[str]:
    """Run ``script`` in sh with ``$0`` the Python of the tests and ``$1``… ``argv``."""
    return subprocess.run(["sh", "-c", script, sys.executable, *argv], cwd=folder,
                          capture_output=True, text=True, check=False, timeout=120)


@pytest.fixture
def square(tmp_path: Path) -> Path:
    path = tmp_path / "sq.off"
    path.write_text(SQUARE_OFF)
    return path


@pytest.mark.parametrize("argv", [["info", "sq.off"], ["info", "sq.off", "--json"],
                                  ["convert", "sq.off", "out.off"]])
def test_closed_stdout_is_one_line_and_exit_141(square: Path, argv: list[str]) -> None:
    done = _shell(square.parent, f'"$0" -m geomexact {" ".join(argv)} >&-')
    assert (done.returncode, done.stdout, done.stderr) == (EXIT_BROKEN_PIPE, "", CLOSED)
    assert sorted(os.listdir(square.parent)) == ["sq.off"]  # convert wrote nothing


def test_closed_stdout_and_stderr_exit_141_silently(square: Path) -> None:
    done = _shell(square.parent, '"$0" -m geomexact info sq.off >&- 2>&-; echo "$?" >&2')
    assert (done.stdout, done.stderr) == ("", f"{EXIT_BROKEN_PIPE}\n")


def test_closed_stderr_alone_still_prints_the_report(square: Path) -> None:
    done = _shell(square.parent, '"$0" -m geomexact info sq.off 2>&-')
    assert done.returncode == 0 and done.stdout.startswith("sq.off (off, polygon mesh)")


def test_read_only_folder_names_the_output(square: Path, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str],
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "RO"
    folder.mkdir()
    monkeypatch.chdir(tmp_path)
    if os.geteuid() != 0:
        folder.chmod(0o555)
        try:
            code = main(["convert", "sq.off", "RO/out.off"])
        finally:
            folder.chmod(0o755)
        captured = capsys.readouterr()
        assert (code, captured.err) == (2, "geomexact: error: RO/out.off: Permission denied\n")
    else:  # root writes through chmod: a read-only bind mount in a mount namespace
        if shutil.which("unshare") is None:
            pytest.skip("root, and no unshare for a read-only mount")
        done = subprocess.run(
            ["unshare", "--mount", "sh", "-c", "mount --bind RO RO && mount -o remount,ro,bind "
             'RO || exit 99; exec "$0" -m geomexact convert sq.off RO/out.off', sys.executable],
            cwd=tmp_path, capture_output=True, text=True, check=False, timeout=120)
        if done.returncode == 99 or done.stderr.startswith("unshare:"):
            pytest.skip("root, and no read-only mount possible here")
        assert (done.returncode, done.stderr) == (
            2, "geomexact: error: RO/out.off: Read-only file system\n")
    assert os.listdir(folder) == []


def test_a_target_that_is_a_directory_is_named(square: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "x"
    target.mkdir()
    assert main(["convert", str(square), str(target), "--to", "off", "--force"]) == 2
    err = capsys.readouterr().err
    assert err == f"geomexact: error: {target}: Is a directory\n"
    assert STAGING_PREFIX not in err and os.listdir(target) == []
