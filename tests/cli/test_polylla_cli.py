"""``geomexact polylla``: JSON keys, written polygon meshes, --convex / --no-opt,
--check, --picture, PSLG input, and the exit codes of bad input."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from helpers.polygon_checks import is_convex

from geomexact import io
from geomexact.cli import main
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh

# the pentagon of the convex module's doctest: one Polylla polygon, reflex at vertex 0
PENTAGON_OFF = """OFF
5 3 0
1 1 0
0 1 0
0 0 0
4 1 0
3 2 0
3 0 1 2
3 0 2 3
3 0 3 4
"""
SQUARE_POLY = """4 2 0 0
0 0 0
1 4 0
2 4 4
3 0 4
4 1
0 0 1 1
1 1 2 1
2 2 3 1
3 3 0 1
0
"""
KEYS = {"input", "triangulated", "vertices", "triangles", "regions", "barrier_tips",
        "repair_edges", "polygons", "nonconvex", "convex_decomposition", "criterion_one",
        "inserted_edges", "polygons_after", "nonconvex_after", "seconds", "valid", "stats",
        "written", "violations"}


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, Any]:
    code, out, err = run(capsys, *argv, "--json")
    assert out, err
    return code, json.loads(out)


@pytest.fixture
def pentagon(tmp_path: Path) -> Path:
    path = tmp_path / "pentagon.off"
    path.write_text(PENTAGON_OFF)
    return path


def test_polylla_json_report(capsys: pytest.CaptureFixture[str], pentagon: Path) -> None:
    code, report = run_json(capsys, "polylla", pentagon)
    assert code == 0
    assert set(report) == KEYS
    assert report["polygons"] == 1 and report["nonconvex"] == 1 and report["regions"] == 1
    assert report["inserted_edges"] is None and report["polygons_after"] is None
    assert report["nonconvex_after"] is None and report["valid"] is None
    assert report["convex_decomposition"] is False and report["triangulated"] is False
    assert report["stats"]["polygons"] == 1 and report["stats"]["total_area"] == "3.5"
    assert report["written"] == [] and report["violations"] == []
    assert isinstance(report["seconds"], float)


def test_convex_output_written_and_checked(
    capsys: pytest.CaptureFixture[str], pentagon: Path, tmp_path: Path
) -> None:
    out = tmp_path / "convex.off"
    code, report = run_json(capsys, "polylla", pentagon, "-o", out, "--convex", "--check",
                            "--exact")
    assert code == 0
    assert report["inserted_edges"] == 1 and report["polygons_after"] == 2
    assert report["nonconvex_after"] == 0 and report["criterion_one"] is True
    assert report["valid"] is True and report["written"] == [str(out)]
    written = io.read(out)
    assert isinstance(written, PolygonMesh)
    assert written.polygons == ((0, 1, 2), (0, 2, 3, 4))
    assert all(is_convex(written.vertices, p) for p in written.polygons)
    # an existing output is refused without --force (exit 2, nothing printed on stdout)
    code, stdout, err = run(capsys, "polylla", pentagon, "-o", out, "--convex")
    assert code == 2 and stdout == "" and "--force" in err
    code, _, _ = run(capsys, "polylla", pentagon, "-o", out, "--convex", "--force")
    assert code == 0


def test_no_opt_implies_convex(capsys: pytest.CaptureFixture[str], pentagon: Path) -> None:
    code, report = run_json(capsys, "polylla", pentagon, "--no-opt")
    assert code == 0
    assert report["convex_decomposition"] is True and report["criterion_one"] is False
    assert report["nonconvex_after"] == 0


def test_text_output(capsys: pytest.CaptureFixture[str], pentagon: Path) -> None:
    code, out, _ = run(capsys, "polylla", pentagon, "--convex")
    assert code == 0
    assert "Polylla + convex decomposition in" in out
    assert "polygons after   2" in out or "polygons after" in out


def test_pslg_input_is_triangulated(capsys: pytest.CaptureFixture[str], tmp_path: Path
                                    ) -> None:
    path = tmp_path / "square.poly"
    path.write_text(SQUARE_POLY)
    code, report = run_json(capsys, "polylla", path, "--check")
    assert code == 0
    assert report["triangulated"] is True and report["valid"] is True
    assert report["triangles"] == 2 and report["stats"]["total_area"] == "16"


def test_bad_inputs_exit_2(capsys: pytest.CaptureFixture[str], pentagon: Path,
                           tmp_path: Path) -> None:
    polygons = tmp_path / "polygons.off"
    assert run(capsys, "polylla", pentagon, "-o", polygons)[0] == 0
    code, out, err = run(capsys, "polylla", polygons)
    assert code == 2 and out == ""
    assert err.startswith("geomexact: error: ") and "is a polygon mesh: polylla works on" in err
    code, _, err = run(capsys, "polylla", pentagon, "-o", tmp_path / "out.ele")
    assert code == 2 and "polygon mesh" in err
    code, _, err = run(capsys, "polylla", pentagon, "--picture", tmp_path / "x.gif")
    assert code == 2 and ".png" in err
    code, _, err = run(capsys, "polylla", tmp_path / "missing.off")
    assert code == 2 and "missing.off" in err


def test_picture(capsys: pytest.CaptureFixture[str], pentagon: Path, tmp_path: Path) -> None:
    picture = tmp_path / "pentagon.png"
    code, report = run_json(capsys, "polylla", pentagon, "--convex", "--picture", picture)
    assert code == 0 and report["written"] == [str(picture)]
    assert picture.read_bytes().startswith(b"\x89PNG")


def test_help_lists_polylla(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "polylla" in out
    code, out, _ = run(capsys, "polylla", "--help")
    assert code == 0 and "--no-opt" in out and "--convex" in out


def test_shared_pikachu(capsys: pytest.CaptureFixture[str], shared_data: Path) -> None:
    path = shared_data / "polylla-dcel" / "pikachu.1.ele"
    code, report = run_json(capsys, "polylla", path, "--convex", "--check")
    assert code == 0
    assert (report["regions"], report["polygons"], report["barrier_tips"]) == (165, 167, 2)
    assert (report["inserted_edges"], report["polygons_after"]) == (63, 230)
    assert report["valid"] is True
