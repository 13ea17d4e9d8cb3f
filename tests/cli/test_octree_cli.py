"""``geomexact octree``: the JSON keys and their values, the box, grid, level, max-edge and
region options, the three output formats read back, the trace replayed from the start
file, and the refusals of bad input (exit 2, nothing written).  Levels stay <= 3."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from geomexact.cli import main
from geomexact.io import read
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh3d.snapshot import Mesh3

KEYS = ("leaves", "levels", "tetrahedra", "vertices", "min_dihedral", "max_dihedral",
        "max_radius_edge", "conforming", "volume", "seconds", "stage_seconds",
        "peak_memory_mb", "written")
STAGES = ("initial", "refinement", "improvement", "final", "conformity")


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, Any]:
    code = main(list(argv))
    out = capsys.readouterr().out
    return code, json.loads(out) if out.strip().startswith("{") else out


def octree(capsys: pytest.CaptureFixture[str], *argv: str) -> Any:
    code, report = run_json(capsys, "octree", *argv, "--json", "--no-progress")
    assert code == 0, report
    assert isinstance(report, dict)
    return report


def leaves_by_level(report: Any) -> dict[int, int]:
    return {int(level): count for level, count in report["levels"].items()}


def test_json_keys_of_the_default_run(capsys: pytest.CaptureFixture[str]) -> None:
    """The unit cube to level 3 everywhere: 512 cubes of 5 tetrahedra each."""
    report = octree(capsys)
    for key in KEYS:
        assert key in report, key
    assert report["leaves"] == 512 and leaves_by_level(report) == {3: 512}
    assert report["tetrahedra"] == 5 * 512 and report["vertices"] == 9 ** 3
    assert report["conforming"] is True and report["volume"] == "1"
    assert report["forced_splits"] == 0 and report["written"] == []
    # a cube's 5-tetrahedron partition: right angles and the regular middle tetrahedron
    assert report["min_dihedral"] == pytest.approx(54.7356, abs=1e-3)
    assert report["max_dihedral"] == pytest.approx(90.0)
    assert report["max_radius_edge"] == pytest.approx(3 ** 0.5 / 2)
    assert set(report["stage_seconds"]) == set(STAGES)
    assert all(value >= 0 for value in report["stage_seconds"].values())
    assert report["seconds"] >= sum(report["stage_seconds"].values()) - 1e-3
    assert report["peak_memory_mb"] > 0
    assert report["steps"] is None  # no --trace: the fast assembly


def test_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["octree", "--level", "1", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "octree mesh of" in out and "tetrahedra" in out and "40" in out
    assert "conforming" in out


@pytest.mark.parametrize(("box", "grid"), [
    (("0", "0", "0", "1/3", "1/2", "2/7"), ("2", "1", "3")),
    (("-0.25", "0.1", "2", "1/7", "1/2", "5/2"), ("1", "3", "2")),
])
def test_rational_box_and_grid_volume_is_exact(capsys: pytest.CaptureFixture[str],
                                               box: tuple[str, ...],
                                               grid: tuple[str, ...]) -> None:
    report = octree(capsys, "--box", *box, "--grid", *grid, "--level", "1")
    low = [parse_rational(v) for v in box[:3]]
    high = [parse_rational(v) for v in box[3:]]
    volume = (high[0] - low[0]) * (high[1] - low[1]) * (high[2] - low[2])
    assert parse_rational(report["volume"]) == volume
    assert report["volume"] == format_rational(volume)
    cells = int(grid[0]) * int(grid[1]) * int(grid[2])
    assert report["grid"] == [int(g) for g in grid]
    assert report["leaves"] == 8 * cells and report["tetrahedra"] == 40 * cells
    assert report["box"] == [format_rational(parse_rational(v)) for v in box]
    assert report["conforming"] is True


def test_stretched_grid_level_zero(capsys: pytest.CaptureFixture[str]) -> None:
    """--box 0 0 0 2 1 1 --grid 2 1 1: two unit cubes, 10 tetrahedra, volume 2."""
    report = octree(capsys, "--box", "0", "0", "0", "2", "1", "1", "--grid", "2", "1", "1",
                    "--level", "0")
    assert report["leaves"] == 2 and report["tetrahedra"] == 10
    assert report["vertices"] == 12 and report["volume"] == "2"


def test_max_edge_refines_until_short_enough(capsys: pytest.CaptureFixture[str]) -> None:
    """A 1 x 1/2 x 1/4 box with --max-edge 1/4: leaves of extents 1/4 x 1/8 x 1/16 (level
    2), all of them; 1/3 needs the same; 1/5 needs level 3."""
    box = ("--box", "0", "0", "0", "1", "1/2", "1/4")
    report = octree(capsys, *box, "--max-edge", "1/4")
    assert leaves_by_level(report) == {2: 64}
    assert octree(capsys, *box, "--max-edge", "1/3")["levels"] == report["levels"]
    assert leaves_by_level(octree(capsys, *box, "--max-edge", "1/5")) == {3: 512}
    # --level bounds it
    assert leaves_by_level(octree(capsys, *box, "--max-edge", "1/5", "--level", "1")) == {
        1: 8}
    assert report["volume"] == "0.125"  # exact text: a finite decimal


def test_refine_box_refines_only_near_it(capsys: pytest.CaptureFixture[str]) -> None:
    report = octree(capsys, "--refine-box", "0", "0", "0", "1/8", "1/8", "1/8",
                    "--level", "3")
    levels = leaves_by_level(report)
    assert max(levels) == 3 and min(levels) < 3
    assert report["leaves"] < 512 and report["conforming"] is True
    assert report["volume"] == "1"
    # the box touches only the corner cell: level 3 leaves there, coarser ones far away
    assert levels[3] < 64


def test_two_spheres_refine_more_than_one(capsys: pytest.CaptureFixture[str]) -> None:
    one = octree(capsys, "--refine-sphere", "1/4", "1/4", "1/4", "1/8", "--level", "3")
    two = octree(capsys, "--refine-sphere", "1/4", "1/4", "1/4", "1/8",
                 "--refine-sphere", "3/4", "3/4", "3/4", "1/8", "--level", "3")
    assert one["conforming"] and two["conforming"]
    assert one["leaves"] < two["leaves"] < 512
    assert one["tetrahedra"] < two["tetrahedra"]
    # symmetric spheres: the second doubles the level-3 leaves
    assert leaves_by_level(two)[3] == 2 * leaves_by_level(one)[3]
    assert one["volume"] == two["volume"] == "1"


def test_surface_refines_less_than_the_ball(capsys: pytest.CaptureFixture[str]) -> None:
    """The sphere of centre (0, 0, 0) and radius 3/4: the ball refines the corner cells,
    which the surface does not meet (their farthest point is nearer than 3/4)."""
    sphere = ("--refine-sphere", "0", "0", "0", "3/4", "--level", "3")
    ball = octree(capsys, *sphere)
    surface = octree(capsys, *sphere, "--surface")
    assert leaves_by_level(ball)[3] > leaves_by_level(surface)[3] > 0
    assert surface["conforming"] and surface["volume"] == "1"
    assert surface["leaves"] < ball["leaves"]
    # with radius 0.3 around the centre every level-2 cell the ball meets also meets the
    # sphere: the two agree
    centred = ("--refine-sphere", "0.5", "0.5", "0.5", "0.3", "--level", "3")
    assert octree(capsys, *centred)["levels"] == octree(capsys, *centred,
                                                       "--surface")["levels"]


def test_final_delaunay(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ("--refine-sphere", "0.5", "0.5", "0.5", "0.3", "--surface", "--level", "3")
    patterns = octree(capsys, *argv)
    delaunay = octree(capsys, *argv, "--final", "delaunay")
    assert delaunay["final"] == "delaunay" and patterns["final"] == "patterns"
    assert delaunay["leaves"] == patterns["leaves"]
    assert delaunay["conforming"] and delaunay["volume"] == "1"
    assert delaunay["digest"] != patterns["digest"]


def _read_back(path: Path) -> Mesh3:
    mesh = read(path)
    assert isinstance(mesh, Mesh3)
    return mesh


@pytest.mark.parametrize("name", ["m.ele", "m.vtu"])
def test_output_reads_back(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                           name: str) -> None:
    out = tmp_path / name
    report = octree(capsys, "--refine-sphere", "0.5", "0.5", "0.5", "0.3", "--surface",
                    "--level", "3", "-o", str(out))
    assert str(out) in report["written"]
    mesh = _read_back(out)
    assert mesh.tetrahedron_count == report["tetrahedra"]
    assert mesh.vertex_count == report["vertices"]
    if name.endswith(".ele"):  # decimals: the TetGen files hold the mesh exactly
        assert mesh.digest_text == report["digest"]
        assert {Path(p).name for p in report["written"]} == {"m.node", "m.ele", "m.face"}
    code, info = run_json(capsys, "info", str(out), "--json")
    assert code == 0 and info["tetrahedra"] == report["tetrahedra"]
    assert info["kind"] == "tetrahedral_mesh" and info["volume"] == "1"
    code, checked = run_json(capsys, "check", str(out), "--json")
    assert code == 0 and checked["valid"] is True
    assert checked["tetrahedra"] == report["tetrahedra"]


@pytest.mark.parametrize(("side", "radius", "name"), [("1e300", "3e299", "big.ele"),
                                                     ("1e-300", "3e-301", "small.vtu")])
def test_extreme_boxes_have_the_unit_boxs_figures(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str],
                                                  side: str, radius: str, name: str) -> None:
    """Issue 27 item 5: the doubles overflowed at 1e300 (NaN angles, and ``--json`` died
    after writing the mesh); the figures are scale-free, so they are the unit box's."""
    unit = octree(capsys, "--level", "2", "--refine-sphere", "0", "0", "0", "0.3")
    out = tmp_path / name
    report = octree(capsys, "--box", "0", "0", "0", side, side, side, "--level", "2",
                    "--refine-sphere", "0", "0", "0", radius, "-o", str(out))
    assert report["written"] and out.exists()
    assert report["tetrahedra"] == unit["tetrahedra"] and unit["leaves"] > 8
    for key in ("min_dihedral", "max_dihedral", "max_radius_edge"):
        assert isinstance(report[key], float) and math.isfinite(report[key])
        assert report[key] == unit[key], key
    if out.suffix == ".vtu":  # the file's angles too: no NaN from underflowing doubles
        import meshio

        angles = meshio.read(out).cell_data["min_dihedral"][0]
        assert np.isfinite(angles).all()
        assert angles.min() == pytest.approx(report["min_dihedral"], rel=1e-12)
    assert main(["octree", "--box", "0", "0", "0", side, side, side, "--level", "1",
                 "--no-progress"]) == 0
    assert "nan" not in capsys.readouterr().out


