"""``geomexact info`` and ``check`` on a part's surface (a 3D OBJ, STL, PLY or OFF), which
the mesh readers refuse as not planar: the surface is read exactly and reported (closed,
whether it bounds a domain, its problems, its exact enclosed volume), or checked with the
exact checks a domain's surface must pass (exit 1 listing the problems)."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from helpers.command import run
from helpers.paths import SHARED_DATA
from helpers.surface_cases import cube, torus, write_ascii_stl, write_obj

from geomexact.mesh3d.surface.value import triangle_surface


def test_info_reports_a_closed_surface(capsys: pytest.CaptureFixture[str],
                                       tmp_path: Path) -> None:
    path = write_obj(tmp_path / "box.obj", cube(Fraction(0), Fraction(2)))
    code, text, _ = run(capsys, "info", path, "--json")
    report = json.loads(text)
    assert code == 0 and report["kind"] == "triangle_surface"
    assert report["closed"] and report["bounds_a_domain"] and report["problems"] == {}
    assert report["enclosed_volume"] == "8" and report["triangles"] == 12
    code, text, _ = run(capsys, "info", write_ascii_stl(tmp_path / "t.stl", torus()))
    assert code == 0 and "triangle surface" in text
    assert any(line.split()[:4] == ["bounds", "a", "domain", "yes"] for line in text.splitlines())


def test_check_lists_the_problems_of_an_open_surface(capsys: pytest.CaptureFixture[str],
                                                     tmp_path: Path) -> None:
    whole = cube(Fraction(0), Fraction(2))
    opened = triangle_surface(whole.points, whole.triangles[:-2], "open")
    path = write_obj(tmp_path / "open.obj", opened)
    code, text, _ = run(capsys, "check", path)
    assert code == 1 and "not the surface of a domain" in text and "boundary" in text
    code, text, _ = run(capsys, "check", path, "--json")
    report = json.loads(text)
    assert code == 1 and not report["valid"] and report["kind"] == "triangle_surface"
    code, text, _ = run(capsys, "check", write_obj(tmp_path / "box.obj", whole))
    assert code == 0 and "closed, manifold, oriented outward" in text


@pytest.mark.skipif(not (SHARED_DATA / "surfaces").is_dir(), reason="no ../shared")
def test_real_surfaces(capsys: pytest.CaptureFixture[str]) -> None:
    code, text, _ = run(capsys, "info", SHARED_DATA / "surfaces" / "spot.obj", "--json")
    assert code == 0 and json.loads(text)["bounds_a_domain"] is True
    code, text, _ = run(capsys, "info", SHARED_DATA / "surfaces" / "stanford-bunny.obj",
                        "--json")
    assert code == 0 and json.loads(text)["problems"] == {"boundary-edge": 223}
