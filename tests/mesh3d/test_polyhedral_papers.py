"""The papers' counts of co-spherical elements (issue 23, item 3; Contreras and
Hitschfeld-Kahler, arXiv 1312.1181 and IMR23 2014; docs/polyhedral-cells.md): the
configurations they count on, combinatorial types, cuts by internal faces, and the exact
lattice Delaunay cells that make a 1 x 1 x sqrt 2 cuboid exact.  The full enumerations are
slow; a sample runs always."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest

from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.numbering import FACE_EDGES
from geomexact.mesh3d.cuboid.polyhedral_census import (
    CellShape,
    cell_shape,
    cell_type,
    hull_faces,
    lattice_cells,
    lattice_census,
    lattice_shape,
    papers_count,
    papers_patterns,
    pattern_cells,
    plane_cuts,
    polyhedral_census,
    uncut_parts,
)

CUBE: CellShape = tuple(sorted((x, y, z) for x in (0, 2) for y in (0, 2) for z in (0, 2)))
PYRAMID: CellShape = ((0, 0, 0), (0, 0, 2), (0, 2, 0), (0, 2, 2), (2, 0, 1))
OCTAHEDRON: CellShape = ((0, 1, 1), (1, 0, 1), (1, 1, 0), (1, 1, 2), (1, 2, 1), (2, 1, 1))
HALF_CUBE: CellShape = tuple(sorted((x, y, z) for x in (0, 2) for y in (0, 2) for z in (0, 1)))


def test_the_papers_patterns_have_no_face_with_four_split_edges() -> None:
    patterns = papers_patterns()
    assert len(patterns) == 2902 and patterns[0] == 0
    assert all(pattern < 1 << 12 for pattern in patterns)
    assert all(any(not pattern >> edge & 1 for edge in edges)
               for pattern in patterns for edges in FACE_EDGES)
    assert 0b1111 not in patterns and 0b0111 in patterns  # the bottom ring: all four / three


def test_hull_faces_of_a_cube_a_pyramid_and_an_octahedron() -> None:
    assert sorted(len(face) for face in hull_faces(CUBE)) == [4] * 6
    assert sorted(len(face) for face in hull_faces(PYRAMID)) == [3, 3, 3, 3, 4]
    assert sorted(len(face) for face in hull_faces(OCTAHEDRON)) == [3] * 8
    for face in hull_faces(CUBE):  # counter-clockwise from outside: each edge once per way
        edges = {(face[i], face[(i + 1) % 4]) for i in range(4)}
        assert len(edges) == 4
    darts = [(f[i], f[(i + 1) % len(f)]) for f in hull_faces(PYRAMID) for i in range(len(f))]
    assert len(darts) == len(set(darts)) == 16 and all((b, a) in darts for a, b in darts)


def test_cell_type_is_combinatorial_and_blind_to_mirrors() -> None:
    assert cell_type(CUBE) == cell_type(HALF_CUBE)  # both hexahedra with quad faces
    other_pyramid = ((0, 0, 0), (0, 0, 2), (0, 2, 0), (0, 2, 2), (2, 1, 1))
    assert cell_type(PYRAMID) == cell_type(other_pyramid)
    assert len({cell_type(PYRAMID), cell_type(OCTAHEDRON), cell_type(CUBE)}) == 3
    mirrored = tuple(sorted((2 - x, y, z) for x, y, z in PYRAMID))
    assert cell_type(mirrored) == cell_type(PYRAMID)


def test_plane_cuts_leave_every_face_whole() -> None:
    assert plane_cuts(PYRAMID) == ()  # its only cut would split the square base
    assert uncut_parts(PYRAMID) == frozenset([PYRAMID])
    assert plane_cuts(CUBE) == ()  # a plane through two opposite edges splits two faces
    octahedron = plane_cuts(OCTAHEDRON)
    assert len(octahedron) == 3 and all(len(a) == len(b) == 5 for a, b in octahedron)
    # the octahedron's halves are square pyramids, which no plane cuts again
    assert {cell_type(part) for part in uncut_parts(OCTAHEDRON)} == {cell_type(PYRAMID)}
    assert uncut_parts(((0, 0, 0), (0, 0, 2), (0, 2, 0), (2, 0, 0))) == frozenset()


def test_papers_count_of_a_known_census() -> None:
    count = papers_count({CUBE: 1, HALF_CUBE: 2, PYRAMID: 5, OCTAHEDRON: 1,
                          ((0, 0, 0), (0, 0, 2), (0, 2, 0), (2, 0, 0)): 9})
    assert count.types == dict(sorted({cell_type(CUBE): 3, cell_type(PYRAMID): 5,
                                       cell_type(OCTAHEDRON): 1}.items()))
    assert count.uncuttable == frozenset([cell_type(PYRAMID), cell_type(CUBE)])
    assert cell_type(PYRAMID) in count.reduced and cell_type(OCTAHEDRON) not in count.reduced


def _sample(patterns: tuple[int, ...] | range, size: int) -> list[int]:
    return random.Random(23).sample(list(patterns), size)


@pytest.mark.parametrize(("box", "squares"), [
    (Box((0, 0, 0), (1, 1, 1)), (1, 1, 1)),
    (Box((0, 0, 0), (1, 1, 2)), (1, 1, 4)),
    (Box((0, 0, 0), (1, 2, Fraction(3, 2))), (4, 16, 9)),
])
def test_lattice_cells_agree_with_the_flipped_tetrahedralizations(
        box: Box, squares: tuple[int, int, int]) -> None:
    for pattern in [0, 1, 0b111, 1 << 12, (1 << 18) - 1, *_sample(range(1 << 18), 25)]:
        mesh, cells = pattern_cells(pattern, box)
        assert (sorted(cell_shape(mesh, cell, box) for cell in cells)
                == sorted(lattice_shape(cell, squares) for cell in lattice_cells(pattern, squares)))


def test_a_sqrt2_cuboid_has_cospherical_points_no_rational_ratio_has() -> None:
    """Pattern 257 (edge 0 and the vertical edge 8 split) on 1 x 1 x sqrt 2: six points
    on one empty sphere, which no rational ratio keeps (an insphere determinant here is
    linear in the squared ratio, zero at 2 only); next to it they are three cells."""
    six = ((0, 0, 1), (1, 0, 0), (2, 0, 0), (2, 0, 2), (2, 2, 0), (2, 2, 2))
    assert six in lattice_cells(257, (1, 1, 2))
    near = lattice_cells(257, (10_000, 10_000, 19_999))
    assert six not in near and sum(set(cell) <= set(six) for cell in near) == 3


def test_the_papers_counts_on_a_sample() -> None:
    """A sample of the papers' patterns: at most the full counts (the slow test)."""
    census = polyhedral_census(_sample(papers_patterns(), 60))
    count = papers_count(census.shapes)
    assert 5 <= len(count.types) <= 24
    assert count.uncuttable <= count.reduced and len(count.reduced) <= 15


