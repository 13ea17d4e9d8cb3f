"""The ``geomexact`` command, run in-process through ``main(argv)``: output, JSON keys and
exit codes (0 ok, 1 check failed / trace diverged, 2 bad input or usage)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from helpers.paths import SUPERIOR

from geomexact import __version__, io
from geomexact.cli import main
from geomexact.io.trace_file import write_trace
from geomexact.mesh2d.ops import bisect, bisect_in, flip, flip_in, insert_centroid_in
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import Transient2
from geomexact.trace.record import trace_of

SUMMARY_KEYS = {
    "vertices", "triangles", "edges", "boundary_edges", "constrained_edges",
    "min_angle_deg", "max_angle_deg", "min_area", "max_area", "mean_area", "total_area",
    "is_delaunay", "digest",
}

SQUARE_OFF = """OFF
4 2 0
0 0 0
1 0 0
1 1 0
0 1 0
3 0 1 2
3 0 2 3
"""


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of ``geomexact argv…``."""
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, Any]:
    """Exit code and the one JSON object printed by ``geomexact argv… --json``."""
    code, out, _ = run(capsys, *argv, "--json")
    return code, json.loads(out)


def assert_one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("geomexact: error: "), err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0]


@pytest.fixture
def square_file(tmp_path: Path) -> Path:
    path = tmp_path / "square.off"
    path.write_text(SQUARE_OFF)
    return path


def record_trace(mesh: Mesh2, path: Path) -> tuple[Mesh2, Mesh2]:
    """Record flip, bisect and centroid steps on the square into ``path``; return the mesh
    after the first two steps and after all three."""
    t = Transient2(mesh)
    flip_in(t, 0, 2)
    bisect_in(t, 1, 3)
    insert_centroid_in(t, 1, 4)  # centroid (2/3, 1/3): not a finite decimal
    write_trace(path, trace_of(mesh, t))
    return bisect(flip(mesh, (0, 2)), (1, 3)), t.seal()


