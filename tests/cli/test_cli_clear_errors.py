"""Clear errors from the command line (issue 11, section 3): each message names the file
and line of every offending item, and the command-line option (never a Python parameter)
that changes the behaviour; seeds outside the domain are warnings (``check --strict``:
violations); ``replay`` names the input a trace was recorded on."""

from __future__ import annotations

import ast
import json
import re
import tempfile
from pathlib import Path

import pytest
from helpers.io_cases import pslgs
from helpers.paths import SUPERIOR
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geomexact import io, point2
from geomexact.cli import main
from geomexact.cli.errors import OPTION_WORDING, cli_wording
from geomexact.io.trace_file import read_trace
from geomexact.mesh2d.pslg import PSLG

PACKAGE = Path(__file__).resolve().parents[2] / "geomexact"

SQUARE_CORNERS = "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n"
CROSSING_POLY = SQUARE_CORNERS + "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 2 4\n"
THROUGH_POLY = "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 2 0\n1 0\n1 1 2\n"
SEEDS_POLY = (SQUARE_CORNERS + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n"
              "2\n1 10 10\n2 2 2\n1\n1 -5 1 7 -1\n")


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("geomexact: error: "), err
    return lines[0]


def write(directory: Path, name: str, text: str) -> Path:
    path = directory / name
    path.write_text(text)
    return path


