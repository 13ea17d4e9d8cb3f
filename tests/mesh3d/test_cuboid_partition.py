"""The reference partition and improvement of 1-irregular cuboids, by property tests over
random patterns, boxes, orders and templates: validity with the exact volume, positive
orientation, interior faces shared by two tetrahedra, boundary triangulations that depend
only on the face's own Steiner points, replay = result, and an improvement that keeps all
of it, terminates and leaves no transformable face failing its sphere test."""

from __future__ import annotations

import attrs
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import PreconditionError
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.improvement import improve
from geomexact.mesh3d.cuboid.numbering import FACE_EDGES, PATTERN_COUNT
from geomexact.mesh3d.cuboid.partition import CuboidMesh, partition_cuboid, recorded_start
from geomexact.mesh3d.cuboid.split_order import ORDERS
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.ops import FaceKind, classify_face
from geomexact.mesh3d.validation import validate3
from geomexact.trace.playback import replay

BOXES = [
    unit_cube(),
    box_of_extents(1, 2, 4),  # x extent 1, y extent 2, z extent 4
    Box(("-1/3", 2, "0.5"), (1, "17/7", 3)),  # any exact rational box
]

patterns = st.integers(0, PATTERN_COUNT - 1)
boxes = st.sampled_from(BOXES)
orders = st.sampled_from(ORDERS)
templates = st.sampled_from([0, 1])


def face_pattern(pattern: int, face_bit: int) -> int:
    """The bits of ``pattern`` on face ``face_bit``: its centre and its four edges."""
    own = (1 << face_bit) | sum(1 << edge for edge in FACE_EDGES[face_bit - 12])
    return pattern & own


def assert_valid(run: CuboidMesh) -> None:
    box = run.box
    for mesh in (run.partition, run.mesh):
        assert validate3(mesh, volume=box.volume) == []
        assert total_volume(mesh) == box.volume
        for tetrahedron in mesh.tetrahedra():
            assert orient3d(*(mesh.point(v) for v in tetrahedron)) > 0
        # every face is interior (two tetrahedra, both orientations) or on the box
        for a, b, c in mesh.faces:
            if mesh.apex(a, c, b) is None:
                points = [mesh.point(v) for v in (a, b, c)]
                assert any(
                    len({p[axis] for p in points}) == 1
                    and points[0][axis] in (box.low[axis], box.high[axis])
                    for axis in range(3)
                )


@settings(deadline=None)
@given(patterns, boxes, orders, templates)
def test_the_partition_is_valid_with_the_exact_volume_and_replays(
    pattern: int, box: Box, order: str, template: int
) -> None:
    run = partition_cuboid(pattern, box, order=order, template=template)
    assert_valid(run)
    assert run.partition is run.mesh and run.improvement is None
    assert run.mesh.vertex_count == 8 + bin(pattern).count("1")
    assert [step.op for step in run.trace.steps] == ["split_tetra"] * bin(pattern).count("1")
    assert replay(run.start, run.trace) == run.mesh
    for bit, vertex in run.steiner:
        assert run.mesh.point(vertex) == box.steiner_point(bit)


@settings(deadline=None)
@given(patterns, boxes, orders, templates)
def test_each_box_face_is_triangulated_by_its_own_steiner_points(
    pattern: int, box: Box, order: str, template: int
) -> None:
    faces = partition_cuboid(pattern, box, order=order, template=template).face_triangulations()
    for face_bit in range(12, 18):
        alone = partition_cuboid(face_pattern(pattern, face_bit), box, order=order,
                                 template=template)
        assert alone.face_triangulations()[face_bit] == faces[face_bit]
        other = partition_cuboid(face_pattern(pattern, face_bit), unit_cube(), order=order,
                                 template=template)
        assert other.face_triangulations()[face_bit] == faces[face_bit]  # any box


@settings(deadline=None)
@given(patterns, boxes, orders, templates, st.booleans())
def test_the_improvement_keeps_validity_terminates_and_leaves_no_failing_transformable_face(
    pattern: int, box: Box, order: str, template: int, boundary: bool
) -> None:
    run = partition_cuboid(pattern, box, order=order, template=template, improve=True,
                           allow_boundary_flips=boundary)
    assert_valid(run)
    assert replay(run.start, run.trace) == run.mesh
    report = run.improvement
    assert report is not None
    flips = [step.op for step in run.trace.steps if step.op != "split_tetra"]
    assert len(flips) == report.flip_count
    assert ("flip22" in flips) <= boundary
    flippable = {FaceKind.T23, FaceKind.T32, FaceKind.T44} | ({FaceKind.T22} if boundary
                                                              else set())
    from geomexact.mesh3d.measures import locally_non_delaunay_faces

    failing = locally_non_delaunay_faces(run.mesh)
    kinds = {classify_face(run.mesh, face).kind for face in failing}
    assert not kinds & flippable
    assert tuple(sorted(kind.value for kind in kinds)) == report.failing_kinds
    if not boundary:  # the box's faces are untouched
        assert run.face_triangulations() == run.face_triangulations(run.partition)
    # improving the improved mesh again does nothing
    again, second = improve(run.mesh, allow_boundary_flips=boundary)
    assert second.flip_count == 0 and again == run.mesh


def test_pattern_zero_is_the_five_tetrahedra_and_already_delaunay() -> None:
    run = partition_cuboid(0, improve=True)
    assert run.mesh.tetrahedron_count == 5 and run.mesh == run.start
    assert run.improvement is not None and run.improvement.flip_count == 0
    assert len(run.trace) == 0


def test_every_single_steiner_point_makes_a_locally_non_delaunay_face() -> None:
    """docs/cuboid.md: why hardly any partition is Delaunay as made.  The eight corners are
    cospherical; a Steiner point inside that sphere makes a tetrahedron whose sphere
    bulges past it across the opposite face, and takes in the corner beyond."""
    from geomexact.mesh3d.measures import is_delaunay3

    for box in BOXES[:2]:
        for bit in range(18):
            for template in (0, 1):
                assert not is_delaunay3(partition_cuboid(1 << bit, box,
                                                         template=template).partition)


def test_the_full_pattern_on_both_shapes() -> None:
    for box in BOXES[:2]:
        for order in ORDERS:
            run = partition_cuboid(PATTERN_COUNT - 1, box, order=order, improve=True)
            assert_valid(run)
            assert run.partition.tetrahedron_count == 40
            assert replay(run.start, run.trace) == run.mesh


def test_recorded_start_rebuilds_the_start_from_the_trace_alone() -> None:
    """recorded_start(trace) is the run's start for any box and template; a trace of
    another algorithm, a malformed box or template is a PreconditionError."""
    for template in (0, 1):
        run = partition_cuboid(70688, Box(("-1/3", 0, 2), (1, "0.5", 7)), template=template,
                               improve=True)
        assert recorded_start(run.trace) == run.start
        assert recorded_start(run.trace).digest == run.trace.input_digest
    parameters = dict(run.trace.parameters)
    for bad in ({"algorithm": "lepp"}, {"box": {"low": [0, 0]}}, {"template": 2},
                {"box": {"low": [1, 0, 0], "high": [0, 1, 1]}}, {"box": {"low": "x"}}):
        with pytest.raises(PreconditionError):
            recorded_start(attrs.evolve(run.trace, parameters={**parameters, **bad}))
