"""The orientation rule of the tetrahedral readers (issue 27, item 4), TetGen and meshio
alike, the 3D form of the 2D readers' rule: all negative are reversed with a note, a mix
is refused naming the file, the line or cell and one tetrahedron of each, a flat one is
refused naming it (``specs/formats/tetgen.md``, ``specs/formats/meshio.md``)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import meshio
import numpy
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geomexact import io
from geomexact.errors import FormatError
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3

POINTS = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1),
          (1, 1, 1)]
CUBE = [(0, 1, 2, 4), (1, 3, 2, 7), (1, 4, 5, 7), (2, 7, 6, 4), (1, 2, 4, 7)]  # positive


def _negative(tetrahedra: list[tuple[int, int, int, int]]) -> list[tuple[int, int, int, int]]:
    return [(b, a, c, d) for a, b, c, d in tetrahedra]


def _tetgen(directory: Path, tetrahedra: list[tuple[int, int, int, int]],
            points: Sequence[tuple[object, ...]] = POINTS, comment: bool = False) -> Path:
    """TetGen files; ``comment``: a comment line first, which the bulk reader leaves to
    the line reader (both must say the same)."""
    head = "# written by hand\n" if comment else ""
    (directory / "m.node").write_text(head + f"{len(points)} 3 0 0\n" + "".join(
        f"{i} {x} {y} {z}\n" for i, (x, y, z) in enumerate(points)))
    (directory / "m.ele").write_text(head + f"{len(tetrahedra)} 4 0\n" + "".join(
        f"{i} {a} {b} {c} {d}\n" for i, (a, b, c, d) in enumerate(tetrahedra)))
    return directory / "m.ele"


def _vtu(directory: Path, tetrahedra: list[tuple[int, int, int, int]],
         points: Sequence[tuple[object, ...]] = POINTS, name: str = "m.vtu") -> Path:
    path = directory / name
    cells = [("vertex", numpy.array([[0]])),
             ("tetra", numpy.array(tetrahedra, dtype=numpy.int32).reshape(-1, 4))]
    coordinates = numpy.array([[float(c) for c in p] for p in points])  # type: ignore[arg-type]
    meshio.write(path, meshio.Mesh(coordinates, cells))
    return path


def _refusal(path: Path) -> FormatError:
    with pytest.raises(FormatError) as caught:
        io.read(path)
    return caught.value


@pytest.mark.parametrize("comment", [False, True])
def test_tetgen_all_negative_reversed_with_a_note(tmp_path: Path, comment: bool) -> None:
    expected = io.read(_tetgen(tmp_path, CUBE))
    value, notes = io.read_with_notes(_tetgen(tmp_path, _negative(CUBE), comment=comment))
    assert value == expected
    assert "all 5 tetrahedra were negatively oriented; reversed them" in notes
    _, notes = io.read_with_notes(_tetgen(tmp_path, _negative(CUBE[:1]), comment=comment))
    assert "the only tetrahedron was negatively oriented; reversed it" in notes
    _, notes = io.read_with_notes(_tetgen(tmp_path, CUBE, comment=comment))
    assert not any("negatively" in note for note in notes)


@pytest.mark.parametrize("comment", [False, True])
def test_tetgen_mixed_names_a_tetrahedron_of_each(tmp_path: Path, comment: bool) -> None:
    tetrahedra = CUBE[:3] + _negative(CUBE[3:])
    error = _refusal(_tetgen(tmp_path, tetrahedra, comment=comment))
    line = 5 + comment
    assert error.path == str(tmp_path / "m.ele") and error.line == line
    assert error.problem == (
        f"tetrahedra have mixed orientations: tetrahedron 3 (7, 2, 6, 4) on line {line} is "
        f"negatively oriented but tetrahedron 0 (0, 1, 2, 4) on line {2 + comment} is "
        "positive (orient3d, specs/predicates.md)")


def test_tetgen_flat_names_it(tmp_path: Path) -> None:
    error = _refusal(_tetgen(tmp_path, [CUBE[0], (0, 1, 2, 3)]))
    assert error.line == 3 and error.problem == (
        "tetrahedron 1 (0, 1, 2, 3) on line 3 is flat (zero volume): its corners are coplanar")


def test_vtu_all_negative_reversed_with_a_note(tmp_path: Path) -> None:
    """Was: each negative tetrahedron reversed on its own, without a word."""
    value, notes = io.read_with_notes(_vtu(tmp_path, _negative(CUBE)))
    assert isinstance(value, Mesh3) and value == io.read(_vtu(tmp_path, CUBE, name="p.vtu"))
    assert notes == ["ignored 1 vertex cells",
                     "all 5 tetrahedra were negatively oriented; reversed them"]


@pytest.mark.parametrize("suffix", [".vtu", ".vtk"])
def test_vtk_mixed_names_a_cell_of_each(tmp_path: Path, suffix: str) -> None:
    """Cells are numbered over all the file's cells (the vertex cell is cell 0)."""
    path = _vtu(tmp_path, CUBE[:3] + _negative(CUBE[3:]), name=f"m{suffix}")
    error = _refusal(path)
    assert error.path == str(path) and error.line is None
    assert error.problem == (
        "tetrahedra have mixed orientations: tetrahedron (7, 2, 6, 4) in cell 4 is "
        "negatively oriented but tetrahedron (0, 1, 2, 4) in cell 1 is positive (orient3d, "
        "specs/predicates.md)")