# -- triangulate: the file and line of each offending item ------------------------------
def test_crossing_segments_name_both_lines_and_the_crossing(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Was: "segments (0, 2) and (1, 3) meet" (0-based ids, no file, no line, and
    "pass split_segments=True")."""
    path = write(tmp_path, "x.poly", CROSSING_POLY)
    code, _, err = run(capsys, "triangulate", path)
    assert code == 2
    line = one_error_line(err)
    assert (f"{path}:11 and {path}:12: segments 5 (1, 3) and 6 (2, 4) cross at (2, 2)"
            in line)
    assert "use --split-segments" in line and "split_segments=" not in line
    code, _, err = run(capsys, "refine", path, "--max-area", "1")  # triangulates first
    assert code == 2
    line = one_error_line(err)
    assert f"{path}:11 and {path}:12" in line and "triangulate --split-segments" in line
    code, _, _ = run(capsys, "triangulate", path, "--split-segments")
    assert code == 0


def test_a_segment_through_a_vertex_names_both(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = write(tmp_path, "t.poly", THROUGH_POLY)
    code, _, err = run(capsys, "triangulate", path)
    assert code == 2
    assert (f"{path}:7 and {path}:5: segment 1 (1, 2) passes through vertex 4 (2, 0)"
            in one_error_line(err))


def test_duplicate_points_name_both_lines_and_the_option(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Was: "vertex = earlier vertex: 3 = 1; pass merge_duplicates=True (...)"."""
    path = write(tmp_path, "d.node", "4 2 0 0\n0 0 0\n1 1 0\n2 0 1\n3 1 0\n")
    code, _, err = run(capsys, "triangulate", path)
    assert code == 2
    line = one_error_line(err)
    assert f"{path}:5 and {path}:3: vertex 3 repeats vertex 1 (1, 0)" in line
    assert "--merge-duplicates" in line and "merge_duplicates" not in line


def test_collinear_points_name_their_lines(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = write(tmp_path, "c.pslg", "v 0 0\nv 1 1\n# a comment\nv 2 2\n")
    code, _, err = run(capsys, "triangulate", path)
    assert code == 2
    line = one_error_line(err)
    assert f"({path}:1, {path}:2, {path}:4)" in line and "collinear" in line


def test_the_offending_items_listed_are_bounded(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """100 duplicates: ten shown with their lines, then a count (a message stays short)."""
    text = "".join(f"v {k} 0\nv {k} 0\n" for k in range(100)) + "v 0 1\n"
    path = write(tmp_path, "many.pslg", text)
    code, _, err = run(capsys, "triangulate", path)
    assert code == 2
    line = one_error_line(err)
    assert "100 duplicate points" in line and "and 90 more" in line
    assert len(line) < 20 * len(str(path)) + 1000


# -- seeds outside the domain -----------------------------------------------------------
def test_seeds_outside_the_domain_are_warnings_and_strict_check_errors(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Was: silently ignored.  Hole 1 at (10, 10) and the region at (-5, 1) lie in no
    triangle: triangulate warns (stderr, and "warnings" in --json), check exits 0 with the
    warnings, check --strict exits 1 listing them as violations."""
    path = write(tmp_path, "s.poly", SEEDS_POLY)
    code, out, err = run(capsys, "triangulate", path, "--json")
    assert code == 0
    hole = f"{path}:12: hole 1 at (10, 10) is in no triangle"
    region = f"{path}:15: region 1 at (-5, 1) is in no triangle"
    warnings = json.loads(out)["warnings"]
    assert len(warnings) == 2 and warnings[0].startswith(hole)
    assert warnings[1].startswith(region)
    assert f"geomexact: warning: {hole}" in err and f"geomexact: warning: {region}" in err
    code, out, err = run(capsys, "check", path)
    assert code == 0 and "valid" in out and hole in err
    code, out, err = run(capsys, "check", path, "--strict", "--json")
    assert code == 1
    report = json.loads(out)
    assert not report["valid"]
    assert [v["kind"] for v in report["violations"]] == ["ignored-seed", "ignored-seed"]
    code, _, err = run(capsys, "refine", path, "--max-area", "4")
    assert code == 0 and hole in err


def test_check_of_a_pslg_lists_what_triangulate_refuses(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = write(tmp_path, "x.poly", CROSSING_POLY)
    code, out, _ = run(capsys, "check", path)
    assert code == 1
    assert "segments-meet" in out and f"{path}:11 and {path}:12" in out
    code, out, err = run(capsys, "check", SUPERIOR, "--strict")
    assert code == 0 and not err


# -- options, not parameters --------------------------------------------------------------
def test_unknown_extension_names_the_option(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Was: "...; pass format=" (a Python parameter)."""
    path = write(tmp_path, "mesh.xyz", "OFF\n")
    for command in ("info", "check", "triangulate", "view"):
        argv = [command, path] + (["-o", tmp_path / "v.html"] if command == "view" else [])
        code, _, err = run(capsys, *argv)
        assert code == 2
        line = one_error_line(err)
        assert "--format F" in line and "format=" not in line, (command, line)


def _library_strings() -> list[tuple[Path, str]]:
    """Every string constant (f-string parts too) in the library outside ``cli/``."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if "cli" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                found.append((path, node.value))
    return found


def test_every_parameter_hint_of_the_library_has_its_command_line_wording() -> None:
    """A library message that says "pass name=" (or another hint of OPTION_WORDING's form)
    is reworded by the CLI: each such hint is in OPTION_WORDING.  A new hint must be
    added there, with its option."""
    hints = re.compile(r"\bpass ([a-z_]+)=")
    known = {library for library, _ in OPTION_WORDING}
    for path, text in _library_strings():
        for match in hints.finditer(text):
            assert any(text[match.start():].startswith(hint) for hint in known), (
                f"{path.name}: {text!r} has a parameter hint with no command-line wording"
            )


def test_cli_wording_leaves_no_parameter_behind() -> None:
    for library, command in OPTION_WORDING:
        worded = cli_wording(f"problem; {library} to fix it")
        assert library not in worded and command in worded
    assert cli_wording("engine 'compiled' cannot run this") == "--engine compiled cannot run this"


# -- replay: the input the trace was recorded on -----------------------------------------
def test_replay_on_the_wrong_input_names_the_recorded_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Was: "this trace was recorded on a mesh with digest …" (which file?).  A trace
    written by triangulate carries its input's name; given the mesh instead of the PSLG,
    replay names superior.poly and says a triangulation trace replays on the PSLG."""
    mesh, trace = tmp_path / "superior.1.ele", tmp_path / "superior.1.trace.jsonl"
    code, _, err = run(capsys, "triangulate", SUPERIOR, "-o", mesh, "--trace", trace)
    assert code == 0, err
    assert read_trace(trace).input_name == "superior.poly"
    code, _, err = run(capsys, "replay", mesh, trace, "-o", tmp_path / "r.ele")
    assert code == 2
    line = one_error_line(err)
    assert f"{trace} was recorded on 'superior.poly' (digest " in line
    assert f"but {mesh} gives digest" in line and "replays on the PSLG" in line
    code, _, err = run(capsys, "replay", SUPERIOR, trace, "-o", tmp_path / "r.ele")
    assert code == 0, err


def test_old_traces_without_input_name_still_read_and_replay(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    trace = tmp_path / "t.jsonl"
    code, _, _ = run(capsys, "triangulate", SUPERIOR, "--trace", trace)
    assert code == 0
    header, *steps = trace.read_text().splitlines()
    old = json.loads(header)
    del old["input_name"], old["header_digest"]  # neither was written then
    trace.write_text("\n".join([json.dumps(old, sort_keys=True), *steps]) + "\n")
    assert read_trace(trace).input_name == ""
    code, _, err = run(capsys, "replay", SUPERIOR, trace, "-o", tmp_path / "r.ele")
    assert code == 0, err
    mesh = tmp_path / "m.off"
    mesh.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    code, _, err = run(capsys, "replay", mesh, trace, "-o", tmp_path / "r2.ele")
    assert code == 2 and f"{trace} was recorded on (digest " in one_error_line(err)


def test_demo_says_which_trace_replays_on_which_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    directory = tmp_path / "demo"
    code, out, _ = run(capsys, "demo", "-o", directory)
    assert code == 0
    assert "superior.1.trace.jsonl replays on superior.poly" in out
    assert "superior.2.trace.jsonl replays on superior.1.ele" in out
    for trace, source in (("superior.1.trace.jsonl", "superior.poly"),
                          ("superior.2.trace.jsonl", "superior.1.ele")):
        code, _, err = run(capsys, "replay", directory / source, directory / trace,
                           "-o", tmp_path / f"{trace}.ele")
        assert code == 0, err


# -- refine: the reason of each left triangle --------------------------------------------
def test_superior_left_triangle_is_at_a_sharp_corner(
    capsys: pytest.CaptureFixture[str]
) -> None:
    """Lake Superior at 30°: the one left triangle lies at the 15° corner of vertex 125
    (specs/refine.md), reported as such — not as a protected tip or a step limit."""
    code, out, err = run(capsys, "refine", SUPERIOR, "--min-angle", "30", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert len(report["left"]) == 1 and report["left_reasons"] == ["sharp-corner"]
    assert "1 at a sharp input corner" in err
    assert "protected tip" not in err and "step limit" not in err


# -- properties over random PSLGs --------------------------------------------------------
@given(pslgs())
@settings(max_examples=40, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_every_line_a_triangulate_refusal_names_holds_that_item(
    capsys: pytest.CaptureFixture[str], pslg: PSLG
) -> None:
    """Whatever the PSLG, a refusal names only ``file:line`` of vertex or segment lines,
    and the lines of all crossing segments it reports."""
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "p.poly"
        io.write(path, pslg, exact=True)
        lines = path.read_text().split("\n")
        code, _, err = run(capsys, "triangulate", path)
        if code == 0:
            return
        line = one_error_line(err)
    vertex_lines = range(2, 2 + len(pslg.vertices))
    segment_lines = range(3 + len(pslg.vertices), 3 + len(pslg.vertices) + len(pslg.segments))
    named = [int(number) for number in re.findall(re.escape(str(path)) + r":(\d+)", line)]
    if any(word in line for word in ("segments cross", "duplicate points", "collinear")):
        assert named
    for number in named:
        assert number in vertex_lines or number in segment_lines, (number, lines)


@given(pslgs(), st.integers(1, 3))
@settings(max_examples=25, suppress_health_check=[HealthCheck.function_scoped_fixture])
def test_a_seed_far_outside_is_always_a_warning_naming_its_line(
    capsys: pytest.CaptureFixture[str], pslg: PSLG, far: int
) -> None:
    seed = point2(10**6 * far + 7, -999_999)
    outside = PSLG(vertices=pslg.vertices, segments=pslg.segments, holes=(seed,),
                   vertex_markers=pslg.vertex_markers)
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "p.poly"
        io.write(path, outside, exact=True)
        code, _, err = run(capsys, "triangulate", path, "--merge-duplicates",
                           "--split-segments")
    if code != 0:  # e.g. all points collinear: nothing to warn about
        return
    hole_line = 2 + len(pslg.vertices) + 1 + len(pslg.segments) + 1
    assert f"geomexact: warning: {path}:{hole_line}: hole 1 at ({10**6 * far + 7}, -999999)" in err


@pytest.mark.parametrize(("argv", "expected"), [
    (["refine", "x.off", "-q30"], "-q: --min-angle DEG"),
    (["triangulate", "x.poly", "-pq30a0.1"], "-a: --max-area A"),
])
def test_triangle_switches_are_translated(capsys: pytest.CaptureFixture[str],
                                          argv: list[str], expected: str) -> None:
    """Triangle habit (-q30, -pq30a0.1) gets the usage error and a line naming the
    geomexact options (issue 26, item 7)."""
    from geomexact.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "looks like Triangle's switches" in err and expected in err


def test_a_negative_number_is_not_taken_for_a_switch() -> None:
    from geomexact.cli.parser import triangle_switch_hint

    assert triangle_switch_hint(["octree", "--box", "-1", "-2.5", "0", "1", "1", "1"]) is None


def test_triangle_switches_become_a_refine_command() -> None:
    from geomexact.cli.parser import triangle_switch_hint

    hint = triangle_switch_hint(["-pq30a0.01"])
    assert hint is not None
    assert hint.endswith("try: geomexact refine INPUT --min-angle 30 --max-area 0.01")
    hint = triangle_switch_hint(["-pqa"])
    assert hint is not None and hint.endswith("--min-angle 20 --region-areas")
    hint = triangle_switch_hint(["-pc"])
    assert hint is not None and "try:" not in hint
