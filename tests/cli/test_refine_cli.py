"""``geomexact refine``: criteria, regions, methods, outputs (mesh, trace, every step),
JSON summary, progress on stderr, status and exit codes (0 ok, 1 a check failed, 2 bad
input or usage)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from geomexact import Mesh2, io, mpq, total_area
from geomexact.cli import main
from geomexact.io.trace_file import read_trace

SQUARE_OFF = """OFF
4 2 0
0 0 0
1 0 0
1 1 0
0 1 0
3 0 1 2
3 0 2 3
"""

PENTAGON_POLY = """# a pentagon with two inner points
7 2 0 0
1 0 0
2 8 0
3 9 3
4 4 5
5 -1 3
6 3 1
7 5 2
5 0
1 1 2
2 2 3
3 3 4
4 4 5
5 5 1
0
"""

SUMMARY_KEYS = {
    "vertices", "triangles", "edges", "boundary_edges", "constrained_edges",
    "min_angle_deg", "max_angle_deg", "min_area", "max_area", "mean_area", "total_area",
    "is_delaunay", "digest",
}


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def one_line_error(err: str, *fragments: str) -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("geomexact: error: "), err
    for fragment in fragments:
        assert fragment in lines[0]


@pytest.fixture
def square(tmp_path: Path) -> Path:
    path = tmp_path / "square.off"
    path.write_text(SQUARE_OFF)
    return path


@pytest.fixture
def pentagon(tmp_path: Path) -> Path:
    path = tmp_path / "pentagon.poly"
    path.write_text(PENTAGON_POLY)
    return path


def test_refine_max_area_writes_the_mesh_and_a_json_summary(
    capsys: pytest.CaptureFixture[str], square: Path, tmp_path: Path
) -> None:
    """--max-area 1/64 on the unit square: 64 triangles; the JSON has the info keys plus
    steps, seconds and status."""
    out_path = tmp_path / "out.off"
    code, out, err = run(capsys, "refine", square, "--max-area", "1/64", "-o", out_path,
                         "--json")
    assert code == 0, err
    report = json.loads(out)
    assert SUMMARY_KEYS | {"steps", "seconds", "status"} <= set(report)
    assert report["triangles"] == 64 and report["status"] == "complete"
    assert report["criterion"] == {"kind": "max_area", "area": "0.015625"}  # exact 1/64
    mesh = io.read(out_path)
    assert isinstance(mesh, Mesh2) and mesh.triangle_count == 64
    assert total_area(mesh) == 1


def test_refine_table_summary(capsys: pytest.CaptureFixture[str], square: Path) -> None:
    """Without --json: a table with the mesh statistics, the steps and the status."""
    code, out, _ = run(capsys, "refine", square, "--max-edge", "0.3", "--method", "centroid")
    assert code == 0
    assert "Lepp-centroid refinement" in out and "complete" in out
    assert "min angle deg" in out and "mean area" in out


def test_refine_a_pslg_writes_a_trace_that_replays_from_the_pslg(
    capsys: pytest.CaptureFixture[str], pentagon: Path, tmp_path: Path
) -> None:
    """A PSLG is triangulated first; the trace starts at its vertices and `replay` on the
    PSLG reproduces the refined mesh (same digest)."""
    trace_path = tmp_path / "run.jsonl"
    code, out, err = run(capsys, "refine", pentagon, "--min-angle", "30", "--method", "quasi",
                         "--trace", trace_path, "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["triangulated"] is True
    trace = read_trace(trace_path)
    assert trace.parameter("method") == "quasi"
    assert trace.parameter("triangulation_steps") > 0
    code, out, err = run(capsys, "replay", pentagon, trace_path, "-o", tmp_path / "r.ele",
                         "--json")
    assert code == 0, err
    assert json.loads(out)["final_digest"] == report["digest"]


@pytest.mark.parametrize(
    "region",
    [["--circle", "0.5", "0.5", "0.2"], ["--rectangle", "0", "0", "0.25", "0.5"]],
)
def test_refine_in_a_region(
    capsys: pytest.CaptureFixture[str], square: Path, region: list[str]
) -> None:
    """Circle and rectangle regions are parsed exactly and reported."""
    code, out, err = run(capsys, "refine", square, "--max-area", "0.001", *region, "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["region"]["kind"] == region[0][2:]
    whole = json.loads(run(capsys, "refine", square, "--max-area", "0.001", "--json")[1])
    assert report["triangles"] < whole["triangles"]


def test_refine_in_a_polygon_file_region(
    capsys: pytest.CaptureFixture[str], square: Path, tmp_path: Path
) -> None:
    """--polygon reads an OFF polygon (one face) or a PSLG loop."""
    off = tmp_path / "region.off"
    off.write_text("OFF\n4 1 0\n0 0 0\n0.5 0 0\n0.5 0.25 0\n0 0.25 0\n4 0 1 2 3\n")
    poly = tmp_path / "region.poly"
    poly.write_text("4 2 0 0\n1 0 0\n2 0.5 0\n3 0.5 0.25\n4 0 0.25\n4 0\n1 1 2\n2 2 3\n"
                    "3 3 4\n4 4 1\n0\n")
    reports = []
    for region in (off, poly):
        code, out, err = run(capsys, "refine", square, "--max-area", "0.001", "--polygon",
                             region, "--json")
        assert code == 0, err
        reports.append(json.loads(out))
    assert reports[0]["digest"] == reports[1]["digest"]
    assert reports[0]["region"]["kind"] == "polygon"


def test_refine_pikachu_in_its_polygon(
    capsys: pytest.CaptureFixture[str], shared_data: Path
) -> None:
    """The shared Pikachu mesh with the shared polygon.off region."""
    folder = shared_data / "polylla-refinement"
    code, out, err = run(capsys, "refine", folder / "pikachu_triangle.off", "--max-area",
                         "50000", "--polygon", folder / "polygon.off", "--method", "centroid",
                         "--check", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["valid"] is True and report["status"] == "complete"


def test_min_angle_with_bisection_is_refused_without_a_step_limit(
    capsys: pytest.CaptureFixture[str], pentagon: Path
) -> None:
    """Bisection does not raise angles: --method bisection exits 2 with the explanation in
    command-line words; allowed with a limit, which stops the run with status step-limit
    (said on stderr, with the number of bad triangles not refined yet)."""
    code, _, err = run(capsys, "refine", pentagon, "--min-angle", "30", "--method", "bisection")
    assert code == 2
    one_line_error(err, "does not raise angles", "--method centroid", "--max-steps N")
    assert "max_steps" not in err and "method=" not in err
    code, out, err = run(capsys, "refine", pentagon, "--min-angle", "30", "--max-steps", "3",
                         "--method", "bisection", "--json")
    assert code == 0
    report = json.loads(out)
    assert report["status"] == "step-limit" and report["steps"] == 3
    assert report["waiting"] > 0 and report["left"] == [] and report["notes"] == []
    assert f"{report['waiting']} not refined yet: the run stopped at the step limit" in err


def test_min_angle_without_a_method_chooses_centroid_and_says_so(
    capsys: pytest.CaptureFixture[str], pentagon: Path
) -> None:
    """--min-angle without --method: the centroid method (which can meet it), a note on
    stderr and in --json, exit 0 (it was exit 2: bisection refused)."""
    code, out, err = run(capsys, "refine", pentagon, "--min-angle", "30", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["method"] == "centroid" and report["status"] == "complete"
    note = "--min-angle without --method: using --method centroid"
    assert any(note in text for text in report["notes"]) and note in err
    code, out, err = run(capsys, "refine", pentagon, "--max-area", "1", "--json")
    assert code == 0 and json.loads(out)["method"] == "bisection" and "--method" not in err


def test_no_delaunay_refusal_names_the_options(
    capsys: pytest.CaptureFixture[str], pentagon: Path
) -> None:
    """A minimum angle with --no-delaunay and no step limit: the remedy in options."""
    code, _, err = run(capsys, "refine", pentagon, "--min-angle", "30", "--no-delaunay")
    assert code == 2
    one_line_error(err, "drop --no-delaunay", "--max-steps N")
    assert "delaunay=True" not in err


def test_progress_goes_to_stderr_and_json_stays_one_object(
    capsys: pytest.CaptureFixture[str], square: Path
) -> None:
    """--progress with --json: stdout is exactly one JSON object, the bar is on stderr."""
    code, out, err = run(capsys, "refine", square, "--max-area", "1/256", "--progress",
                         "--json")
    assert code == 0
    assert json.loads(out)["triangles"] == 256
    assert "refine [" in err and "256 triangles" in err


def test_progress_moves_with_the_work_and_names_each_stage(
    tmp_path: Path, square: Path
) -> None:
    """Issue 26, item 5: the bar follows the work (steps against the steps plus the
    triangles still to fix, or the criterion's estimate), not the step budget (200
    million steps for a 500,000-step run: empty, then full), and the stages after the
    run are named -- writing included -- before 'done'."""
    from geomexact.cli.refine import RefineProgress

    progress = RefineProgress(estimate=1000)
    assert progress.fraction(100, 200, 100) == 0.5
    assert progress.fraction(10, 900, 5000) == 0.9  # the estimate is further
    assert progress.fraction(10, 5000, 1) == 0.99  # never full while work is queued
    assert progress.fraction(10, 5000, 0) == 1.0
    done = subprocess.run(
        [sys.executable, "-m", "geomexact", "refine", str(square), "--max-area", "1/1024",
         "-o", str(tmp_path / "out.off"), "--trace", str(tmp_path / "run.trace"),
         "--progress"], capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.startswith("refine [")]
    stages = [line.split("; ", 1)[1].rsplit(",", 1)[0] for line in lines if "; " in line]
    assert stages == [f"writing {tmp_path / 'out.off'}", f"writing {tmp_path / 'run.trace'}",
                      "summarising", "done"]


def test_check_delaunay_fails_for_a_non_delaunay_result(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A non-Delaunay input that needs no refinement: --check-delaunay exits 1 and says
    so (refinement legalizes only around new vertices)."""
    path = tmp_path / "kite.off"
    path.write_text("OFF\n4 2 0\n0 0 0\n4 0 0\n2 1 0\n2 -1 0\n3 0 1 2\n3 1 0 3\n")
    code, out, err = run(capsys, "refine", path, "--max-area", "100", "--check-delaunay",
                         "--json")
    assert code == 1
    assert json.loads(out)["is_delaunay"] is False
    assert "not Delaunay" in err