def test_vtu_flat_out_of_range_repeated_and_overlapping(tmp_path: Path) -> None:
    assert _refusal(_vtu(tmp_path, [CUBE[0], (0, 1, 2, 3)])).problem == (
        "tetrahedron (0, 1, 2, 3) in cell 2 is flat (zero volume): its corners are coplanar")
    assert _refusal(_vtu(tmp_path, [(0, 1, 2, 9)])).problem == (
        "tetrahedron (0, 1, 2, 9) in cell 1: vertex 9 is out of range (there are 8 points)")
    assert _refusal(_vtu(tmp_path, [(0, 1, 2, 1)])).problem == (
        "tetrahedron (0, 1, 2, 1) in cell 1 repeats a vertex")
    assert _refusal(_vtu(tmp_path, [CUBE[0], (0, 1, 2, 7)])).problem == (
        "the tetrahedra overlap: face (0, 1, 2) of tetrahedron (0, 1, 2, 7) in cell 2 is on "
        "the same side as tetrahedron (0, 1, 2, 4) in cell 1")


@settings(max_examples=20, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(pattern=st.integers(0, 2**18 - 1), turned=st.data())
def test_any_partition_turned_all_or_in_part(tmp_path_factory: pytest.TempPathFactory,
                                             pattern: int, turned: st.DataObject) -> None:
    """A cuboid partition with every tetrahedron turned reads back as itself, noted; with
    some but not all turned it is refused at the first line where the second orientation
    appears, naming the first tetrahedron of each."""
    mesh = partition_cuboid(pattern).mesh
    points = [p[:3] for p in mesh.point_list()]  # halves: exact in both formats
    tetrahedra = mesh.tetrahedra()
    directory = tmp_path_factory.mktemp("turned")
    value, notes = io.read_with_notes(_tetgen(directory, _negative(tetrahedra), points))
    assert value == mesh and any("negatively oriented" in note for note in notes)
    chosen = turned.draw(st.sets(st.integers(0, len(tetrahedra) - 1), min_size=1,
                                 max_size=len(tetrahedra) - 1))
    mixed = [_negative([t])[0] if i in chosen else t for i, t in enumerate(tetrahedra)]
    error = _refusal(_tetgen(directory, mixed, points))
    first_negative, first_positive = min(chosen), min(set(range(len(mixed))) - chosen)
    assert error.line == max(first_negative, first_positive) + 2
    assert (f"tetrahedron {first_negative} ({', '.join(map(str, mixed[first_negative]))}) "
            f"on line {first_negative + 2} is negatively oriented") in error.problem
    assert f"tetrahedron {first_positive} (" in error.problem
    vtu = _refusal(_vtu(directory, mixed, points))
    assert f"in cell {first_negative + 1} is negatively oriented" in vtu.problem
