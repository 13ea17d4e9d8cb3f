"""Bad input: every problem is a FormatError naming the file, the line and the problem,
never a traceback from inside a reader.  One file per problem in ``tests/data/bad``."""

from __future__ import annotations

import contextlib
import tempfile
from pathlib import Path

import pytest
from helpers.io_cases import BAD, write
from hypothesis import given
from hypothesis import strategies as st

from geomexact import io
from geomexact.errors import FormatError

# file read, file the error names, its line, a fragment of the problem
CASES = [
    ("ele-corner-not-an-integer.ele", "ele-corner-not-an-integer.ele", 3,
     "corner of triangle 1: 'x' is not an integer"),
    ("ele-degenerate-triangle.ele", "ele-degenerate-triangle.ele", 3,
     "triangle 1 (0, 1, 2) on line 3 is degenerate: its corners are collinear"),
    ("ele-mixed-orientation.ele", "ele-mixed-orientation.ele", 3,
     "triangles have mixed orientations: triangle 1 (0, 3, 2) on line 3 is clockwise but "
     "triangle 0 (0, 1, 2) on line 2 is counter-clockwise"),
    ("ele-overlapping-triangles.ele", "ele-overlapping-triangles.ele", 3,
     "the triangles overlap"),
    ("ele-six-node-triangles.ele", "ele-six-node-triangles.ele", 1,
     "only 3-node triangles are supported"),
    ("ele-truncated.ele", "ele-truncated.ele", 3, "the file ends before triangle 2 (of 3)"),
    ("ele-vertex-out-of-range.ele", "ele-vertex-out-of-range.ele", 3,
     "triangle 1: vertex 4 is out of range (expected 0..3)"),
    ("neigh-disagrees.ele", "neigh-disagrees.neigh", 2,
     "the neighbour opposite its vertex 1 is listed as none (-1), but in the mesh it is "
     "triangle 1"),
    ("node-dimension-3.ele", "node-dimension-3.ele", 1,
     "lists 3-node triangles, but its .node is 3D (dimension 3)"),
    ("node-duplicate-vertex.ele", "node-duplicate-vertex.node", 5,
     "vertex 3 (1, 0) has the same coordinates as vertex 1 (line 3)"),
    ("node-first-number-2.ele", "node-first-number-2.node", 2,
     "the first vertex is numbered 2; it must be 0 or 1"),
    ("node-missing-marker.ele", "node-missing-marker.node", 3, "needs 4 fields, found 3"),
    ("node-nan-coordinate.ele", "node-nan-coordinate.node", 4,
     "y of vertex 2: cannot read 'nan' as a number: NaN is not a number"),
    ("node-not-consecutive.ele", "node-not-consecutive.node", 4,
     "vertex numbered 3, expected 2"),
    ("node-not-utf8.node", "node-not-utf8.node", 3, "not UTF-8"),
    ("node-unparsable-coordinate.ele", "node-unparsable-coordinate.node", 3,
     "x of vertex 1: cannot read '1.0.0' as a number"),
    ("off-bad-counts.off", "off-bad-counts.off", 2, "face count: 'one' is not an integer"),
    ("off-face-vertex-out-of-range.off", "off-face-vertex-out-of-range.off", 7,
     "face 0: vertex 3 is out of range (expected 0..2)"),
    ("off-mixed-orientation.off", "off-mixed-orientation.off", 8,
     "triangle 1 (0, 3, 2) on line 8 is clockwise but triangle 0 (0, 1, 2) on line 7 is "
     "counter-clockwise"),
    ("off-nonzero-z.off", "off-nonzero-z.off", 5, "vertex 2 has z = 0.5"),
    ("off-two-vertex-face.off", "off-two-vertex-face.off", 6,
     "a polygon needs at least 3"),
    ("off-unclosed-geomview-block.off", "off-unclosed-geomview-block.off", 7,
     "expected '}' closing the Geomview block opened on line 1"),
    ("off-zero-area-polygon.off", "off-zero-area-polygon.off", 7, "has zero area"),
    ("poly-missing-node.poly", "poly-missing-node.poly", 1,
     "vertices in poly-missing-node.node', but there is no such file"),
    ("poly-segment-equal-ends.poly", "poly-segment-equal-ends.poly", 7,
     "segment 1 (2, 2) has equal ends"),
    ("poly-segment-out-of-range.poly", "poly-segment-out-of-range.poly", 8,
     "segment 3: vertex 4 is out of range (expected 1..3)"),
    ("poly-truncated-holes.poly", "poly-truncated-holes.poly", 7,
     "the file ends before hole 2 (of 2)"),
    ("pslg-corner-out-of-range.pslg", "pslg-corner-out-of-range.pslg", 4,
     "vertex 3 is out of range (expected 0..2)"),
    ("pslg-neighbour-disagrees.pslg", "pslg-neighbour-disagrees.pslg", 7,
     "triangle 0: the neighbour opposite its vertex 1 is listed as -1, but in the mesh it "
     "is 1"),
    ("pslg-unknown-record.pslg", "pslg-unknown-record.pslg", 4, "unknown record 'q'"),
    ("trilist-degenerate-triangle.txt", "trilist-degenerate-triangle.txt", 2,
     "is degenerate: its corners are collinear"),
    ("trilist-five-fields.txt", "trilist-five-fields.txt", 2, "found 5 fields"),
    ("trilist-overlapping-triangles.txt", "trilist-overlapping-triangles.txt", 2,
     "the triangles overlap"),
]


