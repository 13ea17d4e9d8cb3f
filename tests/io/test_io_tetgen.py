"""TetGen ``.node/.ele/.face``: digest-exact round trips, numbering, orientation and the
errors of bad files (``specs/formats/tetgen.md``)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geomexact import io
from geomexact.errors import FormatError
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.validation import validate3

CUBE_NODE = """8 3 0 0
0 0 0 0
1 1 0 0
2 0 1 0
3 1 1 0
4 0 0 1
5 1 0 1
6 0 1 1
7 1 1 1
"""
# the 5-tetrahedron cube, each positive in our orient3d
CUBE_TETS = [(0, 1, 2, 4), (1, 3, 2, 7), (1, 4, 5, 7), (2, 7, 6, 4), (1, 2, 4, 7)]


def _ele(tets: list[tuple[int, int, int, int]], base: int = 0) -> str:
    rows = [f"{len(tets)} 4 0"]
    rows += [f"{i + base} " + " ".join(str(v + base) for v in t) for i, t in enumerate(tets)]
    return "\n".join(rows) + "\n"


def _node(base: int) -> str:
    rows = CUBE_NODE.splitlines()
    return "\n".join([rows[0]] + [
        " ".join([str(int(r.split()[0]) + base), *r.split()[1:]]) for r in rows[1:]
    ]) + "\n"


def _files(tmp_path: Path, node: str, ele: str, face: str | None = None) -> Path:
    (tmp_path / "m.node").write_text(node)
    (tmp_path / "m.ele").write_text(ele)
    if face is not None:
        (tmp_path / "m.face").write_text(face)
    return tmp_path / "m.ele"


def _cube(tmp_path: Path, base: int = 0) -> Mesh3:
    value = io.read(_files(tmp_path, _node(base), _ele(CUBE_TETS, base)))
    assert isinstance(value, Mesh3)
    return value


def test_reads_the_cube_0_and_1_based(tmp_path: Path) -> None:
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    zero = _cube(tmp_path / "a")
    one = _cube(tmp_path / "b", base=1)
    assert zero == one and zero.tetrahedron_count == 5 and zero.vertex_count == 8
    assert validate3(zero, volume=1) == []


def test_auto_detected_by_dimension_and_named_format(tmp_path: Path) -> None:
    path = _files(tmp_path, CUBE_NODE, _ele(CUBE_TETS))
    assert io.detect_format(path) == "triangle"  # .ele; the .node's dimension decides
    assert io.read(path, format="tetgen") == io.read(path)


def test_all_negative_is_reversed_with_a_note(tmp_path: Path) -> None:
    flipped = [(b, a, c, d) for a, b, c, d in CUBE_TETS]
    value, notes = io.read_with_notes(_files(tmp_path, CUBE_NODE, _ele(flipped)))
    assert isinstance(value, Mesh3) and validate3(value) == []
    assert any("negatively oriented" in note for note in notes)


def _write_read(mesh: Mesh3, path: Path) -> Mesh3:
    report = io.write_with_report(path, mesh)
    assert report.rounded == 0
    assert sorted(p.name for p in report.paths) == ["m.ele", "m.face", "m.node"]
    back, notes = io.read_with_notes(path)
    assert isinstance(back, Mesh3)
    assert any("agrees with the boundary" in note for note in notes)
    return back


def test_round_trip_cube(tmp_path: Path) -> None:
    mesh = _cube(tmp_path)
    (tmp_path / "out").mkdir()
    back = _write_read(mesh, tmp_path / "out" / "m.ele")
    assert back == mesh and back.digest == mesh.digest


rationals = st.fractions(min_value=-10, max_value=10, max_denominator=12)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=20)
@given(
    pattern=st.integers(0, 2**18 - 1),
    low=st.tuples(rationals, rationals, rationals),
    size=st.tuples(*[st.fractions(min_value=Fraction(1, 7), max_value=5,
                                  max_denominator=9)] * 3),
    template=st.integers(0, 1),
)
def test_round_trip_cuboid_partitions(
    tmp_path_factory: pytest.TempPathFactory,
    pattern: int,
    low: tuple[Fraction, Fraction, Fraction],
    size: tuple[Fraction, Fraction, Fraction],
    template: int,
) -> None:
    """Random partitions of shifted and scaled rational boxes come back digest-exact
    (thirds and sevenths are written as p/q in the exact style)."""
    box = Box(low, tuple(lo + s for lo, s in zip(low, size, strict=True)))
    mesh = partition_cuboid(pattern, box, template=template).mesh
    path = tmp_path_factory.mktemp("rt") / "m.ele"
    io.write(path, mesh, numbers="exact")
    back = io.read(path)
    assert back == mesh and back.digest == mesh.digest


def _error(tmp_path: Path, node: str, ele: str, face: str | None = None) -> FormatError:
    with pytest.raises(FormatError) as caught:
        io.read(_files(tmp_path, node, ele, face))
    return caught.value


def test_wrong_counts(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, "6 4 0\n" + _ele(CUBE_TETS).split("\n", 1)[1])
    assert error.path.endswith("m.ele") and error.line == 6
    assert "expected 6 tetrahedra, found 5" in str(error)
    error = _error(tmp_path, "9 3 0 0\n" + CUBE_NODE.split("\n", 1)[1], _ele(CUBE_TETS))
    assert error.path.endswith("m.node") and "expected 9 vertices" in str(error)


def test_bad_index(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, _ele(CUBE_TETS).replace("4 1 2 4 7", "4 1 2 4 8"))
    assert error.line == 6 and "vertex 8 is out of range" in str(error)
    assert str(error).startswith(f"{tmp_path / 'm.ele'}:6:")


def test_flat_tetrahedron(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, _ele([(0, 1, 2, 3)]))
    assert error.line == 2 and "flat" in str(error)


def test_mixed_orientation_names_both_lines(tmp_path: Path) -> None:
    tets = list(CUBE_TETS)
    a, b, c, d = tets[3]
    tets[3] = (b, a, c, d)
    error = _error(tmp_path, CUBE_NODE, _ele(tets))
    assert error.line == 5 and ("tetrahedron 3 (7, 2, 6, 4) on line 5 is negatively "
                                "oriented but tetrahedron 0 (0, 1, 2, 4) on line 2 is "
                                "positive") in str(error)


def test_missing_node(tmp_path: Path) -> None:
    (tmp_path / "m.ele").write_text(_ele(CUBE_TETS))
    with pytest.raises(FormatError, match=r"m\.node, which does not exist"):
        io.read(tmp_path / "m.ele", format="tetgen")


def test_two_dimensional_node_is_read_by_triangle(tmp_path: Path) -> None:
    path = _files(tmp_path, "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n", "1 3 0\n0 0 1 2\n")
    assert isinstance(io.read(path), Mesh2)
    with pytest.raises(FormatError, match="dimension is 2; a TetGen mesh is 3") as caught:
        io.read(path, format="tetgen")
    assert caught.value.line == 1


def test_face_file_must_match_the_boundary(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, _ele(CUBE_TETS), "1 0\n0 0 1 2\n")
    assert error.path.endswith("m.face") and "12 boundary faces" in str(error)
    faces = "12 0\n" + "".join(f"{i} 1 2 4\n" for i in range(12))
    error = _error(tmp_path, CUBE_NODE, _ele(CUBE_TETS), faces)
    assert error.line == 2 and "not a boundary face" in str(error)


def test_repeated_vertex_and_numbering(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, "1 4 0\n0 0 1 1 2\n")
    assert error.line == 2 and "repeats a vertex" in str(error)
    error = _error(tmp_path, CUBE_NODE, "2 4 0\n0 0 1 2 4\n3 1 3 2 7\n")
    assert error.line == 3 and "consecutive" in str(error)


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture], max_examples=10)
@given(pattern=st.integers(0, 2**18 - 1), shift=rationals)
def test_round_trip_one_based_and_decimal(
    tmp_path_factory: pytest.TempPathFactory, pattern: int, shift: Fraction
) -> None:
    """A written mesh renumbered from 1 reads back the same; dyadic boxes need no
    rounding in the default decimal style."""
    box = Box((shift, 0, -shift), (shift + Fraction(3, 4), 2, -shift + Fraction(5, 8)))
    mesh = partition_cuboid(pattern, box).mesh
    directory = tmp_path_factory.mktemp("one")
    report = io.write_with_report(directory / "m.ele", mesh, numbers="exact")
    assert report.rounded == 0
    for suffix, width in ((".node", 1), (".ele", 5), (".face", 4)):
        file = directory / f"m{suffix}"
        rows = file.read_text().splitlines()
        file.write_text("\n".join([rows[0], *(
            " ".join([*(str(int(t) + 1) for t in row.split()[:width]), *row.split()[width:]])
            for row in rows[1:] if not row.startswith("#")
        )]) + "\n")
    back = io.read(directory / "m.ele")
    assert back == mesh and back.digest == mesh.digest


def test_overlap_names_both_lines(tmp_path: Path) -> None:
    error = _error(tmp_path, CUBE_NODE, _ele([*CUBE_TETS, CUBE_TETS[1]]))
    assert error.line == 7 and "the tetrahedra overlap" in str(error)
    assert "tetrahedron on line 3" in str(error)


# -- the orientation written: TetGen's own (specs/formats/tetgen.md, "What TetGen writes") --
def _rows(path: Path) -> list[list[str]]:
    return [line.split() for line in path.read_text().splitlines()[1:]
            if line.strip() and not line.startswith("#")]


def _det(a: list[Fraction], b: list[Fraction], c: list[Fraction],
         d: list[Fraction]) -> Fraction:
    """det[b - a, c - a, d - a], computed here with Fractions (not our orient3d)."""
    u, v, w = ([q - p for p, q in zip(a, x, strict=True)] for x in (b, c, d))
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]))


def _written(tmp_path: Path, mesh: Mesh3) -> tuple[list[list[Fraction]], Path]:
    path = tmp_path / "w.ele"
    io.write(path, mesh, numbers="exact")
    points = [[Fraction(t) for t in row[1:4]] for row in _rows(tmp_path / "w.node")]
    return points, path


@pytest.mark.parametrize(("pattern", "box"), [
    (0, Box((0, 0, 0), (1, 1, 1))),
    (70688, Box((0, 0, 0), (1, 2, 4))),
    (262143, Box((Fraction(-1, 3), 0, 5), (Fraction(1, 7), 2, 6))),
])
def test_written_tetrahedra_are_positive_as_tetgen_writes_them(
    tmp_path: Path, pattern: int, box: Box
) -> None:
    """Every .ele line a b c d has det[b - a, c - a, d - a] > 0 (TetGen's convention:
    positive in our orient3d, negative in Shewchuk's); reading it back needs no reversal."""
    mesh = partition_cuboid(pattern, box, improve=True).mesh
    points, path = _written(tmp_path, mesh)
    tetrahedra = [[int(t) for t in row[1:5]] for row in _rows(path)]
    assert len(tetrahedra) == mesh.tetrahedron_count
    assert all(_det(*(points[v] for v in t)) > 0 for t in tetrahedra)
    back, notes = io.read_with_notes(path)
    assert back == mesh and not any("negatively oriented" in note for note in notes)


def test_written_faces_point_inward_as_tetgen_writes_them(tmp_path: Path) -> None:
    """Every .face line a b c is counter-clockwise seen from inside: the tetrahedron on it
    has its fourth vertex on the side (b - a) x (c - a) points to."""
    mesh = partition_cuboid(70688, Box((0, 0, 0), (1, 2, 4)), improve=True).mesh
    points, path = _written(tmp_path, mesh)
    faces = [tuple(int(t) for t in row[1:4]) for row in _rows(tmp_path / "w.face")]
    assert len(faces) == len(mesh.boundary_faces())
    tetrahedra = [[int(t) for t in row[1:5]] for row in _rows(path)]
    for a, b, c in faces:
        (apex,) = next(set(t) - {a, b, c} for t in tetrahedra if {a, b, c} <= set(t))
        assert _det(points[a], points[b], points[c], points[apex]) > 0


def test_a_file_in_tetgens_orientation_reads_without_a_note(tmp_path: Path) -> None:
    """A hand-made cube in TetGen's convention (positive tetrahedra, inward faces) reads
    with no reversal note, its .face agreeing with the boundary."""
    (tmp_path / "seed").mkdir()
    outward = _cube(tmp_path / "seed").boundary_faces()
    face = f"{len(outward)} 1\n" + "".join(
        f"{i} {a} {c} {b} 1\n" for i, (a, b, c) in enumerate(outward))
    value, notes = io.read_with_notes(_files(tmp_path, CUBE_NODE, _ele(CUBE_TETS), face))
    assert isinstance(value, Mesh3) and value.tetrahedron_count == 5
    assert not any("negatively oriented" in note for note in notes)
    assert any("agrees with the boundary" in note for note in notes)
