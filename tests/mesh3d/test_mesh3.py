"""Tetrahedral snapshots and their steps: canonical forms, split_tetra, Joe's flips and the
face classification, with property tests over random walks of steps (validity, exact
volume, replay = result, inputs never mutated)."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import mpq, point3
from geomexact.errors import PreconditionError
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.measures import is_delaunay3, locally_non_delaunay_faces, total_volume
from geomexact.mesh3d.ops import (
    FLIP_OF_KIND,
    FaceKind,
    apply,
    classify_face,
    flip,
    split_tetra,
)
from geomexact.mesh3d.snapshot import (
    Mesh3,
    canonical_tetrahedron,
    full_digest3,
    tetrahedron_faces,
)
from geomexact.mesh3d.transient import mesh3_from_tetrahedra
from geomexact.mesh3d.validation import check3, validate3
from geomexact.trace.playback import replay
from geomexact.trace.record import trace_of

CUBE = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]  # corner i = bits zyx
FIVE = [(0, 3, 5, 6), (1, 0, 3, 5), (2, 0, 6, 3), (4, 0, 5, 6), (7, 3, 6, 5)]


def cube() -> Mesh3:
    return mesh3_from_tetrahedra(CUBE, FIVE, orient=True)


def test_the_five_tetrahedron_cube_is_valid_with_volume_one() -> None:
    mesh = cube()
    assert validate3(mesh, volume=1) == []
    assert mesh.tetrahedron_count == 5 and total_volume(mesh) == 1
    assert len(mesh.boundary_faces()) == 12 and len(mesh.interior_faces()) == 4
    assert is_delaunay3(mesh)  # all eight corners are cospherical: ties are Delaunay


@given(st.permutations(range(4)))
def test_canonical_tetrahedron_keeps_the_orientation(order: list[int]) -> None:
    points = [point3(0, 0, 0), point3(1, 0, 0), point3(0, 1, 0), point3(0, 0, 1)]
    tetrahedron = tuple(order)
    canonical = canonical_tetrahedron(*tetrahedron)
    assert sorted(canonical) == [0, 1, 2, 3] and canonical[0] == 0
    assert orient3d(*(points[v] for v in canonical)) == orient3d(
        *(points[v] for v in tetrahedron)
    )


def test_each_face_has_its_apex_on_its_positive_side() -> None:
    points = [point3(0, 0, 0), point3(1, 0, 0), point3(0, 1, 0), point3(0, 0, 1)]
    for face, apex in tetrahedron_faces(0, 1, 2, 3):
        assert orient3d(*(points[v] for v in (*face, apex))) > 0


def test_split_tetra_splits_every_tetrahedron_of_the_edge() -> None:
    mesh = cube()
    diagonal = (0, 3)  # in 3 of the 5 tetrahedra
    result = split_tetra(mesh, diagonal)
    assert result.tetrahedron_count == 8
    assert result.point(8) == point3(mpq(1, 2), mpq(1, 2), 0)
    assert validate3(result, volume=1) == []
    assert mesh == cube()  # the input is unchanged
    with pytest.raises(PreconditionError, match="not an edge"):
        split_tetra(mesh, (1, 2))


def _bipyramid(top: tuple[object, ...], bottom: tuple[object, ...]) -> Mesh3:
    points = [(0, 0, 0), (4, 0, 0), (0, 4, 0), top, bottom]
    return mesh3_from_tetrahedra(points, [(0, 1, 2, 3), (0, 2, 1, 4)], orient=True)


def test_flip23_and_flip32_undo_each_other() -> None:
    mesh = _bipyramid((1, 1, 1), (1, 1, -1))
    assert classify_face(mesh, (0, 1, 2)).kind == FaceKind.T23
    three = flip(mesh, "flip23", (0, 1, 2))
    assert three.tetrahedron_count == 3 and validate3(three, volume=total_volume(mesh)) == []
    kinds = {classify_face(three, face).kind for face in three.interior_faces()}
    assert kinds == {FaceKind.T32}
    back = flip(three, "flip32", (0, 3, 4))
    assert back == mesh
    with pytest.raises(PreconditionError, match="is T23, not T32"):
        flip(mesh, "flip32", (0, 1, 2))


@pytest.mark.parametrize(("top", "bottom", "kind"), [
    ((0, 0, 1), (0, 0, -1), FaceKind.N30),  # d, e and vertex 0 collinear
    ((2, 2, 1), (2, 2, -1), FaceKind.T22),  # de crosses edge (1, 2): coplanar, boundary
    ((3, 3, 1), (3, 3, -1), FaceKind.N32),  # beyond edge (1, 2), which has 2 tetrahedra
    ((-1, 1, 1), (-1, 1, -1), FaceKind.N32),  # beyond edge (0, 2)
    ((6, -1, 1), (6, -1, -1), FaceKind.N20),  # beyond edges (0, 1) and (1, 2)
    ((6, -2, 1), (6, -2, -1), FaceKind.N40),  # on line (1, 2) beyond vertex 1
    ((5, -1, 1), (6, -2, -1), FaceKind.N40),  # de meets the plane on line (1, 2), outside
])
def test_the_classification_of_a_bipyramid(
    top: tuple[int, int, int], bottom: tuple[int, int, int], kind: FaceKind
) -> None:
    mesh = _bipyramid(top, bottom)
    assert classify_face(mesh, (0, 1, 2)).kind == kind


def test_flip22_swaps_the_diagonal_of_a_boundary_square() -> None:
    mesh = _bipyramid((2, 2, 1), (2, 2, -1))
    configuration = classify_face(mesh, (0, 1, 2))
    assert configuration.kind == FaceKind.T22 and configuration.edge == (1, 2)
    swapped = flip(mesh, "flip22", (0, 1, 2))
    assert validate3(swapped, volume=total_volume(mesh)) == []
    assert swapped.tetrahedron_count == 2
    assert {frozenset(t) for t in swapped.tetrahedra()} == {
        frozenset((0, 3, 4, 1)), frozenset((0, 3, 4, 2))
    }


def _octahedron() -> Mesh3:
    """Four tetrahedra around the axis (0, 1): a T44 at each of its four faces."""
    points = [(0, 0, -1), (0, 0, 1), (1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0)]
    ring = [2, 3, 4, 5]
    tetrahedra = [(0, 1, ring[i], ring[(i + 1) % 4]) for i in range(4)]
    return mesh3_from_tetrahedra(points, tetrahedra, orient=True)


def test_flip44_turns_the_axis_of_an_octahedron() -> None:
    mesh = _octahedron()
    assert validate3(mesh) == []
    face = (0, 1, 2)
    configuration = classify_face(mesh, face)
    assert configuration.kind == FaceKind.T44 and configuration.edge == (0, 1)
    turned = flip(mesh, "flip44", face)
    assert validate3(turned, volume=total_volume(mesh)) == []
    assert (0, 1) not in turned.edges()
    assert turned.tetrahedron_count == 4


# -- random walks of steps --------------------------------------------------------------
def _steps_available(mesh: Mesh3) -> list[tuple[str, tuple[int, ...]]]:
    """Every step that applies: a split of each edge, the flip of each transformable
    face."""
    available: list[tuple[str, tuple[int, ...]]] = [
        ("split_tetra", edge) for edge in mesh.edges()
    ]
    for face in mesh.interior_faces():
        configuration = classify_face(mesh, face)
        if configuration.transformable:
            available.append((FLIP_OF_KIND[configuration.kind], face))
    return available


@st.composite
def _jittered_cube(draw: st.DrawFn) -> Mesh3:
    scale = draw(st.sampled_from([mpq(1), mpq(1, 3), mpq(1000), mpq(-2, 7)]))
    shift = mpq(draw(st.integers(-5, 5)), 7)
    points = [tuple(mpq(c) * scale + shift for c in corner) for corner in CUBE]
    return mesh3_from_tetrahedra(points, FIVE, orient=True)


@settings(max_examples=30, deadline=None)
@given(_jittered_cube(), st.lists(st.integers(0, 10**6), min_size=1, max_size=12))
def test_random_walks_keep_every_invariant_and_replay(mesh: Mesh3, choices: list[int]) -> None:
    from geomexact.mesh3d.transient import Transient3
    from geomexact.trace.step import Step

    start = mesh
    volume = total_volume(start)
    snapshot_before = (start.digest, start.tetrahedra())
    transient = Transient3(start)
    current = start
    for choice in choices:
        available = _steps_available(current)
        op, args = available[choice % len(available)]
        current = apply(current, Step(op, args))
        transient.apply(Step(op, args))
        assert validate3(current, volume=volume) == [], (op, args)
    trace = trace_of(start, transient)
    batch = transient.seal()
    assert batch == current
    assert replay(start, trace) == current
    assert (start.digest, start.tetrahedra()) == snapshot_before
    assert full_digest3(current) == current.digest


def test_locally_non_delaunay_faces_are_found_exactly() -> None:
    # a flat bipyramid: the far apex is inside the sphere of the other tetrahedron
    mesh = _bipyramid((1, 1, mpq(1, 10)), (1, 1, mpq(-1, 10)))
    assert locally_non_delaunay_faces(mesh) == [(0, 1, 2)]
    improved = flip(mesh, "flip23", (0, 1, 2))
    assert is_delaunay3(improved)


def test_check3_raises_with_every_violation() -> None:
    mesh = cube()
    assert check3(mesh, volume=1) is mesh
    with pytest.raises(ValueError, match="volume"):
        check3(mesh, volume=2)


def test_every_permutation_of_input_orientation_is_accepted_with_orient() -> None:
    for order in itertools.permutations(range(4)):
        mesh = mesh3_from_tetrahedra(
            [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [order], orient=True
        )
        assert validate3(mesh, volume=mpq(1, 6)) == []