@pytest.mark.slow
def test_the_papers_24_and_13_on_the_unit_cube() -> None:
    """Contreras and Hitschfeld-Kahler: 24 co-spherical elements on 1-irregular cubes
    with edge midpoints, 13 after inserting internal faces and edges."""
    census = polyhedral_census(papers_patterns())
    assert len([shape for shape in census.shapes if len(shape) >= 5]) == 87
    count = papers_count(census.shapes)
    assert len(count.types) == 24 and sum(count.types.values()) == 11089
    assert len(count.uncuttable) == 13 and len(count.reduced) == 15
    every = papers_count(polyhedral_census(range(1 << 12)).shapes)
    assert (len(every.types), len(every.uncuttable), len(every.reduced)) == (44, 22, 25)


@pytest.mark.slow
@pytest.mark.parametrize(("squares", "expected"), [
    ((1, 1, 2), (84, 20, 17, 17)),
    ((1, 2, 2), (90, 33, 28, 28)),
    ((16, 16, 25), (71, 9, 6, 6)),
])
def test_the_papers_counts_on_cuboids(squares: tuple[int, int, int],
                                      expected: tuple[int, int, int, int]) -> None:
    shapes = lattice_census(papers_patterns(), squares)
    count = papers_count(shapes)
    assert (len([s for s in shapes if len(s) >= 5]), len(count.types),
            len(count.uncuttable), len(count.reduced)) == expected
