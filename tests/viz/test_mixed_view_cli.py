"""``geomexact view`` on a mixed-cell mesh: the command dispatches on the loaded value's
type, so a reader returning a ``MixedMesh3`` gets the mixed page and picture (the reader is
stood in for by an in-memory value until the mixed file formats land)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from helpers.mixed_view_cases import every_kind_mesh
from matplotlib.image import imread

from geomexact.cli import main, view
from geomexact.cli.loading import Loaded
from geomexact.mesh3d.mixed.snapshot import MixedMesh3


@pytest.fixture(scope="module")
def mesh() -> MixedMesh3:
    return every_kind_mesh()


@pytest.fixture
def source(monkeypatch: pytest.MonkeyPatch, mesh: MixedMesh3, tmp_path: Path) -> Path:
    """A file name whose loading gives ``mesh``."""
    path = tmp_path / "every-kind.vtu"
    path.write_text("stands for a mixed mesh", encoding="utf-8")

    def load(name: str, format: str | None, verbose: bool) -> Loaded:
        assert name == str(path)
        return Loaded(name, "vtu", mesh, ())

    monkeypatch.setattr(view, "load", load)
    return path


def _run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _payload(page: Path) -> dict[str, Any]:
    match = re.search(r'id="geomexact-data">(.*?)</script>', page.read_text("utf-8"), re.S)
    assert match
    data: dict[str, Any] = json.loads(match.group(1))
    return data


def test_view_writes_the_mixed_page(capsys: pytest.CaptureFixture[str], source: Path,
                                    tmp_path: Path) -> None:
    page = tmp_path / "mixed.html"
    code, out, err = _run(capsys, "view", source, "-o", page, "--clip", "z", "1/2", "--json")
    assert code == 0, err
    assert json.loads(out)["clip"] == {"axis": "z", "position": "1/2"}
    data = _payload(page)
    assert data["kind_counts"]["hexahedra"] == 11 and data["options"]["colour"] == "kind"
    assert data["options"]["clip"]["position"] == "0.5"
    plain = tmp_path / "plain.html"
    assert _run(capsys, "view", source, "-o", plain, "--color-by", "area")[0] == 0
    assert _payload(plain)["options"]["colour"] == "plain"


def test_view_draws_the_mixed_picture(capsys: pytest.CaptureFixture[str], source: Path,
                                      tmp_path: Path) -> None:
    whole, clipped = tmp_path / "whole.png", tmp_path / "clipped.png"
    assert _run(capsys, "view", source, "-o", whole)[0] == 0
    assert _run(capsys, "view", source, "-o", clipped, "--clip", "x", "1/2")[0] == 0
    assert imread(str(whole)).shape[:2] == (600, 800)
    assert (imread(str(whole)) != imread(str(clipped))).any()
    code, _, err = _run(capsys, "view", source, "-o", tmp_path / "bad.png",
                        "--color-by", "min-angle")
    assert code == 2 and "cell kind" in err
