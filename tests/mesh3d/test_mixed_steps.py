"""Mixed-mesh steps: each step's effect and preconditions, and property tests over random
box grids and random walks of steps (validity kept, volume exact and conserved, replay
gives the same meshes and digests, inputs never change, the same run twice gives the
same trace)."""

from __future__ import annotations

import random

import pytest
from helpers.mesh3d_cases import cube_grid
from helpers.mixed_cases import random_grid, random_walk
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import PreconditionError, TraceError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point3
from geomexact.mesh3d.cuboid.boxes import Box, unit_cube
from geomexact.mesh3d.mixed.cells import CellKind, cell_of_faces, reversed_face, standard_cell
from geomexact.mesh3d.mixed.conversion import box_grid_mesh, from_tetrahedral
from geomexact.mesh3d.mixed.ops import (
    OPERATIONS,
    add_cell,
    add_vertex,
    apply,
    merge_cells,
    remove_cell,
    split_cell,
)
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, empty_mixed_mesh, mixed_volume
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed
from geomexact.trace.playback import replay, replay_iter
from geomexact.trace.record import trace_of
from geomexact.trace.step import Step
from geomexact.trace.stepper import Stepper

CUBE = Box((0, 0, 0), (1, 1, 1))


def test_box_grid_is_valid_hexahedra_summing_to_the_box() -> None:
    box = Box((0, "-1/3", 2), (3, 1, "5/2"))
    mesh = box_grid_mesh(box, 3, 2, 2)
    assert mesh.cell_count == 12 and mesh.vertex_count == 36
    assert {cell.kind for cell in mesh.cell_list()} == {CellKind.HEXAHEDRON}
    assert validate_mixed(mesh, volume=box.volume) == []
    assert mixed_volume(mesh) == box.volume
    assert len(mesh.interior_faces()) == 2 * 2 * 2 + 3 * 1 * 2 + 3 * 2 * 1
    assert box_grid_mesh(box, 3, 2, 2) == mesh  # deterministic
    with pytest.raises(PreconditionError):
        box_grid_mesh(box, 0, 1, 1)


def test_from_tetrahedral_keeps_the_digest_and_volume() -> None:
    tetrahedral = cube_grid(2, 1, 1)
    mesh = from_tetrahedral(tetrahedral)
    assert mesh.digest == tetrahedral.digest
    assert mesh.cell_count == tetrahedral.tetrahedron_count == 12
    assert validate_mixed(mesh, volume=2) == []


def test_add_vertex_and_add_cell_build_a_mesh_step_by_step() -> None:
    mesh = empty_mixed_mesh()
    for corner in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), ("1/2", "1/2", 1)]:
        mesh = add_vertex(mesh, *corner)
    pyramid = standard_cell(CellKind.PYRAMID, range(5))
    built = add_cell(mesh, pyramid)
    assert built.cell_count == 1 and mixed_volume(built) == mpq(1, 3)
    assert validate_mixed(built, volume=mpq(1, 3)) == []
    assert mesh.cell_count == 0  # the input is unchanged
    with pytest.raises(PreconditionError, match="already"):
        add_cell(built, pyramid)
    inverted = standard_cell(CellKind.PYRAMID, (0, 3, 2, 1, 4))
    with pytest.raises(PreconditionError, match="non-positive-volume"):
        add_cell(mesh, inverted)
    assert remove_cell(built, pyramid) == mesh
    with pytest.raises(PreconditionError, match="not in the mesh"):
        remove_cell(mesh, pyramid)


def _at(mesh: MixedMesh3, *point: object) -> int:
    """The vertex at ``point``."""
    target = point3(*point)
    return next(v for v, p in mesh.vertices.items() if p == target)


def test_split_a_hexahedron_into_two_wedges_refines_the_neighbour_face() -> None:
    mesh = box_grid_mesh(CUBE, 2, 1, 1)
    left = next(c for c in mesh.cell_list() if _at(mesh, 0, 0, 0) in c.vertices)
    # the plane y = z: through the diagonal of the shared face x = 1/2
    plane = (_at(mesh, 0, 0, 0), _at(mesh, "1/2", 0, 0), _at(mesh, 0, 1, 1))
    result = split_cell(mesh, left, plane)
    kinds = sorted(cell.kind.name for cell in result.cell_list())
    assert kinds == ["POLYHEDRON", "WEDGE", "WEDGE"]
    right = next(c for c in result.cell_list() if c.kind == CellKind.POLYHEDRON)
    assert len(right.faces) == 7  # its face x = 1/2 is now the wedges' two triangles
    assert validate_mixed(result, volume=1) == []
    assert mesh == box_grid_mesh(CUBE, 2, 1, 1)


HEXAGON = [(2, 0), (1, 2), (-1, 2), (-2, 0), (-1, -2), (1, -2)]


def _hexagonal_prism() -> MixedMesh3:
    points = [(x, y, 0) for x, y in HEXAGON] + [(x, y, 1) for x, y in HEXAGON]
    faces = [(5, 4, 3, 2, 1, 0), (6, 7, 8, 9, 10, 11)]
    faces += [(i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6) for i in range(6)]
    return mixed_mesh_from_cells(points, [cell_of_faces(faces)])


def test_split_then_merge_gives_the_cell_back_with_its_faces_split() -> None:
    mesh = box_grid_mesh(CUBE, 1, 1, 1)
    (cube,) = mesh.cell_list()
    v = cube.vertices
    halves = split_cell(mesh, cube, (v[0], v[2], v[4]))
    assert [c.kind for c in halves.cell_list()] == [CellKind.WEDGE, CellKind.WEDGE]
    one, other = halves.cell_list()
    cut = next(f for f in one.faces if reversed_face(f) in other.faces)
    merged = merge_cells(halves, cut)
    (cell,) = merged.cell_list()
    assert cell.kind == CellKind.POLYHEDRON and len(cell.faces) == 8  # two faces split
    assert validate_mixed(merged, volume=1) == []


