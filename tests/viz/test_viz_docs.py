"""The examples of docs/viewer.md run as written: every picture they name is produced,
non-empty, with its documented size (800 × 600), and every page they name is written."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from matplotlib.image import imread

from geomexact.cli import main

DOC = Path(__file__).resolve().parents[2] / "docs" / "viewer.md"
BLOCK = re.compile(r"```(\w*)\n(.*?)```", re.S)


def blocks() -> list[tuple[str, str]]:
    return [(language, body) for language, body in BLOCK.findall(DOC.read_text("utf-8"))
            if language in ("sh", "python")]


@pytest.fixture()
def inside(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_docs_have_picture_examples() -> None:
    """The page has shell and Python examples naming pictures."""
    kinds = {language for language, _ in blocks()}
    assert kinds == {"sh", "python"}
    assert len(re.findall(r"[\w-]+\.png", DOC.read_text("utf-8"))) >= 6


def test_every_example_produces_its_files(inside: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    """Run each block in order (shell lines through the CLI in-process); then every .png
    and .html the examples name exists; pictures are 800 × 600 with content."""
    namespace: dict[str, object] = {}
    named: set[str] = set()
    for language, body in blocks():
        named.update(re.findall(r"[\w-]+\.(?:png|html)", body))
        if language == "python":
            exec(compile(body, str(DOC), "exec"), namespace)
            continue
        for line in body.splitlines():
            if not line.strip():
                continue
            words = shlex.split(line)
            assert words[0] == "geomexact", line
            code = main(words[1:])
            assert code == 0, (line, capsys.readouterr().err)
    pictures = sorted(name for name in named if name.endswith(".png"))
    assert "superior-step.png" in pictures and "polygons.png" in pictures
    for name in sorted(named):
        path = inside / name
        assert path.is_file(), name
        assert path.stat().st_size > 5000, name
    for name in pictures:
        pixels = imread(inside / name)
        assert pixels.shape[:2] == (600, 800), name
        assert (pixels[..., :3] < 0.9).any(axis=-1).mean() > 0.002, f"{name} looks blank"
