"""No command replaces one of its inputs, with or without --force (issue 27, item 2):
`triangulate superior.poly -o superior.ele --force` replaced superior.poly (a companion of
the .ele) with its own and lost its 6 holes."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from geomexact import io
from geomexact.cli import main

SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"
SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"


@pytest.fixture()
def folder(tmp_path: Path) -> Path:
    """sq.off, its Triangle set sq.ele (node/ele/neigh), a trace of a refinement of it, a
    hard link and a symbolic link to sq.off, and Lake Superior's PSLG."""
    (tmp_path / "sq.off").write_text(SQUARE_OFF)
    assert main(["convert", str(tmp_path / "sq.off"), str(tmp_path / "tri.ele")]) == 0
    assert main(["refine", str(tmp_path / "sq.off"), "--max-area", "0.1",
                 "-o", str(tmp_path / "fine.off"), "--trace", str(tmp_path / "run.trace")]) == 0
    os.link(tmp_path / "sq.off", tmp_path / "hard.off")
    (tmp_path / "soft.off").symlink_to(tmp_path / "sq.off")
    (tmp_path / "superior.poly").write_bytes(SUPERIOR.read_bytes())
    return tmp_path


CASES = {
    "triangulate-companion": ["triangulate", "superior.poly", "-o", "superior.ele"],
    "convert-itself": ["convert", "sq.off", "sq.off"],
    "convert-hard-link": ["convert", "sq.off", "hard.off"],
    "convert-symbolic-link": ["convert", "soft.off", "sq.off"],
    "convert-set-member": ["convert", "tri.ele", "tri.node", "--to", "off"],
    "convert-set": ["convert", "tri.ele", "tri.ele"],
    "refine-output": ["refine", "sq.off", "--max-area", "0.2", "-o", "sq.off"],
    "refine-trace": ["refine", "sq.off", "--max-area", "0.2", "-o", "new.off",
                     "--trace", "sq.off"],
    "polylla-output": ["polylla", "sq.off", "-o", "sq.off"],
    "replay-output-is-start": ["replay", "sq.off", "run.trace", "-o", "sq.off"],
    "replay-output-is-trace": ["replay", "sq.off", "run.trace", "-o", "run.trace",
                               "--to", "off"],
}


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {name: (folder / name).read_bytes() for name in sorted(os.listdir(folder))
            if (folder / name).is_file()}


@pytest.mark.parametrize("force", [False, True], ids=["plain", "force"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_no_command_replaces_its_input(capsys: pytest.CaptureFixture[str], folder: Path,
                                       case: str, force: bool) -> None:
    """Exit 2, one line naming the input; every file of the folder as it was, no new one."""
    before = _snapshot(folder)
    argv = [str(folder / word) if (folder / word).exists() or word.endswith(
        (".ele", ".off", ".node", ".trace")) else word for word in CASES[case]]
    capsys.readouterr()
    code = main([*argv, *(["--force"] if force else [])])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    if force:
        assert "is an input of this command" in err
    assert _snapshot(folder) == before
    assert not [name for name in os.listdir(folder) if name.startswith(".geomexact")]


def test_superior_keeps_its_holes(capsys: pytest.CaptureFixture[str], folder: Path) -> None:
    """The issue's own case, then the same command with another output name works."""
    code = main(["triangulate", str(folder / "superior.poly"), "-o",
                 str(folder / "superior.ele"), "--force"])
    assert code == 2
    assert len(io.read(folder / "superior.poly").holes) == 6
    assert main(["triangulate", str(folder / "superior.poly"), "-o",
                 str(folder / "superior.1.ele")]) == 0


@pytest.mark.parametrize("argv", [["triangulate", "missing.node", "-o", "sq.ele"],
                                  ["convert", "missing.off", "sq.off"]],
                         ids=["triangulate", "convert"])
def test_an_existing_output_is_refused_before_the_input_is_read(
        capsys: pytest.CaptureFixture[str], tmp_path: Path, argv: list[str]) -> None:
    """The refusal comes first: the input (here missing) is not even opened (it came
    after 44 s and 2.8 GB of work for 10^6 points)."""
    (tmp_path / "sq.off").write_text(SQUARE_OFF)
    (tmp_path / "sq.node").write_text("0 2 0 0\n")
    code = main([str(tmp_path / word) if "." in word else word for word in argv])
    err = capsys.readouterr().err
    assert code == 2 and "refusing to overwrite" in err and "missing" not in err