def test_every_bad_file_has_a_case() -> None:
    """Each file in tests/data/bad is read by some case (or is the partner of one)."""
    read = {Path(name).stem for name, *_ in CASES}
    assert {path.stem for path in BAD.iterdir()} == read


@pytest.mark.parametrize(("name", "culprit", "line", "fragment"), CASES)
def test_bad_input_is_a_format_error_naming_file_and_line(
    name: str, culprit: str, line: int, fragment: str
) -> None:
    """The error names the culprit file, its line and the problem."""
    with pytest.raises(FormatError) as caught:
        io.read(BAD / name)
    error = caught.value
    assert Path(error.path).name == culprit
    assert error.line == line
    assert fragment in error.problem
    assert str(error).startswith(f"{error.path}:{line}: ")


def test_missing_file(tmp_path: Path) -> None:
    """A missing file is a FormatError too."""
    with pytest.raises(FormatError, match="no such file"):
        io.read(tmp_path / "absent.off")


def test_missing_node_beside_ele(tmp_path: Path) -> None:
    """A Triangle mesh needs the .node beside its .ele."""
    write(tmp_path, "lonely.ele", "1 3 0\n0 0 1 2\n")
    with pytest.raises(FormatError, match=r"needs its vertices in lonely\.node"):
        io.read(tmp_path / "lonely.ele")


def test_unknown_extension() -> None:
    """An extension no format claims is a FormatError that says how to choose one."""
    with pytest.raises(FormatError, match=r"extension '\.xyz' names no known format"):
        io.detect_format("mesh.xyz")
    with pytest.raises(FormatError, match="unknown format 'nope'"):
        io.read("mesh.off", format="nope")


SQUARE_NODE = "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n"


@pytest.mark.parametrize(
    ("ele", "line", "fragment"),
    [
        ("2 3 0\n0 0 1 2\n1 0 2 3\n1 0 2 3\n", 4, "unexpected data after the 2 triangles"),
        ("2 3 0\n0 0 1 2\n2 0 2 3\n", 3, "triangle numbered 2, expected 1"),
        ("2 3 0\n0 0 1 2\n1 0 2\n", 3, "needs 4 fields, found 3"),
        ("two 3 0\n", 1, "triangle count: 'two' is not an integer"),
        ("-2 3 0\n", 1, "triangle count is negative"),
        ("", None, "the file ends before the header"),
        ("2 3 0\n0 0 1 2\n1 0 2 -1\n", 3, "vertex -1 is out of range"),
        ("2 3 0\n0 0 1 1\n1 0 2 3\n", 2, "repeats a vertex"),
    ],
)
def test_bad_ele_lines(tmp_path: Path, ele: str, line: int | None, fragment: str) -> None:
    """More .ele problems, each with its line."""
    write(tmp_path, "m.node", SQUARE_NODE)
    write(tmp_path, "m.ele", ele)
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "m.ele")
    assert caught.value.line == line
    assert fragment in caught.value.problem


@pytest.mark.parametrize(
    ("text", "line", "fragment"),
    [
        ("OFF\n3 1\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", 4, "vertex 1 'x y z' needs 3 fields"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", 6, "needs 5 fields"),
        ("4OFF\n", 1, "4D and n-dimensional OFF variants are not supported"),
        ("OFF BINARY\n", 1, "binary OFF is not supported"),
        ("OFF\n1 2 3 4\n", 2, "expected the counts"),
        ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", 7, "unexpected data"),
        ("{ appearance { +edge LIST\nOFF\n", 1, "is never closed"),
        ("{ LIST OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n} }\n", 7,
         "unexpected data after the 1 face: '}'"),
    ],
)
def test_bad_off_lines(tmp_path: Path, text: str, line: int, fragment: str) -> None:
    """More OFF problems, each with its line."""
    write(tmp_path, "m.off", text)
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "m.off")
    assert caught.value.line == line
    assert fragment in caught.value.problem


@given(st.binary(max_size=200))
def test_garbage_never_escapes_as_another_error(data: bytes) -> None:
    """Random bytes in any format give a value or a FormatError, nothing else."""
    with tempfile.TemporaryDirectory() as directory:
        for name in ("g.node", "g.poly", "g.off", "g.pslg", "g.txt"):
            path = Path(directory) / name
            path.write_bytes(data)
            with contextlib.suppress(FormatError):
                io.read(path)


@given(
    st.lists(
        st.lists(
            st.sampled_from(["0", "1", "2", "-1", "3", "0.5", "1/3", "x", "OFF", "{", "}",
                             "v", "t", "n", "s", "h", "r", "#"]),
            max_size=7,
        ),
        max_size=9,
    )
)
def test_plausible_garbage_never_escapes(lines: list[list[str]]) -> None:
    """Token soup close to real files gives a value or a FormatError, nothing else."""
    text = "\n".join(" ".join(tokens) for tokens in lines)
    with tempfile.TemporaryDirectory() as directory:
        for name in ("g.node", "g.poly", "g.off", "g.pslg", "g.txt"):
            path = Path(directory) / name
            path.write_text(text)
            with contextlib.suppress(FormatError):
                io.read(path)
        ele = Path(directory) / "h.ele"
        write(Path(directory), "h.node", SQUARE_NODE)
        ele.write_text(text)
        with contextlib.suppress(FormatError):
            io.read(ele)
