"""Output sets (issue 27, item 1): the files of one write, or of one command, appear all
new or all old; a set's members carry one stamp and a reader refuses members of two sets;
nothing is left behind in the folder."""

from __future__ import annotations

import errno
import os
import subprocess
import sys
from pathlib import Path

import pytest

from geomexact import io, mesh_from_triangles
from geomexact.errors import FormatError, OverwriteError
from geomexact.io.files import STAGING_PREFIX, output_set, staged_path, write_text_atomic
from geomexact.io.registry import FILE_SET_MARK

SQUARE = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
SPLIT = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1), ("1/2", "1/2")],
                            [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)])


def _listing(folder: Path) -> list[str]:
    return sorted(os.listdir(folder))


def test_a_set_appears_only_when_its_block_ends(tmp_path: Path) -> None:
    """Inside the block the targets do not exist; the staged copies are readable through
    staged_path; at the end every file is in place and no staging folder is left."""
    with output_set() as files:
        write_text_atomic(tmp_path / "a.txt", "a\n")
        write_text_atomic(tmp_path / "b.txt", "b\n")
        assert not (tmp_path / "a.txt").exists() and not (tmp_path / "b.txt").exists()
        assert staged_path(tmp_path / "a.txt").read_text() == "a\n"
        assert files.targets == (tmp_path / "a.txt", tmp_path / "b.txt")
    assert (tmp_path / "a.txt").read_text() == "a\n" and (tmp_path / "b.txt").read_text() == "b\n"
    assert _listing(tmp_path) == ["a.txt", "b.txt"]


def test_a_failed_block_leaves_every_old_file(tmp_path: Path) -> None:
    """An exception (Ctrl-C included) in the block: no target changes, nothing is left."""
    (tmp_path / "a.txt").write_text("old a\n")
    with pytest.raises(KeyboardInterrupt), output_set():
        write_text_atomic(tmp_path / "a.txt", "new a\n", overwrite=True)
        write_text_atomic(tmp_path / "b.txt", "new b\n")
        raise KeyboardInterrupt
    assert (tmp_path / "a.txt").read_text() == "old a\n"
    assert _listing(tmp_path) == ["a.txt"]


def test_a_refusal_late_in_the_set_writes_nothing(tmp_path: Path) -> None:
    """The third file may not be replaced: the first two are not written either."""
    (tmp_path / "c.txt").write_text("keep\n")
    with pytest.raises(OverwriteError), output_set():
        write_text_atomic(tmp_path / "a.txt", "a\n")
        write_text_atomic(tmp_path / "b.txt", "b\n")
        write_text_atomic(tmp_path / "c.txt", "c\n")
    assert _listing(tmp_path) == ["c.txt"]
    assert (tmp_path / "c.txt").read_text() == "keep\n"


def test_a_target_that_appears_meanwhile_is_not_replaced(tmp_path: Path) -> None:
    """Without overwrite, a file created by someone else before the set ends is kept, and
    no file of the set is moved into place."""
    with pytest.raises(OverwriteError), output_set():
        write_text_atomic(tmp_path / "a.txt", "a\n")
        write_text_atomic(tmp_path / "b.txt", "b\n")
        (tmp_path / "b.txt").write_text("theirs\n")
    assert (tmp_path / "b.txt").read_text() == "theirs\n"
    assert _listing(tmp_path) == ["b.txt"]


def test_a_write_error_names_the_target_not_the_staging_folder(tmp_path: Path) -> None:
    """A folder that cannot be written: the OSError names the output file."""
    if os.geteuid() == 0:
        target = Path("/proc/geomexact-cannot-write.txt")  # root may write anywhere else
    else:
        folder = tmp_path / "locked"
        folder.mkdir()
        folder.chmod(0o500)
        target = folder / "out.txt"
    with pytest.raises(OSError) as caught:
        write_text_atomic(target, "x\n")
    assert caught.value.filename == str(target)
    assert STAGING_PREFIX not in str(caught.value)