@pytest.mark.parametrize(("options", "checked"), [
    ((), False),
    (("--check-delaunay",), True),
    (("--method", "centroid"), False),
    (("--method", "quasi"), True),
    (("--no-delaunay",), True),
])
def test_the_delaunay_check_is_skipped_where_the_method_guarantees_it(
    capsys: pytest.CaptureFixture[str], square: Path, options: tuple[str, ...], checked: bool
) -> None:
    """Lepp-bisection and Lepp-centroid with flips keep a Delaunay start Delaunay: the
    result is not checked unless --check-delaunay asks (is_delaunay null,
    delaunay_checked false); quasi-Delaunay and --no-delaunay results are always
    checked."""
    code, out, err = run(capsys, "refine", square, "--max-area", "1/64", *options, "--json")
    assert code == 0, err
    report = json.loads(out)
    assert report["delaunay_checked"] is checked
    if checked:  # quasi-Delaunay results may be non-Delaunay: checked, not failed
        assert isinstance(report["is_delaunay"], bool)
    else:
        assert report["is_delaunay"] is None
    code, out, _ = run(capsys, "refine", square, "--max-area", "1/64", *options)
    assert code == 0
    assert ("not checked" in out) is not checked


def test_a_non_delaunay_start_is_checked_without_asking(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """The guarantee needs a Delaunay start: from a non-Delaunay input the result is
    checked (and reported false) without --check-delaunay, which alone makes it exit 1."""
    path = tmp_path / "kite.off"
    path.write_text("OFF\n4 2 0\n0 0 0\n4 0 0\n2 1 0\n2 -1 0\n3 0 1 2\n3 1 0 3\n")
    code, out, _ = run(capsys, "refine", path, "--max-area", "100", "--json")
    assert code == 0
    report = json.loads(out)
    assert report["delaunay_checked"] is True and report["is_delaunay"] is False


def test_print_iter_writes_every_step(
    capsys: pytest.CaptureFixture[str], square: Path, tmp_path: Path
) -> None:
    """--print-iter DIR: the input and the mesh after each step, exact OFF files."""
    directory = tmp_path / "steps"
    code, out, _ = run(capsys, "refine", square, "--max-area", "1/16", "--print-iter",
                       directory, "--json")
    assert code == 0
    steps = json.loads(out)["steps"]
    files = sorted(directory.glob("step-*.off"))
    assert len(files) == steps + 1
    last = io.read(files[-1])
    assert isinstance(last, Mesh2) and last.triangle_count == 16
    code, _, err = run(capsys, "refine", square, "--max-area", "1/16", "--print-iter",
                       directory)
    assert code == 2 and "exists" in err


def test_existing_outputs_are_not_replaced_without_force(
    capsys: pytest.CaptureFixture[str], square: Path, tmp_path: Path
) -> None:
    """An existing OUT or trace: exit 2 before any work; --force replaces it."""
    out_path = tmp_path / "out.off"
    out_path.write_text("keep")
    code, _, err = run(capsys, "refine", square, "--max-area", "0.1", "-o", out_path)
    assert code == 2 and out_path.read_text() == "keep"
    one_line_error(err, "exists")
    code, _, _ = run(capsys, "refine", square, "--max-area", "0.1", "-o", out_path, "--force")
    assert code == 0 and out_path.read_text() != "keep"


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["--max-area", "abc"], "cannot read 'abc'"),
        (["--max-area", "-1"], "positive"),
        (["--min-angle", "75", "--method", "centroid"], "between 0 and 60"),
        (["--max-area", "0.1", "--circle", "0", "0", "0"], "radius"),
    ],
)
def test_bad_values_are_one_line_errors(
    capsys: pytest.CaptureFixture[str], square: Path, argv: list[str], fragment: str
) -> None:
    """Unreadable or out-of-range numbers: exit 2, one line on stderr."""
    code, _, err = run(capsys, "refine", square, *argv)
    assert code == 2
    one_line_error(err, fragment)


