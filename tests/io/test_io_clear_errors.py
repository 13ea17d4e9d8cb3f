"""Clear reader errors (issue 11, section 3): quotes of at most ~200 characters, "expected N
vertices, found M" for a count larger than the file, the Triangle reading of ``.poly``
hole and region headers, huge integers, and streamed reading that stops at the first bad
line in bounded memory."""

from __future__ import annotations

import tempfile
import time
import tracemalloc
from pathlib import Path

import pytest
from helpers.io_cases import grid_meshes, pslgs, write
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import io
from geomexact.errors import FormatError
from geomexact.io.registry import QUOTE_LIMIT, quoted, quoted_tokens
from geomexact.io.trace_file import read_trace
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2

LONG = "9" * 10_000_000  # a 10 MB token


def read_error(path: Path) -> FormatError:
    with pytest.raises(FormatError) as caught:
        io.read(path)
    return caught.value


# -- quoting -----------------------------------------------------------------------------
def test_quoted_keeps_short_text_and_clips_long_text() -> None:
    assert quoted("1 2 x") == "'1 2 x'"
    long = quoted("a" * 1000)
    assert long.startswith("'" + "a" * QUOTE_LIMIT + "'…") and "1,000 characters" in long
    assert quoted_tokens(["a"] * 1000).endswith("(1,999 characters)")


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("long.off", f"OFF\n3 1 0\n0 0 0\n1 0 0 {LONG} {LONG}\n"),  # a vertex line: fields
        ("long.node", f"3 2 0 0\n0 0 0\n1 {LONG}x 0\n"),  # an unparsable number
        ("long.poly", f"3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n0 0 1 {LONG}\n"),
        ("long.pslg", f"v 0 0\n{LONG}q\n"),  # an unknown record tag
        ("long.txt", f"0 0 1 0 0 1 {LONG}\n"),  # a triangle line with 7 fields
        ("long2.off", f"OFF\n3 1 0\n0 0 {LONG}1\n"),  # a huge z
        ("long3.off", f"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 {LONG}\n"),  # a huge index
    ],
)
def test_a_huge_line_is_quoted_in_at_most_about_200_characters(
    tmp_path: Path, name: str, text: str
) -> None:
    """Was: the whole line in the message (a 100 MB line gave a 100 MB message)."""
    error = read_error(write(tmp_path, name, text))
    assert error.line is not None
    assert len(error.problem) < 3 * QUOTE_LIMIT + 200, error.problem[:500]


def test_a_huge_trace_value_is_quoted_briefly(tmp_path: Path) -> None:
    path = write(tmp_path, "t.jsonl", f'{{"format": "{LONG}"}}\n')
    with pytest.raises(FormatError) as caught:
        read_trace(path)
    assert len(str(caught.value)) < 600


def test_a_bad_rational_step_argument_reads_as_any_bad_number(tmp_path: Path) -> None:
    """A step's string argument is parsed like every number of a file: the message names
    it, quotes the token and gives the parser's reason."""
    header = ('{"format":"geomexact-trace","geomexact":"0","input_digest":"' + "0" * 32
              + '","parameters":{},"steps":1,"version":1}\n')
    step = '{"i":1,"op":"flip","args":[0,"1/x"],"digest":"' + "0" * 32 + '"}\n'
    path = write(tmp_path, "t.jsonl", header + step)
    with pytest.raises(FormatError) as caught:
        read_trace(path)
    assert caught.value.line == 2
    assert caught.value.problem.startswith("step argument: cannot read '1/x' as a number: ")