def test_abandoned_staging_of_a_killed_process_is_removed(tmp_path: Path) -> None:
    """A staging folder whose process no longer runs (kill -9) goes with the next write
    in that folder; one of a running process stays."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    abandoned = tmp_path / f"{STAGING_PREFIX}{dead.stdout.strip()}-abc"
    abandoned.mkdir()
    (abandoned / "x.node").write_text("half")
    alive = tmp_path / f"{STAGING_PREFIX}{os.getppid()}-def"
    alive.mkdir()
    write_text_atomic(tmp_path / "new.txt", "n\n")
    assert not abandoned.exists() and alive.exists()


def test_a_triangle_set_carries_one_stamp_and_mixed_members_are_refused(
        tmp_path: Path) -> None:
    """x.node of one write beside x.ele of another (a write interrupted between its
    renames): reading refuses it, naming both files; each write alone reads back."""
    io.write(tmp_path / "a.ele", SQUARE)
    io.write(tmp_path / "b.ele", SPLIT)
    for stem in ("a", "b"):
        lines = {(tmp_path / f"{stem}{suffix}").read_text().splitlines()[-1]
                 for suffix in (".node", ".ele", ".neigh")}
        assert len(lines) == 1 and next(iter(lines)).startswith(FILE_SET_MARK)
    (tmp_path / "a.node").write_bytes((tmp_path / "b.node").read_bytes())
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "a.ele")
    message = str(caught.value)
    assert "a.node and a.ele come from different writes" in message
    assert io.read(tmp_path / "b.ele") == SPLIT


def test_the_same_mesh_writes_the_same_bytes_under_any_name(tmp_path: Path) -> None:
    """The stamp is made from the contents: two writes of one mesh are byte-identical."""
    io.write(tmp_path / "a.ele", SQUARE)
    io.write(tmp_path / "b.ele", SQUARE)
    for suffix in (".node", ".ele", ".neigh"):
        assert (tmp_path / f"a{suffix}").read_bytes() == (tmp_path / f"b{suffix}").read_bytes()


def test_a_stale_member_is_removed_with_the_new_set(tmp_path: Path) -> None:
    """Rewriting a mesh with segments by one without: the old x.poly goes, so it is not
    read with the new files."""
    with_segments = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)],
                                        [(0, 1, 2), (0, 2, 3)], [(0, 1, 5), (1, 2, 6)])
    io.write(tmp_path / "x.ele", with_segments)
    assert (tmp_path / "x.poly").exists()
    with pytest.raises(OverwriteError):
        io.write(tmp_path / "x.ele", SQUARE)
    io.write(tmp_path / "x.ele", SQUARE, overwrite=True)
    assert not (tmp_path / "x.poly").exists()
    assert io.read(tmp_path / "x.ele") == SQUARE


def test_a_tetgen_set_is_stamped_and_checked(tmp_path: Path) -> None:
    """The same for TetGen's .node/.ele/.face."""
    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    one = partition_cuboid(0).mesh
    two = partition_cuboid(262143).mesh
    io.write(tmp_path / "a.ele", one)
    io.write(tmp_path / "b.ele", two)
    (tmp_path / "a.face").write_bytes((tmp_path / "b.face").read_bytes())
    with pytest.raises(FormatError, match="come from different writes"):
        io.read(tmp_path / "a.ele")


def test_a_full_disk_names_the_file_and_keeps_the_old_set(tmp_path: Path) -> None:
    """ENOSPC while staging: the error names the output, the old files are untouched."""
    io.write(tmp_path / "x.ele", SQUARE)
    before = {name: (tmp_path / name).read_bytes() for name in _listing(tmp_path)}

    def full(*_: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    chunks = iter([b"1 2 3\n"])
    with pytest.raises(OSError) as caught, output_set() as files:
        files.stage(tmp_path / "x.ele", chunks, overwrite=True)
        files.stage(tmp_path / "x.node", map(full, [0]), overwrite=True)  # type: ignore[arg-type]
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(tmp_path / "x.node")
    assert {name: (tmp_path / name).read_bytes() for name in _listing(tmp_path)} == before


def test_ctrl_c_during_the_renames_waits_for_them(tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """A Ctrl-C that arrives between two renames of a commit acts once they are all
    done: the set is all new, and the KeyboardInterrupt comes after."""
    import signal

    from geomexact.io import files as module

    moved: list[Path] = []
    real_move = module._link_or_move

    def move_then_interrupt(staged: Path, target: Path) -> None:
        real_move(staged, target)
        moved.append(target)
        if len(moved) == 1:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(module, "_link_or_move", move_then_interrupt)
    with pytest.raises(KeyboardInterrupt), output_set():
        for name in ("a.txt", "b.txt", "c.txt"):
            write_text_atomic(tmp_path / name, f"{name}\n")
    assert len(moved) == 3
    assert _listing(tmp_path) == ["a.txt", "b.txt", "c.txt"]