@pytest.mark.parametrize(
    "argv",
    [[], ["--max-area", "1", "--factor", "0.5"], ["--max-area", "1", "--method", "newest"],
     ["--max-area", "1", "--circle", "0", "0", "1", "--rectangle", "0", "0", "1", "1"]],
)
def test_usage_errors(capsys: pytest.CaptureFixture[str], square: Path,
                      argv: list[str]) -> None:
    """No criterion, a factor with another goal (the goals --min-angle, --max-area and
    --max-edge combine), an unknown method, two regions: usage error, exit 2."""
    code, _, err = run(capsys, "refine", square, *argv)
    assert code == 2
    assert "usage:" in err or "give a goal" in err or "does not combine" in err


def test_a_polygon_mesh_cannot_be_refined(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """A polygon mesh input (a quad face): exit 2."""
    path = tmp_path / "quad.off"
    path.write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    code, _, err = run(capsys, "refine", path, "--max-area", "0.1")
    assert code == 2
    one_line_error(err, "polygon mesh")


def test_factor_and_left_triangles_are_reported(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """--factor halves the mean area; a sharp input corner is reported as left."""
    path = tmp_path / "wedge.poly"
    path.write_text("4 2 0 0\n1 0 0\n2 10 0\n3 12 1\n4 10 1.76\n4 0\n1 1 2\n2 2 3\n3 3 4\n"
                    "4 4 1\n0\n")
    code, out, err = run(capsys, "refine", path, "--min-angle", "25", "--method", "centroid",
                         "--json")
    assert code == 0, err
    report: dict[str, Any] = json.loads(out)
    assert report["left"] and all(0 in triangle for triangle in report["left"])
    assert report["left_reasons"] == ["sharp-corner"] * len(report["left"])
    assert "at a sharp input corner" in err and "protected tip" not in err
    code, out, _ = run(capsys, "refine", path, "--factor", "0.5", "--json")
    assert code == 0
    report = json.loads(out)
    assert mpq(report["total_area"]) / report["triangles"] <= mpq("10.88") / 2 / 2


def _without_provenance(text: str) -> str:
    """A trace file's text without what records the command that ran (its command line,
    options and engine name differ from engine to engine, and so does the header digest
    that covers them)."""
    header, rest = text.split("\n", 1)
    fields = json.loads(header)
    for key in ("command", "options", "engine"):
        del fields["parameters"][key]
    del fields["header_digest"]
    return json.dumps(fields, sort_keys=True) + "\n" + rest


@pytest.mark.parametrize(
    ("criterion", "method"),
    [(["--max-area", "0.5"], "bisection"), (["--factor", "0.1"], "bisection"),
     (["--min-angle", "30"], "centroid")],
)
def test_every_engine_records_the_same_trace(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, criterion: list[str], method: str
) -> None:
    """--engine auto / compiled / python / reference (and the old names fast, transient):
    the same trace and the same mesh, byte for byte (from a PSLG: the triangulation's steps
    included); the compiled kernel runs the minimum angle too (MinAngle)."""
    from geomexact.mesh2d.refinement.engines import compiled as compiled_engine

    source = tmp_path / "pentagon.poly"
    source.write_text(PENTAGON_POLY)
    texts = set()
    engines = ["auto", "python", "reference", "fast", "transient"]
    in_kernel = True  # every criterion here, the minimum angle included, runs in the kernel
    if compiled_engine.AVAILABLE and in_kernel:
        engines.append("compiled")
    for engine in engines:
        out, trace = tmp_path / f"{engine}.off", tmp_path / f"{engine}.jsonl"
        code, _, err = run(capsys, "refine", source, *criterion, "--method", method,
                           "--engine", engine, "-o", out, "--trace", trace, "--exact")
        assert code == 0, err
        texts.add((out.read_text(), _without_provenance(trace.read_text())))
    assert len(texts) == 1
    if not in_kernel or not compiled_engine.AVAILABLE:
        code, _, err = run(capsys, "refine", source, *criterion, "--method", method,
                           "--engine", "compiled")
        assert code == 2
        assert "--engine compiled cannot run this" in err  # the option, not engine=


def test_triangulate_engines_record_the_same_trace(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    source = tmp_path / "pentagon.poly"
    source.write_text(PENTAGON_POLY)
    from geomexact.mesh2d.delaunay import compiled as compiled_delaunay

    texts = set()
    engines = ["auto", "python", "reference", "fast", "transient",
               *(["compiled"] if compiled_delaunay.AVAILABLE else [])]
    for engine in engines:
        trace = tmp_path / f"{engine}.jsonl"
        code, _, err = run(capsys, "triangulate", source, "--engine", engine, "--trace", trace)
        assert code == 0, err
        texts.add(_without_provenance(trace.read_text()))
    assert len(texts) == 1
    code, _, err = run(capsys, "triangulate", source, "--engine", "turbo")
    assert code == 2  # a usage error: argparse's usage, then the problem
    assert "argument --engine: invalid choice: 'turbo'" in err