def test_split_preconditions() -> None:
    mesh = box_grid_mesh(CUBE, 1, 1, 1)
    (cube,) = mesh.cell_list()
    v = cube.vertices
    with pytest.raises(PreconditionError, match="does not cut"):  # a face's plane
        split_cell(mesh, cube, (v[0], v[1], v[2]))
    prism = _hexagonal_prism()
    assert validate_mixed(prism) == []
    (cell,) = prism.cell_list()
    with pytest.raises(PreconditionError, match="between its ends"):  # edge 3-9 crossed
        split_cell(prism, cell, (0, 2, 10))
    assert validate_mixed(split_cell(prism, cell, (0, 3, 6))) == []
    with pytest.raises(PreconditionError, match="three distinct"):
        split_cell(mesh, cube, (v[0], v[2], 99))


def test_merge_refuses_a_non_convex_union_and_a_boundary_face() -> None:
    mesh = box_grid_mesh(CUBE, 2, 2, 1)
    lower = [c for c in mesh.cell_list() if all(mesh.point(v).y <= mpq(1, 2) for v in c.vertices)]
    left = min(lower)
    shared = next(f for f in left.faces if mesh.neighbours(left, f)
                  and all(mesh.point(v).x == mpq(1, 2) for v in f))
    two = merge_cells(mesh, shared)
    box_cell = next(c for c in two.cell_list() if len(c.vertices) == 12)
    upper_face = next(f for f in box_cell.faces if two.neighbours(box_cell, f) and all(
        two.point(v).y == mpq(1, 2) for v in f) and all(two.point(v).x <= mpq(1, 2) for v in f))
    with pytest.raises(PreconditionError, match="not a valid cell"):  # an L shape
        merge_cells(two, upper_face)
    boundary = two.boundary_faces()[0]
    with pytest.raises(PreconditionError, match="exactly two"):
        merge_cells(two, boundary)


def test_unknown_and_malformed_steps_are_refused() -> None:
    mesh = box_grid_mesh(CUBE, 1, 1, 1)
    for step in [Step("flip23", (0, 1, 2)), Step("add_vertex", (1, 2)),
                 Step("split_cell", (0, 1)), Step("merge_cells", (0, 1))]:
        with pytest.raises(PreconditionError):
            apply(mesh, step)
    assert set(OPERATIONS) == {"add_vertex", "add_cell", "remove_cell", "merge_cells",
                               "split_cell"}


def _walk(seed: int, steps: int) -> tuple[Box, MixedMesh3, MixedMesh3, object]:
    rng = random.Random(seed)
    box, start = random_grid(rng)
    transient = start.transient()
    random_walk(transient, rng, steps)
    return box, start, transient.seal(), trace_of(start, transient)


@settings(max_examples=40)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12))
def test_random_walks_keep_the_mesh_valid_and_the_volume_exact(seed: int, steps: int) -> None:
    box, start, result, _ = _walk(seed, steps)
    assert validate_mixed(result, volume=box.volume) == []
    assert mixed_volume(result) == box.volume
    assert start == box_grid_mesh(box, *_grid_of(start, box))  # the start never changes


def _grid_of(mesh: MixedMesh3, box: Box) -> tuple[int, int, int]:
    xs = {p.x for p in mesh.vertices.values()}
    ys = {p.y for p in mesh.vertices.values()}
    zs = {p.z for p in mesh.vertices.values()}
    return len(xs) - 1, len(ys) - 1, len(zs) - 1


@settings(max_examples=30)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12))
def test_replay_reproduces_every_digest(seed: int, steps: int) -> None:
    box, start, result, trace = _walk(seed, steps)
    assert replay(start, trace) == result  # type: ignore[arg-type]
    meshes = list(replay_iter(start, trace))  # type: ignore[arg-type]
    assert [m.digest for m in meshes] == list(trace.digests)  # type: ignore[attr-defined]
    for mesh in meshes:
        assert validate_mixed(mesh, volume=box.volume) == []
    again = _walk(seed, steps)
    assert again[2] == result and again[3] == trace  # the same run, the same trace


def test_replay_refuses_a_changed_step() -> None:
    _, start, _, trace = _walk(7, 10)
    assert len(trace.steps) > 1  # type: ignore[attr-defined]
    steps = list(trace.steps)  # type: ignore[attr-defined]
    steps[0], steps[1] = steps[1], steps[0]
    import attrs

    changed = attrs.evolve(trace, steps=steps)  # type: ignore[misc]
    with pytest.raises(TraceError):
        replay(start, changed)


def test_the_stepper_walks_a_mixed_trace_back_and_forth() -> None:
    _, start, result, trace = _walk(11, 8)
    stepper = Stepper(start, trace)  # type: ignore[arg-type]
    assert stepper.goto(len(stepper)) == result
    assert stepper.goto(0) == start
    if len(stepper):
        stepper.goto(1)
        assert stepper.changed.removed or stepper.changed.added


def test_unit_cube_grid_hexahedra_are_in_lexicographic_vertex_order() -> None:
    mesh = box_grid_mesh(unit_cube(), 1, 1, 1)
    points = [mesh.point(v) for v in range(8)]
    assert points == sorted(points, key=lambda p: (p.x, p.y, p.z))