def test_a_box_thinner_than_the_doubles_reports_no_nan(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    """1e300 long and 1e-300 thick: the angles round to 0 and 180 degrees, and the
    radius-edge ratio (about 1e600) is beyond the doubles: null in JSON, inf in the
    table."""
    box = ("--box", "0", "0", "0", "1e300", "1", "1e-300", "--level", "1")
    report = octree(capsys, *box)
    assert report["min_dihedral"] == 0.0 and report["max_dihedral"] == 180.0
    assert report["max_radius_edge"] is None
    assert main(["octree", *box, "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "nan" not in out and "inf" in out


def test_off_output_is_the_geomview_off_of_tetrahedra(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Geomview OFF of the tetrahedra (write-only: four coloured faces per tetrahedron)."""
    out = tmp_path / "m.off"
    report = octree(capsys, "--level", "2", "-o", str(out))
    lines = out.read_text().splitlines()
    assert lines[0] == "OFF"
    assert lines[1].split() == [str(report["vertices"]), str(4 * report["tetrahedra"]), "0"]
    faces = lines[2 + report["vertices"]:]
    assert len(faces) == 4 * report["tetrahedra"]
    assert all(face.split()[0] == "3" and len(face.split()) == 8 for face in faces)
    # read back as a triangle surface (a 3D OFF): four faces a tetrahedron, interior
    # faces twice, so not the surface of a domain
    capsys.readouterr()
    assert main(["info", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["kind"] == "triangle_surface" and report["bounds_a_domain"] is False


def test_trace_and_start_replay_to_the_same_digest(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The start (vertices only, no tetrahedra) is written exactly in TetGen files; replay
    rebuilds the mesh with the same digest, also on a box of thirds."""
    for final in ("patterns", "delaunay"):
        directory = tmp_path / final
        directory.mkdir()
        start, trace, out = (directory / n for n in ("start.ele", "run.trace", "m.ele"))
        report = octree(capsys, "--box", "0", "0", "0", "1", "1/3", "2/3", "--grid", "1",
                        "1", "2", "--refine-sphere", "1/2", "1/6", "1/3", "1/5", "--level",
                        "3", "--final", final, "--trace", str(trace), "--start",
                        str(start), "-o", str(out), "--exact")
        assert report["steps"] is not None and report["steps"] >= report["leaves"]
        first = _read_back(start)
        assert first.tetrahedron_count == 0 and first.vertex_count == report["vertices"]
        again = directory / "again.ele"
        code, replayed = run_json(capsys, "replay", str(start), str(trace), "-o",
                                  str(again), "--exact", "--json")
        assert code == 0 and replayed["diverged"] is False
        assert replayed["final_digest"] == report["digest"]
        assert replayed["steps_applied"] == report["steps"]
        assert _read_back(again).digest_text == report["digest"]
        assert _read_back(out).digest_text == report["digest"]


def test_trace_without_start_is_the_same_mesh(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    """Recording the trace (the reference steps) does not change the mesh."""
    argv = ("--refine-sphere", "0.5", "0.5", "0.5", "0.3", "--surface", "--level", "3")
    fast = octree(capsys, *argv)
    traced = octree(capsys, *argv, "--trace", str(tmp_path / "run.trace"))
    assert traced["digest"] == fast["digest"] and traced["steps"] == fast["leaves"]


def _refused(tmp_path: Path, capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    before = sorted(p.name for p in tmp_path.iterdir())
    code = main(["octree", *argv, "--no-progress", "--json"])
    captured = capsys.readouterr()
    assert code == 2, captured
    assert captured.out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == before, "nothing is written"
    return captured.err


def test_refusals_write_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = str(tmp_path / "m.vtu")
    level = ("--level", "1")
    err = _refused(tmp_path, capsys, *level, "--start", str(tmp_path / "s.ele"), "-o", out)
    assert "--trace" in err
    err = _refused(tmp_path, capsys, *level, "--surface", "-o", out)
    assert "--refine-sphere" in err
    err = _refused(tmp_path, capsys, *level, "--box", "1", "0", "0", "1", "1", "1", "-o", out)
    assert "X0 < X1" in err
    _refused(tmp_path, capsys, *level, "--box", "0", "0", "0", "1", "1", "-1", "-o", out)
    err = _refused(tmp_path, capsys, *level, "--refine-sphere", "0", "0", "0", "-0.5",
                   "-o", out)
    assert "radius" in err
    _refused(tmp_path, capsys, *level, "--refine-sphere", "0", "0", "0", "0", "-o", out)
    _refused(tmp_path, capsys, *level, "--refine-box", "1", "0", "0", "0", "1", "1",
             "-o", out)
    _refused(tmp_path, capsys, "--level", "17", "-o", out)
    _refused(tmp_path, capsys, *level, "--grid", "0", "1", "1", "-o", out)
    _refused(tmp_path, capsys, *level, "--box", "0", "0", "0", "1", "1", "x", "-o", out)
    # the start is written exactly: a format of doubles is refused (after the run)
    err = _refused(tmp_path, capsys, *level, "--trace", str(tmp_path / "run.trace"),
                   "--start", str(tmp_path / "s.vtu"), "-o", out)
    assert "s.vtu" in err and "exact" in err


def test_existing_output_is_refused_without_force(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "m.ele"
    first = octree(capsys, "--level", "1", "-o", str(out))
    node = (tmp_path / "m.node").read_text()
    err = _refused(tmp_path, capsys, "--level", "2", "-o", str(out))
    assert "refusing to overwrite" in err
    assert (tmp_path / "m.node").read_text() == node
    # an existing trace output too, even when -o is new
    (tmp_path / "run.trace").write_text("x")
    _refused(tmp_path, capsys, "--level", "1", "-o", str(tmp_path / "n.vtu"), "--trace",
             str(tmp_path / "run.trace"))
    second = octree(capsys, "--level", "2", "-o", str(out), "--force")
    assert _read_back(out).tetrahedron_count == second["tetrahedra"] != first["tetrahedra"]
