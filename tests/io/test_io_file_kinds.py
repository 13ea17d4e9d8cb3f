"""What the readers open (issue 27, items 7 and 9): only regular files, refused before
they are opened otherwise (a FIFO, ``/dev/zero``, a socket, a directory), and lines of at
most ``LINE_LIMIT`` bytes, read in time and memory linear in the file
(``specs/formats/registry.md``, "Files and lines")."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.io_cases import write

from geomexact import io
from geomexact.errors import FormatError
from geomexact.io import bulk
from geomexact.io.files import LINE_LIMIT, check_regular, read_lines, read_text
from geomexact.io.trace_file import read_trace

HANG_GUARD = 60
"""Seconds after which a command that should refuse at once counts as hung."""

needs_fifo = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
needs_dev_zero = pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")


def cli(*arguments: str) -> subprocess.CompletedProcess[str]:
    """``geomexact`` run in a child process, bounded by :data:`HANG_GUARD`."""
    return subprocess.run([sys.executable, "-m", "geomexact", *arguments],
                          capture_output=True, text=True, timeout=HANG_GUARD, check=False)


def refused(path: Path, format: str | None = None) -> FormatError:
    with pytest.raises(FormatError) as caught:
        io.read(path, format=format)
    return caught.value


# -- non-regular files ------------------------------------------------------------------
@needs_fifo
@pytest.mark.parametrize("name", ["fifo.off", "fifo.node", "fifo.poly", "fifo.pslg",
                                  "fifo.txt", "fifo.mellado", "fifo.vtu", "fifo.vtk"])
def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path: Path, name: str) -> None:
    """Opening a FIFO for reading blocks until a writer comes: every reader refuses it
    by its kind first (the call would hang otherwise)."""
    path = tmp_path / name
    os.mkfifo(path)
    error = refused(path)
    assert error.path == str(path) and error.line is None
    assert error.problem.startswith("not a regular file: a FIFO")


@needs_fifo
def test_a_fifo_beside_an_ele_is_refused(tmp_path: Path) -> None:
    """The ``.node`` a Triangle or TetGen ``.ele`` names is checked as the main file."""
    write(tmp_path, "m.ele", "1 3 0\n0 0 1 2\n")
    os.mkfifo(tmp_path / "m.node")
    error = refused(tmp_path / "m.ele")
    assert error.path == str(tmp_path / "m.node") and "a FIFO" in error.problem


@needs_fifo
@pytest.mark.parametrize(("mesh", "companion"), [("2d", "m.neigh"), ("3d", "m.face")])
def test_a_fifo_companion_is_refused(tmp_path: Path, mesh: str, companion: str) -> None:
    """A ``.neigh`` or ``.face`` beside the ``.ele`` that is a FIFO: refused naming it
    (the file-set check reads the last line of each companion: it must not open it)."""
    if mesh == "2d":
        value = io.read(write(tmp_path, "t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
    else:
        from helpers.mesh3d_cases import cube_grid

        value = cube_grid(1, 1, 1)
    io.write(tmp_path / "m.ele", value)
    (tmp_path / companion).unlink()
    os.mkfifo(tmp_path / companion)
    error = refused(tmp_path / "m.ele")
    assert error.path == str(tmp_path / companion) and "a FIFO" in error.problem


@needs_fifo
def test_a_fifo_trace_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "t.jsonl"
    os.mkfifo(path)
    with pytest.raises(FormatError, match="not a regular file: a FIFO"):
        read_trace(path)


@needs_dev_zero
@pytest.mark.parametrize("format", ["off", "node", "pslg", "trilist", "meshio"])
def test_dev_zero_is_refused_as_a_device(format: str) -> None:
    """``/dev/zero`` never ends: refused as a character device, not read."""
    error = refused(Path("/dev/zero"), format)
    assert error.problem.startswith("not a regular file: a character device")


@pytest.mark.skipif(not hasattr(socket, "AF_UNIX"), reason="no Unix sockets")
def test_a_socket_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "s.off"
    with socket.socket(socket.AF_UNIX) as server:
        try:
            server.bind(str(path))
        except OSError:  # pragma: no cover - a path too long for a socket address
            pytest.skip("cannot bind a socket here")
        assert "a socket" in refused(path).problem


def test_a_directory_and_a_missing_file_keep_their_messages(tmp_path: Path) -> None:
    (tmp_path / "d.off").mkdir()
    assert refused(tmp_path / "d.off").problem == "is a directory, not a file"
    assert refused(tmp_path / "missing.off").problem == "no such file"
    assert refused(tmp_path / "missing.vtu").problem == "no such file"


def test_a_link_to_a_regular_file_is_read(tmp_path: Path) -> None:
    target = write(tmp_path, "t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    (tmp_path / "l.off").symlink_to(target)
    check_regular(tmp_path / "l.off")
    assert io.read(tmp_path / "l.off") == io.read(target)


@needs_fifo
def test_the_file_functions_refuse_a_fifo(tmp_path: Path) -> None:
    path = tmp_path / "f.txt"
    os.mkfifo(path)
    for call in (read_text, lambda p: list(read_lines(p)), check_regular):
        with pytest.raises(FormatError, match="a FIFO"):
            call(path)
    with pytest.raises(bulk.NotPlain):
        bulk.PlainLines(path)


@needs_fifo
def test_info_on_a_fifo_exits_2_at_once_with_one_line(tmp_path: Path) -> None:
    path = tmp_path / "fifo.off"
    os.mkfifo(path)
    done = cli("info", str(path))
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"geomexact: error: {path}: not a regular file: a FIFO (named pipe); only regular "
        "files are read"]


@needs_dev_zero
def test_info_on_dev_zero_exits_2_at_once_with_one_line(tmp_path: Path) -> None:
    link = tmp_path / "zero.off"
    link.symlink_to("/dev/zero")
    for arguments in (("info", str(link)), ("info", "--format", "off", "/dev/zero")):
        done = cli(*arguments)
        assert done.returncode == 2, done.stderr
        assert len(done.stderr.splitlines()) == 1
        assert "not a regular file: a character device" in done.stderr


# -- long lines -------------------------------------------------------------------------
def test_a_line_over_the_limit_is_refused_at_its_line(tmp_path: Path) -> None:
    """All of a file on one line (here 1 byte over the limit): refused, naming the line,
    after reading no more than the limit."""
    path = tmp_path / "l.off"
    with open(path, "wb") as handle:
        handle.write(b"OFF\n")
        handle.write(b"1 " * (LINE_LIMIT // 2) + b"1")
    error = refused(path)
    assert error.line == 2 and "longer than 16,777,216 bytes" in error.problem


def test_a_line_at_the_limit_is_read(tmp_path: Path) -> None:
    """A line of exactly the limit (its newline not counted) is data, read in one pass."""
    text = b"v 0 0\nv 1 0\nv 0 1 " + b"#" * (LINE_LIMIT - len(b"v 0 1 ")) + b"\nt 0 1 2\n"
    path = tmp_path / "p.pslg"
    path.write_bytes(text)
    assert [number for number, _ in read_lines(path)] == [1, 2, 3, 4]
    assert io.read(path).triangle_count == 1


def test_a_long_line_in_a_gzip_trace_is_refused(tmp_path: Path) -> None:
    import gzip

    path = tmp_path / "t.jsonl.gz"
    with gzip.open(path, "wb") as handle:
        handle.write(b" " * (LINE_LIMIT + 10))
    with pytest.raises(FormatError) as caught:
        read_trace(path)
    assert caught.value.line == 1 and "longer than" in caught.value.problem


@pytest.mark.parametrize("size", [3 * bulk.BLOCK, bulk.PLAIN_LINE_LIMIT + 2])
def test_the_fast_path_leaves_a_long_line_to_the_line_reader(
    tmp_path: Path, size: int
) -> None:
    """A long line is read by joining its blocks once (it was quadratic: 16 MB took 3 s,
    64 MB 37 s); beyond PLAIN_LINE_LIMIT the fast path gives up, and the line reader
    gives the error it always gave."""
    path = tmp_path / "l.off"
    path.write_bytes(b"OFF\n" + b"1 " * (size // 2))
    with bulk.PlainLines(path) as lines:
        assert lines.next_line()[1] == 1
        if size > bulk.PLAIN_LINE_LIMIT:
            with pytest.raises(bulk.NotPlain):
                lines.next_line()
        else:
            tokens, number = lines.next_line()
            assert number == 2 and len(tokens) == size // 2
    error = refused(path)
    assert error.line == 2 and "expected the counts" in error.problem
