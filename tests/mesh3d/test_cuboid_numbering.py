"""The cuboid's numbering and templates: the worked examples of the source make sense,
the two templates are mirror images whose diagonals each lie in three of the five
tetrahedra, neighbours agree on their shared diagonal, and the documented counts."""

from __future__ import annotations

import itertools

import pytest

from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.cuboid.boxes import box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.numbering import (
    CORNER_POSITIONS,
    EDGE_CORNERS,
    FACE_CORNERS,
    FACE_EDGES,
    bits_of,
    pattern_of,
    steiner_position2,
)
from geomexact.mesh3d.cuboid.partition import initial_mesh, partition_cuboid
from geomexact.mesh3d.cuboid.split_order import ORDERS, split_sequence
from geomexact.mesh3d.cuboid.templates import TEMPLATE_TETRAHEDRA, diagonal, template_at
from geomexact.mesh3d.validation import validate3


def test_the_worked_examples_of_the_source() -> None:
    assert bits_of(70688) == (5, 10, 12, 16) and 70688 == 2**16 + 2**12 + 2**10 + 2**5
    assert bits_of(12304) == (4, 12, 13) and pattern_of([4, 12, 13]) == 12304


@pytest.mark.parametrize("template", [0, 1])
def test_splitting_diagonal_12_after_edges_3_and_8_makes_6_tetrahedra_from_3(
    template: int,
) -> None:
    """Bits 3, 8, 12 in the source's (index) order: edges 3 and 8 lie on face 12 (both at
    corner 0), so they do not add tetrahedra on the diagonal: its split turns 3 into 6."""
    pattern = pattern_of([3, 8, 12])
    run = partition_cuboid(pattern, order="index", template=template)
    assert [step.args for step in run.trace.steps][:2] == [EDGE_CORNERS[3], EDGE_CORNERS[8]]
    assert {3, 8} <= set(FACE_EDGES[0])
    before = partition_cuboid(pattern_of([3, 8]), order="index", template=template)
    assert before.partition.tetrahedron_count == 7
    transient = before.partition.transient()
    assert len(transient.around_edge(*diagonal(12, template))) == 3
    assert run.partition.tetrahedron_count == 7 - 3 + 6


def test_the_numbering_tables() -> None:
    assert CORNER_POSITIONS[5] == (1, 0, 1)
    assert len(set(EDGE_CORNERS)) == 12
    for p, q in EDGE_CORNERS:  # a cube edge joins corners differing in one coordinate
        assert bin(p ^ q).count("1") == 1
    for j, corners in enumerate(FACE_CORNERS):
        assert len(corners) == 4 and len(FACE_EDGES[j]) == 4
        assert steiner_position2(12 + j)[j // 2] == 2 * (j % 2)
    assert FACE_CORNERS[0] == (0, 2, 4, 6) and FACE_EDGES[0] == (3, 7, 8, 11)


@pytest.mark.parametrize("template", [0, 1])
def test_the_template_is_five_positive_tetrahedra_on_every_box(template: int) -> None:
    for box in (unit_cube(), box_of_extents(1, 2, 4), box_of_extents("1/3", 7, "0.25")):
        mesh = initial_mesh(box, template)
        assert validate3(mesh, volume=box.volume) == []
        for tetrahedron in TEMPLATE_TETRAHEDRA[template]:
            assert orient3d(*(box.corner(k) for k in tetrahedron)) > 0
    central = TEMPLATE_TETRAHEDRA[template][0]
    assert all(bin(k).count("1") % 2 == template for k in central)
    for face_bit in range(12, 18):
        p, q = diagonal(face_bit, template)
        holding = [t for t in TEMPLATE_TETRAHEDRA[template] if p in t and q in t]
        assert len(holding) == 3 and central in holding


def test_the_templates_are_mirror_images() -> None:
    mirror = [k ^ 1 for k in range(8)]  # x -> 1 - x
    zero = {frozenset(t) for t in TEMPLATE_TETRAHEDRA[0]}
    one = {frozenset(mirror[k] for k in t) for t in TEMPLATE_TETRAHEDRA[1]}
    assert zero == one


def test_neighbours_by_parity_agree_on_the_diagonal_of_their_shared_face() -> None:
    for position in itertools.product(range(3), repeat=3):
        for axis in range(3):
            neighbour = list(position)
            neighbour[axis] += 1
            low, high = template_at(*position), template_at(*neighbour)
            assert low != high
            shared_low = [tuple(position[i] + CORNER_POSITIONS[k][i] for i in range(3))
                          for k in diagonal(12 + 2 * axis + 1, low)]
            shared_high = [tuple(neighbour[i] + CORNER_POSITIONS[k][i] for i in range(3))
                           for k in diagonal(12 + 2 * axis, high)]
            assert set(shared_low) == set(shared_high)
            assert all(sum(point) % 2 == 0 for point in shared_low)


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("template", [0, 1])
def test_the_documented_counts(order: str, template: int) -> None:
    """specs/cuboid.md: pattern 0 -> 5, one edge -> 6, one face -> 8, all 18 bits -> 40."""
    def count(pattern: int) -> int:
        return partition_cuboid(pattern, order=order, template=template).partition.tetrahedron_count

    assert count(0) == 5
    assert [count(1 << bit) for bit in range(12)] == [6] * 12
    assert [count(1 << bit) for bit in range(12, 18)] == [8] * 6
    assert count(2**18 - 1) == 40


def test_the_conforming_order_is_face_centres_then_edges_lexicographically() -> None:
    box = box_of_extents(1, 2, 4)
    sequence = split_sequence(2**18 - 1, box, "conforming")
    assert sequence[:6] == (12, 14, 16, 17, 15, 13)
    edge_points = [box.steiner_point(bit)[:3] for bit in sequence[6:]]
    assert edge_points == sorted(edge_points)
    assert split_sequence(2**18 - 1, box, "index") == tuple(range(18))