# ---------------------------------------------------------------------------------------
# info
# ---------------------------------------------------------------------------------------
def test_info_json_of_off_mesh_has_exact_counts(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """500poisson.off: 539 vertices, 1012 triangles, total area exactly 1."""
    path = shared_data / "polylla-refinement" / "500poisson.off"
    code, report = run_json(capsys, "info", path)
    assert code == 0
    assert set(report) >= SUMMARY_KEYS
    assert report["file"] == str(path)
    assert report["vertices"] == 539
    assert report["triangles"] == 1012
    assert report["total_area"] == "1"
    assert report["is_delaunay"] is True
    assert len(report["digest"]) == 32


def test_info_of_several_files_lists_each(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """Several files give {"files": [...]} in order, one summary each."""
    paths = [
        shared_data / "polylla-refinement" / "500poisson.off",
        shared_data / "qlepp2d" / "A.off",
    ]
    code, report = run_json(capsys, "info", *paths)
    assert code == 0
    assert [entry["file"] for entry in report["files"]] == [str(p) for p in paths]
    assert report["files"][1]["triangles"] == 2


def test_info_table_names_every_statistic(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """The human table has one row per statistic."""
    code, out, err = run(capsys, "info", shared_data / "qlepp2d" / "B.off")
    assert code == 0, err
    for label in ("vertices", "triangles", "min angle deg", "total area", "is delaunay"):
        assert label in out


def test_info_of_pslg_reports_counts_and_exact_bounding_box(
    capsys: pytest.CaptureFixture[str]
) -> None:
    """superior.poly: 518 vertices and segments, 6 holes, exact decimal bounding box."""
    code, report = run_json(capsys, "info", SUPERIOR)
    assert code == 0
    assert report["kind"] == "pslg"
    assert (report["vertices"], report["segments"], report["holes"]) == (518, 518, 6)
    assert report["bounding_box"] == {
        "x_min": "0.1", "x_max": "0.9", "y_min": "-0.69454", "y_max": "-0.30546"
    }


def test_info_of_polygon_mesh_reports_polygon_sizes(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """The Polylla mesh of points50 has 17 polygons of at least 3 vertices."""
    code, report = run_json(capsys, "info", shared_data / "polylla-dcel" / "points50.1.off")
    assert code == 0
    assert report["kind"] == "polygon_mesh"
    assert report["polygons"] == 17
    assert 3 <= report["min_polygon_size"] <= report["max_polygon_size"]


def test_info_verbose_prints_reader_notes_on_stderr(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """A clockwise file is oriented, and -v says so on stderr (stdout stays JSON)."""
    path = shared_data / "polylla-refinement" / "pikachu_triangle.off"
    code, out, err = run(capsys, "info", path, "--json", "-v")
    assert code == 0
    report = json.loads(out)
    assert report["triangles"] == 531
    assert report["notes"]
    assert str(path) in err


def test_info_of_missing_file_is_one_line_error(capsys: pytest.CaptureFixture[str]) -> None:
    """A missing file: exit 2, one line naming it, nothing on stdout."""
    code, out, err = run(capsys, "info", "no-such-mesh.off")
    assert code == 2
    assert out == ""
    assert_one_line_error(err, "no-such-mesh.off")


def test_bad_number_names_file_and_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """An unparsable coordinate: exit 2 and one line ``file:line: problem``."""
    path = tmp_path / "bad.off"
    path.write_text(SQUARE_OFF.replace("1 1 0", "1 one 0"))
    code, out, err = run(capsys, "info", path, "--json")
    assert code == 2
    assert out == ""
    assert_one_line_error(err, f"{path}:5")


# ---------------------------------------------------------------------------------------
# check
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name", ["qlepp2d/A.off", "qlepp2d/B.off", "polylla-refinement/pikachu_triangle.off"]
)
def test_check_valid_mesh_exits_0(
    capsys: pytest.CaptureFixture[str], shared_data: Path, name: str
) -> None:
    """Real triangulations (one listed clockwise) pass every invariant."""
    code, report = run_json(capsys, "check", shared_data / name)
    assert code == 0
    assert report["valid"] is True
    assert report["violations"] == []
    code, out, _ = run(capsys, "check", shared_data / name)
    assert code == 0
    assert "valid" in out


def test_check_reports_unused_duplicate_vertices_of_500poisson(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """500poisson.off lists the corners (1, 1) and (1, 0) twice; the copies 536 and 538 are
    in no triangle: legal (Triangle keeps such vertices), but --strict names them."""
    path = shared_data / "polylla-refinement" / "500poisson.off"
    code, report = run_json(capsys, "check", path)
    assert code == 0 and report["violations"] == []
    code, report = run_json(capsys, "check", "--strict", path)
    assert code == 1
    assert [(v["kind"], v["elements"]) for v in report["violations"]] == [
        ("isolated-vertex", [536]),
        ("isolated-vertex", [538]),
    ]


def test_check_finds_stacked_components(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A small triangle lying inside a big one, sharing no vertex: exit 1 (overlap)."""
    path = tmp_path / "stacked.off"
    path.write_text("OFF\n6 2 0\n0 0 0\n9 0 0\n0 9 0\n1 1 0\n2 1 0\n1 2 0\n3 0 1 2\n3 3 4 5\n")
    code, report = run_json(capsys, "check", path)
    assert code == 1
    assert [v["kind"] for v in report["violations"]] == ["overlap"]


def test_check_finds_crossing_boundaries(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Two triangles whose boundaries cross, sharing no vertex: exit 1 (overlap)."""
    path = tmp_path / "crossing.off"
    path.write_text("OFF\n6 2 0\n0 0 0\n4 0 0\n0 4 0\n1 1 0\n5 1 0\n1 5 0\n3 0 1 2\n3 3 4 5\n")
    code, report = run_json(capsys, "check", path)
    assert code == 1
    assert {v["kind"] for v in report["violations"]} == {"overlap"}


def test_check_overlapping_triangles_exits_1_listing_violations(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Two overlapping triangles around vertex 0: exit 1 and every violation listed."""
    path = tmp_path / "overlap.off"
    path.write_text("OFF\n5 2 0\n0 0 0\n4 0 0\n0 4 0\n4 1 0\n1 4 0\n3 0 1 2\n3 0 3 4\n")
    code, out, err = run(capsys, "check", path)
    assert code == 1, err
    assert "invalid" in out
    assert "non-manifold-vertex" in out
    code, report = run_json(capsys, "check", path)
    assert code == 1
    assert report["valid"] is False
    assert {"kind", "message", "elements"} <= set(report["violations"][0])


def test_check_unreadable_mesh_exits_2(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Two triangles on the same side of an edge cannot be read: exit 2, not 1."""
    path = tmp_path / "same-side.off"
    path.write_text("OFF\n4 2 0\n0 0 0\n2 0 0\n0 2 0\n1 1 0\n3 0 1 2\n3 0 1 3\n")
    code, _, err = run(capsys, "check", path)
    assert code == 2
    assert_one_line_error(err, str(path))


def test_check_of_a_pslg_says_whether_it_triangulates(
    capsys: pytest.CaptureFixture[str]
) -> None:
    """check of a PSLG: valid when triangulate accepts it and uses every seed (it was a
    usage error, exit 2)."""
    code, out, err = run(capsys, "check", SUPERIOR)
    assert code == 0, err
    assert out.startswith(f"{SUPERIOR}: valid (518 vertices, 518 segments, 6 holes")


TWO_SQUARES_OFF = """OFF
7 2 0
0 0 0
1 0 0
2 0 0
2 1 0
1 1 0
0 1 0
5 5 0
4 0 1 4 5
4 1 2 3 4
"""


def test_check_valid_polygon_mesh(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """Two unit squares sharing an edge: valid; the unused vertex 6 only under --strict."""
    path = tmp_path / "squares.off"
    path.write_text(TWO_SQUARES_OFF)
    code, report = run_json(capsys, "check", path)
    assert code == 0
    assert report["kind"] == "polygon_mesh"
    assert (report["valid"], report["polygons"], report["violations"]) == (True, 2, [])
    code, out, _ = run(capsys, "check", path)
    assert (code, out.strip()) == (0, f"{path}: valid (7 vertices, 2 polygons)")
    code, report = run_json(capsys, "check", "--strict", path)
    assert code == 1
    assert [(v["kind"], v["elements"]) for v in report["violations"]] == [
        ("isolated-vertex", [6])
    ]


@pytest.mark.parametrize(
    ("faces", "kinds"),
    [
        ("4 0 1 4 5\n4 1 2 3 5\n", {"crossing"}),  # the second polygon overlaps the first
        ("4 0 1 4 5\n4 0 1 4 5\n", {"duplicate-edge", "overlap"}),  # the same square twice
        ("4 0 1 4 5\n5 1 2 3 4 0\n", {"duplicate-edge", "overlap"}),  # folds over the first
    ],
)
def test_check_invalid_polygon_mesh_exits_1(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, faces: str, kinds: set[str]
) -> None:
    path = tmp_path / "bad.off"
    path.write_text(TWO_SQUARES_OFF.split("4 0 1 4 5")[0] + faces)
    code, report = run_json(capsys, "check", path)
    assert code == 1
    assert report["valid"] is False
    assert kinds <= {violation["kind"] for violation in report["violations"]}


@pytest.mark.parametrize(
    ("faces", "problem"),
    [
        ("4 0 5 4 1\n4 1 2 3 4\n", ":11: faces have mixed orientations"),
        ("4 0 1 4 1\n4 1 2 3 4\n", ":10: face 0 (0 1 4 1) on line 10 has zero area"),
    ],
)
def test_check_of_unreadable_polygon_mesh_names_the_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, faces: str, problem: str
) -> None:
    path = tmp_path / "bad.off"
    path.write_text(TWO_SQUARES_OFF.split("4 0 1 4 5")[0] + faces)
    code, _, err = run(capsys, "check", path)
    assert code == 2
    assert f"{path}{problem}" in err


def test_info_of_polygon_mesh_reports_convexity_angles_and_area(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "squares.off"
    path.write_text(TWO_SQUARES_OFF)
    code, report = run_json(capsys, "info", path)
    assert code == 0
    assert (report["vertices"], report["used_vertices"], report["polygons"]) == (7, 6, 2)
    assert (report["convex"], report["nonconvex"], report["edges"]) == (2, 0, 7)
    assert (report["min_angle_deg"], report["max_angle_deg"]) == (90.0, 90.0)
    assert report["total_area"] == "2"


# ---------------------------------------------------------------------------------------
# convert
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("suffix", [".ele", ".off"])
def test_convert_round_trip_keeps_the_digest(
    capsys: pytest.CaptureFixture[str], shared_data: Path, tmp_path: Path, suffix: str
) -> None:
    """OFF -> other format (exact) -> read back: same content digest."""
    source = shared_data / "polylla-refinement" / "500poisson.off"
    target = tmp_path / f"poisson{suffix}"
    code, out, err = run(capsys, "convert", source, target, "--exact")
    assert code == 0, err
    assert f"wrote {target}" in out
    _, before = run_json(capsys, "info", source)
    _, after = run_json(capsys, "info", target)
    assert after["digest"] == before["digest"]


def test_convert_refuses_to_overwrite_without_force(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """An existing output is kept unless --force is given."""
    target = tmp_path / "copy.off"
    target.write_text("keep me")
    code, _, err = run(capsys, "convert", square_file, target)
    assert code == 2
    assert_one_line_error(err, str(target), "--force")
    assert target.read_text() == "keep me"
    code, _, err = run(capsys, "convert", square_file, target, "--force")
    assert code == 0, err
    assert isinstance(io.read(target), Mesh2)


def test_convert_to_a_format_that_cannot_hold_the_value_is_bad_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A PSLG cannot be written as OFF: exit 2 with one line, nothing written."""
    target = tmp_path / "superior.off"
    code, _, err = run(capsys, "convert", SUPERIOR, target)
    assert code == 2
    assert_one_line_error(err, "off", "pslg")
    assert not target.exists()


def test_convert_json_lists_written_files(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """--json: one object with the files written."""
    code, report = run_json(capsys, "convert", square_file, tmp_path / "square.ele")
    assert code == 0
    assert str(tmp_path / "square.ele") in report["written"]
    assert report["kind"] == "triangle_mesh"


# ---------------------------------------------------------------------------------------
# replay
# ---------------------------------------------------------------------------------------
def test_replay_reproduces_the_recorded_mesh(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """All steps replayed: the digest is the recorded one and the file holds the mesh."""
    start = io.read(square_file)
    assert isinstance(start, Mesh2)
    _, final = record_trace(start, tmp_path / "run.trace")
    out = tmp_path / "final.off"
    code, report = run_json(
        capsys, "replay", square_file, tmp_path / "run.trace", "-o", out, "--exact"
    )
    assert code == 0
    assert report["steps_applied"] == report["trace_steps"] == 3
    assert report["final_digest"] == final.digest_text
    assert io.read(out) == final


def test_replay_until_stops_after_k_steps(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """--until 2 gives the mesh after two steps."""
    start = io.read(square_file)
    assert isinstance(start, Mesh2)
    after_two, _ = record_trace(start, tmp_path / "run.trace")
    out = tmp_path / "two.off"
    code, report = run_json(
        capsys, "replay", square_file, tmp_path / "run.trace", "--until", "2", "-o", out
    )
    assert code == 0
    assert report["steps_applied"] == 2
    assert report["final_digest"] == after_two.digest_text


def test_replay_on_another_mesh_is_bad_input(
    capsys: pytest.CaptureFixture[str], square_file: Path, shared_data: Path, tmp_path: Path
) -> None:
    """A trace recorded on another mesh: exit 2, the message says so, nothing written."""
    start = io.read(square_file)
    assert isinstance(start, Mesh2)
    record_trace(start, tmp_path / "run.trace")
    other = shared_data / "qlepp2d" / "A.off"
    out = tmp_path / "never.off"
    code, stdout, err = run(capsys, "replay", other, tmp_path / "run.trace", "-o", out)
    assert code == 2
    assert stdout == ""
    assert_one_line_error(err, "not the trace's input")
    assert not out.exists()


def test_replay_of_tampered_trace_diverges_with_exit_1(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """A step digest changed in the file: exit 1, "trace diverged" naming step 2."""
    start = io.read(square_file)
    assert isinstance(start, Mesh2)
    trace_path = tmp_path / "run.trace"
    record_trace(start, trace_path)
    lines = trace_path.read_text().splitlines()
    step = json.loads(lines[2])
    step["digest"] = "0" * 32
    lines[2] = json.dumps(step)
    trace_path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "never.off"
    code, stdout, err = run(capsys, "replay", square_file, trace_path, "-o", out, "--json")
    assert code == 1
    assert json.loads(stdout)["diverged"] is True
    assert "trace diverged" in err and "step 2" in err
    assert not out.exists()


@pytest.mark.parametrize("until", ["4", "-1", "two"])
def test_replay_until_out_of_range_is_usage_error(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path, until: str
) -> None:
    """--until beyond the trace, negative or not a number: exit 2."""
    start = io.read(square_file)
    assert isinstance(start, Mesh2)
    record_trace(start, tmp_path / "run.trace")
    code, _, err = run(
        capsys, "replay", square_file, tmp_path / "run.trace", "--until", until,
        "-o", tmp_path / "x.off",
    )
    assert code == 2
    assert "error" in err and "Traceback" not in err


def test_malformed_trace_names_file_and_line(
    capsys: pytest.CaptureFixture[str], square_file: Path, tmp_path: Path
) -> None:
    """A trace that is not JSON Lines: exit 2 with ``trace:1``."""
    trace_path = tmp_path / "bad.trace"
    trace_path.write_text("this is not json\n")
    code, _, err = run(capsys, "replay", square_file, trace_path, "-o", tmp_path / "x.off")
    assert code == 2
    assert_one_line_error(err, f"{trace_path}:1")


# ---------------------------------------------------------------------------------------
# demo, usage, version
# ---------------------------------------------------------------------------------------
def test_demo_writes_exact_copies_and_refuses_to_overwrite(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """demo writes superior.node/.poly (read back: the same PSLG); a second run without
    --force changes nothing and exits 2; with --force it succeeds."""
    directory = tmp_path / "demo"
    code, report = run_json(capsys, "demo", "-o", directory)
    assert code == 0
    assert report["input"]["vertices"] == 518
    assert report["input"]["holes"] == 6
    assert sorted(Path(p).name for p in report["written"]) == [
        "superior.1.ele", "superior.1.neigh", "superior.1.node", "superior.1.poly",
        "superior.1.trace.jsonl", "superior.2.ele", "superior.2.neigh", "superior.2.node",
        "superior.2.poly", "superior.2.polylla.off", "superior.2.trace.jsonl",
        "superior.html", "superior.node", "superior.png", "superior.poly",
    ]
    assert report["triangulation"]["triangles"] == 528
    assert report["triangulation"]["is_delaunay"] is True
    refined = report["refinement"]
    assert refined["status"] == "complete" and refined["is_delaunay"] is True
    assert refined["total_area"] == report["triangulation"]["total_area"]  # exact
    assert refined["triangles"] > 528 and report["polylla"]["polygons"] > 0
    pslg = io.read(directory / "superior.poly")
    assert isinstance(pslg, PSLG)
    assert len(pslg.vertices) == 518 and len(pslg.segments) == 518 and len(pslg.holes) == 6
    bundled = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
    assert pslg == io.read(bundled)
    stamp = (directory / "superior.node").stat().st_mtime_ns
    code, out, err = run(capsys, "demo", "-o", directory)
    assert code == 2
    assert out == ""
    assert_one_line_error(err, "superior.node", "--force")
    assert (directory / "superior.node").stat().st_mtime_ns == stamp
    code, out, err = run(capsys, "demo", "-o", directory, "--force")
    assert code == 0, err
    assert "518" in out


@pytest.mark.parametrize(
    "argv", [[], ["frobnicate"], ["info"], ["replay", "a.off", "b.trace"], ["info", "--format",
                                                                             "nope", "x"]]
)
def test_usage_errors_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str]) -> None:
    """argparse errors: exit 2 with a usage line."""
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert "usage: geomexact" in err


def test_help_lists_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    """--help exits 0 and documents the exit codes."""
    code, out, _ = run(capsys, "--help")
    assert code == 0
    assert "exit codes" in out and "check found violations" in out


def test_python_m_geomexact_version() -> None:
    """``python -m geomexact --version`` works in a fresh process."""
    completed = subprocess.run(
        [sys.executable, "-m", "geomexact", "--version"],
        capture_output=True, text=True, check=False,
    )
    assert completed.returncode == 0, completed.stderr
    first, kernels, *runs = completed.stdout.strip().splitlines()
    assert first == f"geomexact {__version__}"
    from geomexact.mesh2d.delaunay import compiled as delaunay_compiled
    from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
    from geomexact.mesh3d.cuboid import compiled as cuboid_compiled

    expected = [name for name, built in (("lepp", compiled_engine.AVAILABLE),
                                         ("delaunay", delaunay_compiled.AVAILABLE),
                                         ("cuboid", cuboid_compiled.AVAILABLE)) if built]
    assert kernels == "compiled kernels: " + (
        ", ".join(expected) if expected else "none (pure-Python engines)")
    assert [line.split(":")[0].strip() for line in runs] == expected


def test_triangulate_superior_writes_mesh_and_a_replayable_trace(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """triangulate superior.poly: 518 vertices, 528 triangles, every segment constrained;
    the trace replays on the .poly itself to the same digest."""
    bundled = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
    out, trace = tmp_path / "superior.1.ele", tmp_path / "superior.trace"
    code, report = run_json(capsys, "triangulate", bundled, "-o", out, "--trace", trace,
                            "--check", "--exact")
    assert code == 0, report
    assert (report["vertices"], report["triangles"], report["constrained_edges"]) == (
        518, 528, 518)
    assert report["is_delaunay"] and report["valid"]
    code, replayed = run_json(capsys, "replay", bundled, trace, "-o", tmp_path / "r.ele",
                              "--exact")
    assert code == 0
    assert replayed["final_digest"] == report["digest"]
    mesh = io.read(out)
    assert isinstance(mesh, Mesh2) and mesh.digest_text == report["digest"]


def test_triangulate_makes_a_mesh_delaunay(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A non-Delaunay mesh (a thin quadrilateral split along its long diagonal) is flipped."""
    path = tmp_path / "thin.off"
    path.write_text("OFF\n4 2 0\n0 0 0\n10 -1 0\n20 0 0\n10 1 0\n3 0 1 2\n3 0 2 3\n")
    code, report = run_json(capsys, "triangulate", path, "-o", tmp_path / "d.off")
    assert code == 0
    assert report["algorithm"] == "lawson flips" and report["steps"] == 1
    assert report["is_delaunay"] is True


def test_triangulate_crossing_segments_is_bad_input_unless_split(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "cross.poly"
    path.write_text("4 2 0 0\n1 0 0\n2 2 2\n3 0 2\n4 2 0\n2 0\n1 1 2\n2 3 4\n0\n")
    code, out, err = run(capsys, "triangulate", path)
    assert code == 2 and out == ""
    assert_one_line_error(err, "cross", "--split-segments")
    code, report = run_json(capsys, "triangulate", path, "--split-segments")
    assert code == 0
    assert report["vertices"] == 5 and report["constrained_edges"] == 4


def test_refine_writes_the_polylla_mesh_of_the_result(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """refine … --polylla OFF writes a polygon mesh covering the refined mesh exactly."""
    bundled = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
    out, polygons = tmp_path / "r.ele", tmp_path / "r.off"
    code, report = run_json(capsys, "refine", bundled, "--min-angle", "25", "--method",
                            "centroid", "-o", out, "--polylla", polygons, "--exact")
    assert code == 0 and report["status"] == "complete"
    assert str(polygons) in report["written"]
    mesh, polygon_mesh = io.read(out), io.read(polygons)
    assert isinstance(mesh, Mesh2) and isinstance(polygon_mesh, PolygonMesh)
    assert polygon_mesh.total_area() == report_area(report)


def report_area(report: dict[str, Any]) -> object:
    from geomexact.kernel.numbers import parse_rational

    return parse_rational(report["total_area"])


def test_the_command_table_is_what_the_command_modules_register() -> None:
    """``geomexact --help`` lists the commands from ``COMMAND_TABLE`` without loading
    their modules: the table names every command each module's ``add_parser`` registers,
    in order, with the same help line, and every subcommand (``trace show``) likewise."""
    import argparse

    from geomexact.cli.command_table import COMMAND_TABLE
    from geomexact.cli.parser import build_parser

    def subcommands(parser: argparse.ArgumentParser) -> argparse._SubParsersAction[Any]:
        return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))

    def commands(parser: argparse.ArgumentParser) -> list[tuple[str, str | None]]:
        return [(choice.dest, choice.help) for choice in subcommands(parser)._choices_actions]

    expected = [(spec.name, spec.summary) for spec in COMMAND_TABLE]
    assert commands(build_parser()) == expected
    assert commands(build_parser(["--help"])) == expected
    assert commands(build_parser(["refine", "x.off"])) == expected
    registered = subcommands(build_parser()).choices
    for spec in COMMAND_TABLE:
        if spec.subcommands:
            assert commands(registered[spec.name]) == [
                (inner.name, inner.summary) for inner in spec.subcommands]


def test_help_loads_no_command_module() -> None:
    """``geomexact --help`` starts without the library: no io, numpy or mesh modules."""
    script = ("import contextlib, io, json, sys\nfrom geomexact.cli import main\n"
              "with contextlib.redirect_stdout(io.StringIO()):\n    main(['--help'])\n"
              "print(json.dumps(sorted(sys.modules)))")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          check=True)
    loaded = set(json.loads(done.stdout))
    assert not {"numpy", "gmpy2", "geomexact.io", "geomexact.mesh2d.snapshot",
                "geomexact.cli.refine"} & loaded
