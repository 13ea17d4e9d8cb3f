"""docs/meshing-a-part.md: its Python block runs and prints what its comment says; its
pictures exist, are small and linked from the index; the numbers of its captions."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest
from helpers.paths import SHARED_DATA

DOCS = Path(__file__).resolve().parents[2] / "docs"
GUIDE = DOCS / "meshing-a-part.md"
SHARED = SHARED_DATA


def test_pictures_exist_are_small_and_linked() -> None:
    text = GUIDE.read_text(encoding="utf-8")
    pictures = re.findall(r"!\[[^\]]*\]\((images/[^)]+\.png)\)", text)
    assert pictures == ["images/part-fandisk.png", "images/part-spot.png"]
    for name in pictures:
        path = DOCS / name
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert path.stat().st_size < 150 * 1024, name
    assert "(meshing-a-part.md)" in (DOCS / "index.md").read_text(encoding="utf-8")


@pytest.mark.skipif(not SHARED.is_dir(), reason="../shared/data is absent")
def test_the_python_block_prints_what_it_says(monkeypatch: pytest.MonkeyPatch) -> None:
    (block,) = re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), re.S)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(block.replace("../shared/data", str(SHARED)), {})
    count, volume = out.getvalue().split()
    assert count == "2077" and volume.startswith("0.718")