# -- counts larger (or smaller) than the file --------------------------------------------
@pytest.mark.parametrize(
    ("name", "text", "line", "fragment"),
    [
        # was: "vertex 3 has z = 1; only planar meshes ..." on the first face line
        ("v.off", "OFF\n5 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6,
         "expected 5 vertices, found 3: this line is not one of them ('3 0 1 2' is a face); "
         "is the count on line 2 right?"),
        # was: "the file ends before vertex 3 (of 5)"
        ("v2.off", "OFF\n5 0 0\n0 0 0\n1 0 0\n0 1 0\n", 5, "expected 5 vertices, found 3"),
        ("f.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6, "expected 3 faces, found 1"),
        # a vertex count too small: a vertex line read as a face
        ("s.off", "OFF\n2 1 0\n0 0 0\n1 0 0\n0.5 1 0\n3 0 1 2\n", 5,
         "face 0: '0.5 1 0' is a vertex, but the header (line 2) announces 2 vertices"),
        # was: "a vertex line 'number x y' needs 3 fields, found 2: '3 0'"
        ("v.poly", "5 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n", 5,
         "expected 5 vertices, found 3: this line is not one of them ('3 0' is the segment "
         "header 'count markers'); is the count on line 1 right?"),
        ("s.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 0\n1 1 2\n2 2 3\n3 3 1\n0\n", 9,
         "expected 4 segments, found 3"),
        ("h.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n2\n1 0.1 0.1\n0\n", 8,
         "expected 2 holes, found 1"),
        ("r.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n2\n1 0.1 0.1 1\n", 8,
         "expected 2 regions, found 1"),
        ("n.node", "4 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", 4, "expected 4 vertices, found 3"),
    ],
)
def test_a_count_larger_than_the_file_says_expected_and_found(
    tmp_path: Path, name: str, text: str, line: int, fragment: str
) -> None:
    error = read_error(write(tmp_path, name, text))
    assert error.line == line
    assert fragment in error.problem


def test_a_vertex_line_missing_a_field_is_not_taken_for_the_next_section(
    tmp_path: Path,
) -> None:
    """Only a line of the next header's shape ends the vertices: a vertex line short of a
    field stays a field-count error."""
    error = read_error(write(tmp_path, "m.poly", "3 2 0 1\n1 0 0 1\n2 1 0\n3 0 1 1\n0 0\n"))
    assert error.line == 3 and "needs 4 fields, found 3" in error.problem


def test_ele_count_larger_than_the_file(tmp_path: Path) -> None:
    write(tmp_path, "m.node", "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n")
    write(tmp_path, "m.ele", "3 3 0\n0 0 1 2\n1 0 2 3\n")
    error = read_error(tmp_path / "m.ele")
    assert error.line == 3 and "expected 3 triangles, found 2" in error.problem


# -- .poly holes and regions read as Triangle reads them ---------------------------------
def test_region_and_hole_headers_with_extra_fields_read_as_triangle(tmp_path: Path) -> None:
    """Triangle reads only the first number of a hole or region header, and the first 3
    (hole) or 5 (region) fields of their lines.  Was: "the region header 'count' needs 1
    fields, found 2"."""
    path = write(
        tmp_path, "x.poly",
        "3 2 0 0\n1 0 0\n2 4 0\n3 0 4\n3 0\n1 1 2\n2 2 3\n3 3 1\n"
        "1 0 # holes, then a stray field\n1 1 1 extra\n"
        "2 1 # regions\n1 0.5 0.5 7 0.25 junk\n2 0.25 0.25 8\n",
    )
    value, notes = io.read_with_notes(path)
    assert isinstance(value, PSLG)
    assert len(value.holes) == 1 and [r.attribute for r in value.regions] == [7, 8]
    assert value.regions[0].max_area == 0.25 and value.regions[1].max_area is None
    assert any("ignored the fields after the ones Triangle reads" in n for n in notes)


# -- numbers ----------------------------------------------------------------------------
def test_an_integer_too_long_for_int_is_too_large_not_garbage(tmp_path: Path) -> None:
    """Was: "'999…' is not an integer" (int() refuses more than 4300 digits)."""
    error = read_error(write(tmp_path, "big.off", f"OFF\n{'9' * 5000} 1 0\n"))
    assert error.line == 2 and "is too large (5,000 digits)" in error.problem


# -- streaming: stop at the first bad line, in bounded memory ----------------------------
SIZE = 20_000_000


def _big(path: Path, head: str, line: str, size: int = SIZE) -> Path:
    """``head`` then ``line`` repeated to about ``size`` bytes."""
    with path.open("w", encoding="utf-8") as handle:
        handle.write(head)
        handle.write(line * (size // len(line)))
    return path


def _peak_of_failing_read(path: Path) -> tuple[float, int, FormatError]:
    tracemalloc.start()
    began = time.perf_counter()
    try:
        with pytest.raises(FormatError) as caught:
            io.read(path)
        seconds = time.perf_counter() - began
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return seconds, peak, caught.value


@pytest.mark.parametrize(
    ("name", "head", "line", "bad_line"),
    [
        # a bad vertex near the start of a 20 MB OFF (was: 20 MB read, split and held)
        ("v.off", "OFF\n1000000 1 0\n0 0 0\n1 x 0\n", "0.5 0.5 0\n", 4),
        # the first triangle degenerate, a million faces after it (was: every face read
        # before the orientation check failed on the first one)
        ("f.off", "OFF\n3 1000000 0\n0 0 0\n1 0 0\n2 0 0\n", "3 0 1 2\n", 6),
        ("v.node", "1000000 2 0 0\n0 0 0\n1 0 0 0\n", "2 0.5 0.5\n", 3),
        ("t.txt", "0 0 1 0 2 0\n", "0 0 1 0 0 1\n", 1),
        ("r.pslg", "v 0 0\nq\n", "v 0.5 0.5\n", 2),
    ],
)
def test_a_large_file_fails_fast_at_an_early_bad_line_in_bounded_memory(
    tmp_path: Path, name: str, head: str, line: str, bad_line: int
) -> None:
    path = _big(tmp_path / name, head, line)
    seconds, peak, error = _peak_of_failing_read(path)
    assert error.line == bad_line
    assert seconds < 2.0, seconds
    assert peak < 2_000_000, peak  # bytes: a few lines, never the 20 MB text


def test_a_large_ele_fails_at_its_first_degenerate_triangle(tmp_path: Path) -> None:
    write(tmp_path, "m.node", "3 2 0 0\n0 0 0\n1 1 0\n2 2 0\n")
    path = _big(tmp_path / "m.ele", "1000000 3 0\n0 0 1 2\n", "1 0 1 2\n")
    seconds, peak, error = _peak_of_failing_read(path)
    assert error.line == 2 and "degenerate" in error.problem
    assert seconds < 2.0 and peak < 2_000_000


def test_a_large_trace_fails_at_an_early_bad_line(tmp_path: Path) -> None:
    header = ('{"format":"geomexact-trace","geomexact":"0","input_digest":"' + "0" * 32
              + '","parameters":{},"steps":1,"version":1}\n')
    path = _big(tmp_path / "t.jsonl", header + "not json\n", '{"i": 2}\n')
    tracemalloc.start()
    try:
        with pytest.raises(FormatError) as caught:
            read_trace(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert caught.value.line == 2 and peak < 2_000_000


# -- properties: each class of problem, on random valid files ----------------------------
@given(pslgs(), st.integers(1, 5), st.sampled_from(["p.poly", "p.node"]))
@settings(max_examples=30)
def test_any_vertex_count_too_large_says_expected_and_found(
    pslg: PSLG, extra: int, name: str
) -> None:
    """Whatever the file, a header announcing ``extra`` more vertices than it lists is
    "expected N vertices, found M" (at the segment header, or at the end of the file)."""
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / name
        io.write(path, pslg, exact=True)
        lines = path.read_text().split("\n")
        count, rest = lines[0].split(" ", 1)
        lines[0] = f"{int(count) + extra} {rest}"
        path.write_text("\n".join(lines))
        with pytest.raises(FormatError) as caught:
            io.read(path)
    found = len(pslg.vertices)
    assert f"expected {found + extra} vertices, found {found}" in caught.value.problem


@given(grid_meshes(extras=False), st.integers(1, 5))
@settings(max_examples=20)
def test_any_off_vertex_count_too_large_says_expected_and_found(mesh: Mesh2, extra: int) -> None:
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "m.off"
        io.write(path, mesh, exact=True)
        lines = path.read_text().split("\n")
        vertices, faces, edges = lines[1].split()
        lines[1] = f"{int(vertices) + extra} {faces} {edges}"
        path.write_text("\n".join(lines))
        with pytest.raises(FormatError) as caught:
            io.read(path)
    assert (f"expected {mesh.vertex_count + extra} vertices, found {mesh.vertex_count}"
            in caught.value.problem)


@given(pslgs(), st.lists(st.sampled_from(["0", "x", "1.5", "#"]), min_size=1, max_size=3))
@settings(max_examples=30)
def test_extra_fields_after_hole_and_region_fields_change_nothing(
    pslg: PSLG, extra: list[str]
) -> None:
    """Triangle's reading: fields after a hole or region header's count, after a hole's
    ``number x y`` and a region's five fields are ignored — the same PSLG."""
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "p.poly"
        io.write(path, pslg, exact=True)
        lines = path.read_text().rstrip("\n").split("\n")
        holes_at = len(pslg.vertices) + 1 + len(pslg.segments) + 1
        regions_at = holes_at + 1 + len(pslg.holes)
        tail = " " + " ".join(extra)
        for index in (holes_at, regions_at, *range(holes_at + 1, regions_at)):
            lines[index] += tail
        for index in range(regions_at + 1, len(lines)):
            fields = lines[index].split()
            lines[index] = " ".join(fields + (["-1"] if len(fields) == 4 else [])) + tail
        path.write_text("\n".join(lines) + "\n")
        assert io.read(path) == io.read_with_notes(path)[0]
        again = io.read(path)
    assert isinstance(again, PSLG)
    assert (again.vertices, again.segments, again.holes) == (
        pslg.vertices, pslg.segments, pslg.holes)
    assert [(r.point, r.attribute) for r in again.regions] == [
        (r.point, r.attribute) for r in pslg.regions]
