"""``geomexact trace show / diff / bisect`` on real traces (the demo's, a bisection
refinement of a square, cuboid traces) and on planted faults; and the provenance every
trace written by a command records."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest
from helpers.trace_faults import planted_trace

from geomexact import io, mesh_from_triangles
from geomexact.cli import main
from geomexact.io.trace_file import read_trace, write_trace
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace

SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"
SHOW_KEYS = {"trace", "format", "format_version", "geomexact", "input_name", "input_digest",
             "final_digest", "dimension", "parameters", "steps", "operations",
             "header_checked", "checked_steps", "unchecked_steps", "check_note"}
DIFF_KEYS = {"input", "a", "b", "input_digest", "steps_a", "steps_b", "identical",
             "first_difference", "common_steps", "prefix", "longer", "step_a", "step_b",
             "digest_a", "digest_b", "cells", "only_in_a", "only_in_b", "picture",
             "picture_highlights"}
BISECT_KEYS = {"input", "trace", "check", "dimension", "steps", "failing_step",
               "failed_at_start", "holds", "checks", "check_bound", "step", "cells",
               "removed", "added", "written"}


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, Any]:
    code, out, err = run(capsys, *argv, "--json")
    assert out, err
    return code, json.loads(out)


def one_error(err: str, *fragments: str) -> str:
    lines = err.strip().splitlines()
    assert lines and lines[-1].startswith("geomexact: error: "), err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[-1], lines[-1]
    return lines[-1]


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("demo") / "out"
    assert main(["demo", "-o", str(directory)]) == 0
    return directory


@pytest.fixture(scope="module")
def square_run() -> Any:
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    return refine(square, MaxArea("0.002"), method="bisection")


@pytest.fixture
def square(tmp_path: Path) -> Path:
    path = tmp_path / "square.off"
    path.write_text(SQUARE_OFF)
    return path


@pytest.fixture
def refined(capsys: pytest.CaptureFixture[str], square: Path) -> Path:
    """The trace of ``refine square.off --max-area 0.002 --method bisection``."""
    trace = square.parent / "square.trace.jsonl"
    code, _, err = run(capsys, "refine", square, "--max-area", "0.002", "--method",
                       "bisection", "--trace", trace)
    assert code == 0, err
    return trace


def written_trace(path: Path, trace: Trace) -> Path:
    write_trace(path, trace)
    return path


# -- provenance ---------------------------------------------------------------------------
def test_refine_traces_record_the_command_options_and_engine(
    capsys: pytest.CaptureFixture[str], square: Path
) -> None:
    trace_path = square.parent / "run.trace.jsonl.gz"
    argv = ["refine", str(square), "--max-area", "1/8", "--method", "bisection",
            "--engine", "python", "--trace", str(trace_path)]
    assert main(argv) == 0
    capsys.readouterr()
    trace = read_trace(trace_path)
    assert trace.parameter("command") == ["geomexact", *argv]
    assert trace.parameter("engine") == "python"
    options = trace.parameter("options")
    assert options["method"] == "bisection" and options["engine"] == "python"
    assert options["trace"] == str(trace_path) and "run" not in options
    assert trace.input_name == "square.off"
    again = square.parent / "again.trace.jsonl.gz"
    assert main([*argv[:-1], str(again)]) == 0
    capsys.readouterr()
    assert read_trace(again).steps == trace.steps  # same run, same steps (gzip included)


def test_demo_traces_name_their_input_and_the_run(demo: Path) -> None:
    first, second = (read_trace(demo / f"superior.{k}.trace.jsonl") for k in (1, 2))
    assert first.input_name == "superior.poly" and second.input_name == "superior.1.ele"
    assert second.parameter("command")[:2] == ["geomexact", "demo"]
    assert second.parameter("engine") == "auto"


# -- show ---------------------------------------------------------------------------------
def test_show_prints_the_header_and_operation_counts(
    capsys: pytest.CaptureFixture[str], demo: Path
) -> None:
    path = demo / "superior.2.trace.jsonl"
    trace = read_trace(path)
    code, report = run_json(capsys, "trace", "show", path)
    assert code == 0 and set(report) == SHOW_KEYS
    assert report["steps"] == len(trace) and report["dimension"] == 2
    assert sum(report["operations"].values()) == len(trace)
    assert report["input_name"] == "superior.1.ele"
    assert report["parameters"]["command"][:2] == ["geomexact", "demo"]
    code, out, _ = run(capsys, "trace", "show", path)
    assert code == 0
    assert f"steps         {len(trace)}" in out and "superior.1.ele, digest" in out
    assert "command               geomexact demo -o" in out


def test_show_steps_finds_the_input_beside_the_trace(
    capsys: pytest.CaptureFixture[str], demo: Path
) -> None:
    path = demo / "superior.2.trace.jsonl"
    trace = read_trace(path)
    code, report = run_json(capsys, "trace", "show", path, "--steps", "1-3")
    assert code == 0 and report["cells_from"] == "beside"
    assert [entry["step"] for entry in report["shown"]] == [1, 2, 3]
    first = report["shown"][0]
    assert first["op"] == trace.steps[0].op
    assert first["digest"] == f"{trace.digests[0]:032x}"
    assert all(isinstance(a, int) or "/" in a for a in first["args"])  # p/q rationals
    start = io.read(demo / "superior.1.ele")
    assert set(map(tuple, first["removed"])) <= set(start.triangles())
    assert len(first["added"]) == len(first["removed"]) + 2  # a point inserted
    code, out, _ = run(capsys, "trace", "show", path, "--step", "2")
    assert code == 0 and "step 2: flip" in out and "removed  2 triangles:" in out


def test_show_a_bisection_step_removes_two_and_adds_four(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path
) -> None:
    code, report = run_json(capsys, "trace", "show", refined, "--step", "1",
                            "--input", square)
    assert code == 0 and report["cells_from"] == "input" and report["cells"] == "triangles"
    (step,) = report["shown"]
    assert step["op"] == "bisect" and sorted(step["args"]) == [0, 2]  # the diagonal
    assert len(step["removed"]) == 2 and len(step["added"]) == 4
    assert sorted(map(tuple, step["removed"])) == [(0, 1, 2), (0, 2, 3)]


def test_show_without_its_input_says_give_input(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path, tmp_path: Path
) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    moved = elsewhere / refined.name
    refined.rename(moved)
    code, out, _ = run(capsys, "trace", "show", moved, "--step", "1")
    assert code == 0 and "step 1: bisect" in out
    assert "cells not shown: its input square.off is not beside it; give --input" in out
    code, report = run_json(capsys, "trace", "show", moved, "--step", "1")
    assert report["cells"] is None and "give --input" in report["cells_note"]
    assert "removed" not in report["shown"][0]
    # a wrong --input is refused
    other = tmp_path / "other.off"
    other.write_text(SQUARE_OFF.replace("1 1 0", "2 2 0"))
    code, _, err = run(capsys, "trace", "show", moved, "--step", "1", "--input", other)
    assert code == 2 and "not the trace's input" in one_error(err)


def test_show_steps_out_of_range_is_a_clear_error(
    capsys: pytest.CaptureFixture[str], refined: Path
) -> None:
    total = len(read_trace(refined))
    code, _, err = run(capsys, "trace", "show", refined, "--steps", f"5-{total + 1}")
    assert code == 2
    one_error(err, f"--steps 5-{total + 1}", f"has {total} steps (1..{total})")
    for bad in ("0-3", "4-2", "x"):
        code, _, err = run(capsys, "trace", "show", refined, "--steps", bad)
        assert code == 2 and "Traceback" not in err and "--steps" in err
    code, _, err = run(capsys, "trace", "show", refined, "--step", "0")
    assert code == 2 and "Traceback" not in err


def test_show_a_cuboid_trace_rebuilds_its_start(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "cuboid.trace.jsonl.gz"
    assert main(["cuboid", "262143", "--trace", str(path)]) == 0
    capsys.readouterr()
    code, report = run_json(capsys, "trace", "show", path, "--steps", "1-2")
    assert code == 0 and report["dimension"] == 3 and report["cells_from"] == "rebuilt"
    assert report["cells"] == "tetrahedra" and report["operations"] == {"split_tetra": 18}
    for step in report["shown"]:
        assert len(step["added"]) == 2 * len(step["removed"])  # a tetrahedron split: 1 -> 2


def test_show_a_malformed_trace_names_file_and_line(
    capsys: pytest.CaptureFixture[str], refined: Path
) -> None:
    lines = refined.read_text().splitlines()
    lines[3] = lines[3].replace('"op"', '"oops"')
    refined.write_text("\n".join(lines) + "\n")
    code, _, err = run(capsys, "trace", "show", refined)
    assert code == 2 and f"{refined}:4:" in one_error(err)


# -- diff ---------------------------------------------------------------------------------
def test_diff_of_identical_traces_says_so(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path
) -> None:
    code, out, _ = run(capsys, "trace", "diff", square, refined, refined)
    assert code == 0 and "are identical" in out
    code, report = run_json(capsys, "trace", "diff", square, refined, refined)
    assert code == 0 and set(report) == DIFF_KEYS and report["identical"] is True


def test_diff_of_a_prefix_says_which_is_longer(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path
) -> None:
    coarse = square.parent / "coarse.jsonl"
    assert main(["refine", str(square), "--max-area", "0.01", "--method", "bisection",
                 "--trace", str(coarse)]) == 0
    capsys.readouterr()
    short, long = len(read_trace(coarse)), len(read_trace(refined))
    assert short < long
    code, out, _ = run(capsys, "trace", "diff", square, coarse, refined)
    assert code == 1
    assert f"{coarse} is a prefix of {refined}" in out and f"{long} steps" in out
    code, report = run_json(capsys, "trace", "diff", square, refined, coarse)
    assert report["prefix"] is True and report["longer"] == "a"
    assert report["first_difference"] == short + 1 and report["common_steps"] == short


def test_diff_finds_the_step_where_a_planted_change_parts(
    capsys: pytest.CaptureFixture[str], square: Path, square_run: Any, tmp_path: Path
) -> None:
    at = 40
    start, planted, at = planted_trace(square_run, at)
    assert start.digest == io.read(square).digest
    a = written_trace(tmp_path / "a.jsonl", square_run.trace)
    b = written_trace(tmp_path / "b.jsonl.gz", planted)
    picture = tmp_path / "diff.png"
    code, report = run_json(capsys, "trace", "diff", square, a, b, "--picture", picture)
    assert code == 1 and set(report) == DIFF_KEYS
    assert report["first_difference"] == at + 1 and report["common_steps"] == at
    assert report["step_a"]["op"] == square_run.trace.steps[at].op
    assert report["step_b"]["op"] == "flip"
    assert report["digest_a"] == f"{square_run.trace.digests[at]:032x}"
    assert report["digest_b"] == f"{planted.digests[at]:032x}"
    after_a = replay(start, square_run.trace, until=at + 1)
    after_b = replay(start, planted, until=at + 1)
    assert {tuple(c) for c in report["only_in_a"]} == set(after_a.triangles()) - set(
        after_b.triangles())
    assert report["only_in_b"] and report["picture_highlights"] is True
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, out, _ = run(capsys, "trace", "diff", square, a, b)
    assert code == 1 and f"agree on {at} steps and differ at step {at + 1}" in out
    # the picture is not replaced without --force
    code, _, err = run(capsys, "trace", "diff", square, a, b, "--picture", picture)
    assert code == 2 and "refusing to overwrite" in one_error(err)


def test_diff_of_two_cuboid_orders_draws_both_3d_meshes(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    start, a, b = tmp_path / "start.ele", tmp_path / "a.jsonl", tmp_path / "b.jsonl"
    assert main(["cuboid", "262143", "--start", str(start), "--trace", str(a)]) == 0
    assert main(["cuboid", "262143", "--order", "index", "--trace", str(b)]) == 0
    capsys.readouterr()
    picture = tmp_path / "cuboid.png"
    code, out, _ = run(capsys, "trace", "diff", start, a, b, "--picture", picture)
    assert code == 1 and "differ at step 1" in out and "tetrahedra only in" in out
    assert "3D pictures cannot highlight" in out and picture.exists()


def test_diff_refuses_traces_of_different_inputs_and_a_wrong_input(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path, tmp_path: Path
) -> None:
    triangle = tmp_path / "triangle.off"
    triangle.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    other = tmp_path / "other.jsonl"
    assert main(["refine", str(triangle), "--max-area", "0.1", "--trace", str(other)]) == 0
    capsys.readouterr()
    code, _, err = run(capsys, "trace", "diff", square, refined, other)
    assert code == 2
    one_error(err, "were recorded on different inputs", "square.off", "triangle.off")
    code, _, err = run(capsys, "trace", "diff", triangle, refined, refined)
    assert code == 2 and "not the trace's input" in one_error(err)


# -- bisect -------------------------------------------------------------------------------
def test_bisect_finds_a_planted_fault_in_log_checks(
    capsys: pytest.CaptureFixture[str], square: Path, square_run: Any, tmp_path: Path
) -> None:
    for at in (17, 100, len(square_run.trace) - 30):
        start, planted, at = planted_trace(square_run, at)
        path = written_trace(tmp_path / f"planted-{at}.jsonl.gz", planted)
        code, report = run_json(capsys, "trace", "bisect", square, path, "--fails",
                                "delaunay")
        assert code == 1 and set(report) == BISECT_KEYS
        assert report["failing_step"] == at + 1 and report["step"]["op"] == "flip"
        assert report["checks"] <= math.ceil(math.log2(len(planted))) + 2
        assert report["check_bound"] == math.ceil(math.log2(len(planted))) + 2
        assert len(report["removed"]) == 2 and len(report["added"]) == 2
        assert not is_delaunay(replay(start, planted, until=at + 1))


def test_bisect_writes_the_meshes_around_the_step_and_a_picture(
    capsys: pytest.CaptureFixture[str], square: Path, square_run: Any, tmp_path: Path
) -> None:
    at = 60
    start, planted, at = planted_trace(square_run, at)
    path = written_trace(tmp_path / "planted.jsonl", planted)
    out_dir = tmp_path / "found"
    code, out, err = run(capsys, "trace", "bisect", square, path, "--fails", "delaunay",
                         "-o", out_dir)
    assert code == 1, err
    assert f"delaunay holds after step {at} and fails after step {at + 1}" in out
    k = at + 1
    before = io.read(out_dir / f"before-step-{k}.ele")
    after = io.read(out_dir / f"after-step-{k}.ele")
    assert isinstance(before, Mesh2)
    assert before.digest == replay(start, planted, until=at).digest  # lossless
    assert after.digest == replay(start, planted, until=k).digest
    assert (out_dir / f"step-{k}.png").read_bytes()[:4] == b"\x89PNG"
    code, _, err = run(capsys, "trace", "bisect", square, path, "--fails", "delaunay",
                       "-o", out_dir)
    assert code == 2 and "refusing to overwrite" in one_error(err)
    code, _, _ = run(capsys, "trace", "bisect", square, path, "--fails", "delaunay",
                     "-o", out_dir, "--force")
    assert code == 1


def test_bisect_named_checks_on_a_refinement(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path
) -> None:
    for check in ("valid", "delaunay", "area", "min-angle:30", "min-angle:44.9"):
        code, report = run_json(capsys, "trace", "bisect", square, refined, "--fails", check)
        assert code == 0 and report["holds"] is True, check
        assert report["checks"] == 2
    code, report = run_json(capsys, "trace", "bisect", square, refined, "--fails",
                            "min-angle:50")
    assert code == 1 and report["failed_at_start"] is True and report["checks"] == 1


def test_bisect_a_user_check(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path, tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "my_checks_17.py").write_text(
        "def few(mesh):\n    return mesh.triangle_count < 50\n"
        "def broken(mesh):\n    raise RuntimeError('oops')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    trace = read_trace(refined)
    start = io.read(square)
    expected = next(k for k in range(1, len(trace) + 1)
                    if replay(start, trace, until=k).triangle_count >= 50)
    code, report = run_json(capsys, "trace", "bisect", square, refined, "--fails",
                            "my_checks_17:few")
    assert code == 1 and report["failing_step"] == expected
    code, _, err = run(capsys, "trace", "bisect", square, refined, "--fails",
                       "my_checks_17:broken")
    assert code == 2 and "raised RuntimeError: oops" in one_error(err)
    code, _, err = run(capsys, "trace", "bisect", square, refined, "--fails",
                       "my_checks_17:missing")
    assert code == 2 and "has no function missing" in one_error(err)
    code, _, err = run(capsys, "trace", "bisect", square, refined, "--fails",
                       "no_such_module_17:f")
    assert code == 2 and "cannot import no_such_module_17" in one_error(err)


def test_bisect_a_cuboid_trace_without_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "cuboid.jsonl"
    assert main(["cuboid", "262143", "--improve", "--trace", str(path)]) == 0
    capsys.readouterr()
    for check in ("volume", "conforming", "valid"):
        code, report = run_json(capsys, "trace", "bisect", path, "--fails", check)
        assert code == 0 and report["holds"] is True and report["dimension"] == 3
    (tmp_path / "cuboid_checks_17.py").write_text(
        "def few(mesh):\n    return mesh.tetrahedron_count < 20\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    code, report = run_json(capsys, "trace", "bisect", path, "--fails",
                            "cuboid_checks_17:few", "-o", tmp_path / "out")
    assert code == 1 and report["cells"] == "tetrahedra"
    k = report["failing_step"]
    after = io.read(tmp_path / "out" / f"after-step-{k}.ele")
    before = io.read(tmp_path / "out" / f"before-step-{k}.ele")
    assert after.tetrahedron_count >= 20 > before.tetrahedron_count
    for check, word in (("area", "for a 3D trace use --fails volume"),
                        ("min-angle:30", "triangle meshes (2D)")):
        code, _, err = run(capsys, "trace", "bisect", path, "--fails", check)
        assert code == 2 and word in one_error(err)


def test_bisect_bad_checks_and_inputs_are_clear_errors(
    capsys: pytest.CaptureFixture[str], square: Path, refined: Path
) -> None:
    for check, fragment in (("bogus", "unknown check"), ("min-angle:70", "between 0 and 60"),
                            ("min-angle:x", "not an exact number"),
                            ("volume", "2D trace use --fails area"),
                            ("conforming", "--fails valid")):
        code, _, err = run(capsys, "trace", "bisect", square, refined, "--fails", check)
        assert code == 2 and fragment in one_error(err), check
    code, _, err = run(capsys, "trace", "bisect", refined, "--fails", "valid")
    assert code == 2 and "give the INPUT mesh" in one_error(err)


def test_a_trace_that_diverges_exits_1_naming_the_step(
    capsys: pytest.CaptureFixture[str], square: Path, square_run: Any, tmp_path: Path
) -> None:
    digests = list(square_run.trace.digests)
    digests[9] ^= 1
    broken = Trace(square_run.trace.input_digest, square_run.trace.steps, digests)
    path = written_trace(tmp_path / "broken.jsonl", broken)
    code, _, err = run(capsys, "trace", "show", path, "--input", square, "--steps", "8-12")
    assert code == 1 and "trace diverged" in err and "step 10" in err
    assert "Traceback" not in err
    code, report = run_json(capsys, "trace", "bisect", square, path, "--fails", "valid")
    assert code == 1 and report["diverged"] is True and report["step"] == 10


# -- the header's digest, and the steps show checked ---------------------------------------
@pytest.mark.parametrize(("field", "value"), [
    ("command", ["geomexact", "refine", "other.off", "--max-area", "0.5"]),
    ("options", {"max_area": "0.5"}),
    ("engine", "python"),
])
def test_a_changed_header_is_refused(capsys: pytest.CaptureFixture[str], refined: Path,
                                     field: str, value: Any) -> None:
    header, rest = refined.read_text().split("\n", 1)
    record = json.loads(header)
    record["parameters"][field] = value
    refined.write_text(json.dumps(record, sort_keys=True, separators=(",", ":")) + "\n" + rest)
    for argv in (["trace", "show", refined],
                 ["replay", refined.parent / "square.off", refined, "-o",
                  refined.parent / "r.off"]):
        code, out, err = run(capsys, *argv)
        assert code == 2 and out == ""
        assert one_error(err) == (f"geomexact: error: {refined}:1: the header was changed "
                                  "after the trace was written (its header_digest does not "
                                  "match its fields)")


def test_the_header_digest_covers_the_input_name(capsys: pytest.CaptureFixture[str],
                                                 refined: Path) -> None:
    text = refined.read_text()
    assert text.count('"input_name":"square.off"') == 1
    refined.write_text(text.replace('"input_name":"square.off"', '"input_name":"other.off"'))
    code, _, err = run(capsys, "trace", "show", refined)
    assert code == 2
    one_error(err, f"{refined}:1: the header was changed after the trace was written")


def test_a_header_reformatted_but_unchanged_reads(capsys: pytest.CaptureFixture[str],
                                                  refined: Path) -> None:
    header, rest = refined.read_text().split("\n", 1)
    refined.write_text(json.dumps(json.loads(header), indent=None) + "\n" + rest)  # spaces
    code, report = run_json(capsys, "trace", "show", refined)
    assert code == 0 and report["header_checked"] is True


def test_an_old_header_without_its_digest_reads_unchecked(capsys: pytest.CaptureFixture[str],
                                                          refined: Path) -> None:
    header, rest = refined.read_text().split("\n", 1)
    record = json.loads(header)
    del record["header_digest"]
    refined.write_text(json.dumps(record, sort_keys=True) + "\n" + rest)
    code, report = run_json(capsys, "trace", "show", refined)
    assert code == 0 and report["header_checked"] is False
    code, out, _ = run(capsys, "trace", "show", refined)
    assert "  header        not covered by a digest (a trace written before header_digest)" \
        in out.splitlines()


def _tampered_at(path: Path, k: int) -> None:
    """Replace the digest recorded after step ``k`` by another."""
    lines = path.read_text().splitlines()
    record = json.loads(lines[k])
    assert record["i"] == k
    record["digest"] = "0" * 32
    lines[k] = json.dumps(record, sort_keys=True, separators=(",", ":"))
    path.write_text("\n".join(lines) + "\n")


def test_show_steps_says_which_steps_it_did_not_check(capsys: pytest.CaptureFixture[str],
                                                      refined: Path) -> None:
    _tampered_at(refined, 40)
    total = len(read_trace(refined))
    code, report = run_json(capsys, "trace", "show", refined, "--steps", "1-3")
    assert code == 0
    assert (report["checked_steps"], report["unchecked_steps"]) == (3, total - 3)
    hint = (f"steps 4-{total} not replayed, their digests not checked: geomexact trace show "
            f"{refined} --check (or geomexact replay) checks them")
    assert report["check_note"] == hint
    code, out, _ = run(capsys, "trace", "show", refined, "--steps", "1-3")
    assert code == 0
    assert out.splitlines()[-1] == f"checked: steps 1-3 replay as recorded; {hint}"


def test_show_check_replays_every_step(capsys: pytest.CaptureFixture[str], refined: Path,
                                       square: Path) -> None:
    total = len(read_trace(refined))
    code, report = run_json(capsys, "trace", "show", refined, "--check")
    assert code == 0 and report["checked_steps"] == total and report["check_note"] is None
    _tampered_at(refined, 40)
    for extra in ([], ["--steps", "1-3"], ["--input", square]):
        code, out, err = run(capsys, "trace", "show", refined, "--check", *extra)
        assert code == 1 and out == ""
        assert err.startswith(f"geomexact: trace diverged: {refined}: step 40 (")
    lone = refined.parent / "lone"
    lone.mkdir()
    (lone / refined.name).write_bytes(refined.read_bytes())
    code, _, err = run(capsys, "trace", "show", lone / refined.name, "--check")
    assert code == 2
    one_error(err, "--check replays", "give --input INPUT")
