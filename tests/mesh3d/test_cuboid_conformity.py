"""Two cuboids that share a face triangulate it identically when they see the same
Steiner points on it.

* Equal neighbours of a grid (templates by :func:`template_at`): both orders conform, for
  every set of Steiner points on the shared face and any other bits (exhaustive over the
  32 sets, on each axis).  In this numbering the edges of opposite faces are numbered in
  the same relative order, so even the index order sees them in the same order.
* Across levels (one cuboid against four half-size ones, as in a 1-irregular octree): the
  conforming order matches the four small faces, the index order does not — the
  counterexample of ``specs/cuboid.md``.
"""

from __future__ import annotations

import itertools
import random

import pytest

from geomexact.kernel.numbers import Rational, mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.numbering import FACE_EDGES
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.cuboid.split_order import ORDERS
from geomexact.mesh3d.cuboid.templates import template_at

Point = tuple[Rational, Rational, Rational]


def cell(position: tuple[int, int, int], size: Rational | int = 1) -> Box:
    low = tuple(mpq(c) * size for c in position)
    return Box(low, tuple(c + size for c in low))


def triangles_on(box: Box, pattern: int, order: str, template: int, face_bit: int
                 ) -> set[frozenset[Point]]:
    """The triangles of ``box``'s face ``face_bit`` as sets of exact points."""
    run = partition_cuboid(pattern, box, order=order, template=template)
    mesh = run.mesh
    codes = {code: vertex for vertex, code in run.point_codes().items()}
    return {frozenset(mesh.point(codes[c])[:3] for c in triangle)
            for triangle in run.face_triangulations()[face_bit]}


def steiner_bits_at(box: Box, points: set[Point], face_bit: int) -> int:
    """The bits of ``box``'s face ``face_bit`` whose Steiner points are in ``points``."""
    bits = [face_bit, *FACE_EDGES[face_bit - 12]]
    return sum(1 << bit for bit in bits if box.steiner_point(bit)[:3] in points)


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("axis", [0, 1, 2])
def test_equal_neighbours_conform_for_every_set_of_shared_points(order: str, axis: int) -> None:
    rng = random.Random(12 + axis)
    for position in [(0, 0, 0), (1, 0, 1)]:
        neighbour = list(position)
        neighbour[axis] += 1
        low_box, high_box = cell(position), cell((neighbour[0], neighbour[1], neighbour[2]))
        low_face, high_face = 12 + 2 * axis + 1, 12 + 2 * axis
        shared_bits = [low_face, *FACE_EDGES[low_face - 12]]
        candidates = [low_box.steiner_point(bit)[:3] for bit in shared_bits]
        for chosen in itertools.product([False, True], repeat=5):
            points = {p for p, keep in zip(candidates, chosen, strict=True) if keep}
            low_pattern = steiner_bits_at(low_box, points, low_face) | rng.getrandbits(18) & ~(
                sum(1 << b for b in shared_bits))
            high_shared = [high_face, *FACE_EDGES[high_face - 12]]
            high_pattern = steiner_bits_at(high_box, points, high_face) | rng.getrandbits(
                18) & ~sum(1 << b for b in high_shared)
            low = triangles_on(low_box, low_pattern, order, template_at(*position), low_face)
            high = triangles_on(high_box, high_pattern, order, template_at(*neighbour),
                                high_face)
            assert low == high, (order, axis, points)


@pytest.mark.parametrize("order", ORDERS)
def test_a_cuboid_against_four_half_size_ones(order: str) -> None:
    """The big cube [0,2]^3 with its face x=2 refined (centre and four edge midpoints:
    corners of the four small cubes [2,3] x [j,j+1] x [k,k+1] beyond it, whose faces x=2
    carry no Steiner point and take their templates by parity at their own level)."""
    big = cell((0, 0, 0), 2)
    face = 13  # x = 1 of the big cube
    pattern = sum(1 << bit for bit in (face, *FACE_EDGES[face - 12]))
    big_triangles = triangles_on(big, pattern, order, template_at(0, 0, 0), face)
    small_triangles: set[frozenset[Point]] = set()
    for j, k in itertools.product((0, 1), repeat=2):
        small = cell((2, j, k))
        small_triangles |= triangles_on(small, 0, order, template_at(2, j, k), 12)
    if order == "conforming":
        assert big_triangles == small_triangles
    else:  # the index order splits the edges before the centre: not the fan
        assert big_triangles != small_triangles
        assert len(big_triangles) == len(small_triangles) == 8
