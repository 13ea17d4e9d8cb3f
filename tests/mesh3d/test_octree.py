"""The octree mesher: regions and criteria (exact), refinement, 2:1 balance across faces and
edges, the final partition's conformity (checked exactly on every mesh), replay = result,
the fast assembly equal to the reference steps, and every stage swappable for its
identity."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import InvalidMeshError, PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents, unit_cube
from geomexact.mesh3d.octree.balance import (
    balance_two_to_one,
    irregular_leaves,
    tiling_problems,
)
from geomexact.mesh3d.octree.conformity import lattice_conformity
from geomexact.mesh3d.octree.criteria import (
    AllOf,
    AspectRatio,
    MaxEdgeLength,
    MinEdgeLength,
    RadiusEdgeRatio,
    RefineToMaxLevel,
    ScalarFieldVariation,
    VolumeEdgeRatio,
)
from geomexact.mesh3d.octree.lattice import octree_lattice
from geomexact.mesh3d.octree.leaf_partition import assemble_tetrahedra
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.refinement import refine_octree
from geomexact.mesh3d.octree.regions import (
    BallRegion,
    BoxRegion,
    PointRegion,
    SegmentRegion,
    SphereSurfaceRegion,
    UnionRegion,
    WholeDomain,
)
from geomexact.mesh3d.octree.stages import (
    BalanceTwoToOne,
    BoxGrid,
    DelaunayPartition,
    NoImprovement,
    NoRefinement,
    PatternPartition,
    RefineWhere,
    SingleBox,
)
from geomexact.mesh3d.octree.tree import Octree, cell_children, octree_of_grid
from geomexact.mesh3d.validation import validate3
from geomexact.trace.playback import replay

CENTRE = ("1/2", "1/2", "1/2")


def sphere_run(level: int, *, surface: bool = True, final: object = None, trace: bool = True,
               domain: Box | None = None, grid: tuple[int, int, int] = (1, 1, 1)):
    region = (SphereSurfaceRegion if surface else BallRegion)(CENTRE, "0.3")
    return generate(domain or unit_cube(), initial=BoxGrid(*grid),
                    refinement=RefineWhere(level, region=region),
                    final=final or PatternPartition(), trace=trace)


# -- regions and criteria ------------------------------------------------------------------
class TestRegions:
    def test_ball_meets_a_box_through_its_nearest_point(self) -> None:
        ball = BallRegion((0, 0, 0), 1)
        assert ball(Box((1, 0, 0), (2, 1, 1)))  # touches at (1, 0, 0): closed
        assert not ball(Box(("1.01", 0, 0), (2, 1, 1)))
        assert ball(Box(("-0.5", "-0.5", "-0.5"), ("0.5", "0.5", "0.5")))

    def test_surface_misses_a_box_strictly_inside_or_outside(self) -> None:
        sphere = SphereSurfaceRegion((0, 0, 0), 1)
        assert not sphere(Box(("-0.1", "-0.1", "-0.1"), ("0.1", "0.1", "0.1")))
        assert not sphere(Box((2, 2, 2), (3, 3, 3)))
        assert sphere(Box(("0.5", 0, 0), ("1.5", "0.1", "0.1")))

    def test_exact_tangency_counts(self) -> None:
        # the box [1/3, 1] x .. touches the ball of radius 1/3 at the origin's distance exactly
        assert BallRegion((0, "0.5", "0.5"), "1/3")(Box(("1/3", 0, 0), (1, 1, 1)))
        assert not BallRegion((0, "0.5", "0.5"), "1/3")(Box(("0.33333334", 0, 0), (1, 1, 1)))

    def test_point_segment_box_union_whole(self) -> None:
        cell = Box((0, 0, 0), (1, 1, 1))
        assert PointRegion((1, 1, 1))(cell) and not PointRegion((1, 1, "1.5"))(cell)
        assert SegmentRegion((2, 2, 2), ("0.5", "0.5", "0.5"))(cell)
        assert not SegmentRegion((2, 0, 0), (2, 1, 1))(cell)
        assert not SegmentRegion((2, 2, 0), (3, "1.5", 0))(cell)  # its line crosses, it does not
        assert BoxRegion((1, 1, 1), (2, 2, 2))(cell)  # shares a corner
        assert not BoxRegion(("1.5", 0, 0), (2, 1, 1))(cell)
        assert UnionRegion([PointRegion((5, 5, 5)), BoxRegion((0, 0, 0), (0, 0, 0))])(cell)
        assert WholeDomain()(cell)

    def test_bad_regions_are_refused(self) -> None:
        with pytest.raises(PreconditionError):
            BallRegion((0, 0, 0), 0)
        with pytest.raises(PreconditionError):
            BoxRegion((1, 0, 0), (0, 1, 1))


class TestCriteria:
    def test_edge_lengths(self) -> None:
        box = box_of_extents(1, 2, 4)
        assert MaxEdgeLength(4)(box) and not MaxEdgeLength("3.99")(box)
        assert MinEdgeLength(1)(box) and not MinEdgeLength("0.99")(box)

    def test_shape_ratios_exact(self) -> None:
        cube = unit_cube()
        # the cube's radius-edge ratio is sqrt(3)/2 = 0.866..: 0.866 fails, 0.867 holds
        assert not RadiusEdgeRatio("0.866")(cube) and RadiusEdgeRatio("0.867")(cube)
        assert AspectRatio(1)(cube) and not AspectRatio(3)(box_of_extents(1, 2, 4))
        assert VolumeEdgeRatio(1)(cube) and not VolumeEdgeRatio("0.2")(box_of_extents(1, 2, 4))

    def test_scalar_field_and_combinations(self) -> None:
        field = ScalarFieldVariation(lambda x, y, z: 10 * x, "5")
        assert field(box_of_extents("0.5", 1, 1)) and not field(box_of_extents("0.6", 1, 1))
        assert not RefineToMaxLevel()(unit_cube())
        assert not AllOf([MaxEdgeLength(2), MaxEdgeLength("0.5")])(unit_cube())


# -- refinement and balance ----------------------------------------------------------------
def test_refinement_splits_only_where_the_region_meets_and_the_criterion_fails() -> None:
    tree = refine_octree(octree_of_grid(unit_cube()), MaxEdgeLength("0.25"),
                         PointRegion((0, 0, 0)), 5)
    assert sorted({cell[0] for cell in tree.leaves}) == [1, 2]
    assert tree.leaf_count == 1 + 7 + 7
    assert tiling_problems(tree) == []


def test_refining_toward_a_point_grades_itself() -> None:
    graded = refine_octree(octree_of_grid(unit_cube()), RefineToMaxLevel(),
                           PointRegion(("0.01", "0.01", "0.01")), 4)
    assert irregular_leaves(graded) == []


def test_balance_splits_coarse_face_and_edge_neighbours() -> None:
    # next to the plane x = 1/2, level-4 leaves face the level-1 octant beyond it
    deep = refine_octree(octree_of_grid(unit_cube()), RefineToMaxLevel(),
                         PointRegion(("0.49", "0.01", "0.01")), 4)
    assert irregular_leaves(deep)
    balanced = balance_two_to_one(deep)
    assert irregular_leaves(balanced) == [] and tiling_problems(balanced) == []
    assert set(deep.leaves) - set(balanced.leaves)  # something was split
    assert balance_two_to_one(balanced) == balanced


def test_edge_only_neighbours_are_balanced_too() -> None:
    # octants (1,0,0,0), (1,1,0,0), (1,0,1,0) at level 2, and the level-2 cell (2,1,1,0)
    # at level 3: its corner cell (3,3,3,0) has fine face neighbours everywhere, but touches
    # the level-1 octant (1,1,1,0) along the edge x = y = 1/2 only
    refined = {(1, 0, 0, 0), (1, 1, 0, 0), (1, 0, 1, 0)}
    leaves = [c for c in cell_children((0, 0, 0, 0)) if c not in refined]
    for octant in sorted(refined):
        leaves += [c for c in cell_children(octant) if c != (2, 1, 1, 0)]
    leaves += cell_children((2, 1, 1, 0))
    tree = Octree(unit_cube(), (1, 1, 1), leaves)
    assert tiling_problems(tree) == []
    assert irregular_leaves(tree) == [((3, 3, 3, 0), (2, 2, 2, 0)),
                                      ((3, 3, 3, 1), (2, 2, 2, 0))]
    balanced = balance_two_to_one(tree)
    assert irregular_leaves(balanced) == []
    assert (1, 1, 1, 0) not in balanced.leaves
    run = generate(unit_cube(), initial=lambda domain: tree, improvement=NoImprovement())
    assert run.leaf_mesh.forced_splits == 1 and run.conformity.conforming


def _balanced_by_rounds(grid: tuple[int, int, int],
                        leaves: set[tuple[int, int, int, int]]) -> set[tuple[int, ...]]:
    """The 2:1 balance by its definition, on plain sets (no geomexact code): while a leaf
    of level L touches, across a face or an edge, a cell of level L-1 lying inside a
    coarser leaf, split that coarser leaf once."""
    leaves = set(leaves)
    offsets = [(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)
               if 1 <= abs(x) + abs(y) + abs(z) <= 2]

    def covering(cell: tuple[int, int, int, int]) -> tuple[int, int, int, int] | None:
        level, i, j, k = cell
        for up in range(1, level + 1):
            above = (level - up, i >> up, j >> up, k >> up)
            if above in leaves:
                return above
        return None

    while True:
        coarse = set()
        for level, i, j, k in leaves:
            for x, y, z in offsets:
                a, b, c = i + x, j + y, k + z
                if not all(0 <= v < n << level for v, n in zip((a, b, c), grid, strict=True)):
                    continue
                target = (level - 1, a >> 1, b >> 1, c >> 1)
                if level >= 2 and target not in leaves:
                    found = covering(target)
                    if found is not None:
                        coarse.add(found)
        if not coarse:
            return leaves
        for level, i, j, k in coarse:
            leaves.discard((level, i, j, k))
            leaves.update((level + 1, 2 * i + (o & 1), 2 * j + (o >> 1 & 1),
                           2 * k + (o >> 2 & 1)) for o in range(8))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 63), st.integers(0, 63),
                          st.integers(0, 63)), min_size=1, max_size=12),
       st.sampled_from([(1, 1, 1), (2, 1, 1), (1, 2, 3)]))
def test_balance_equals_rounds_of_forced_splits(picks: list[tuple[int, int, int, int]],
                                                grid: tuple[int, int, int]) -> None:
    """The level-by-level balance gives the leaves of the definition (rounds of forced
    splits until none is needed) on random unbalanced octrees: refine toward random
    points down to level 5, one chain each."""
    leaves = {(0, i, j, k) for i in range(grid[0]) for j in range(grid[1])
              for k in range(grid[2])}
    for depth, x, y, z in picks:  # split the chain of cells above a level-5 cell
        cell = (5, x % (grid[0] << 5), y % (grid[1] << 5), z % (grid[2] << 5))
        chain = [(level, cell[1] >> (5 - level), cell[2] >> (5 - level),
                  cell[3] >> (5 - level)) for level in range(depth + 2)]
        for above in chain[:-1]:
            if above in leaves:
                leaves.discard(above)
                level, i, j, k = above
                leaves.update((level + 1, 2 * i + (o & 1), 2 * j + (o >> 1 & 1),
                               2 * k + (o >> 2 & 1)) for o in range(8))
    tree = Octree(box_of_extents(*grid), grid, sorted(leaves))
    balanced = balance_two_to_one(tree)
    assert set(balanced.leaves) == _balanced_by_rounds(grid, leaves)
    assert irregular_leaves(balanced) == [] and tiling_problems(balanced) == []


def test_tiling_problems_name_overlaps_and_gaps() -> None:
    assert tiling_problems(Octree(unit_cube(), (1, 1, 1), [(0, 0, 0, 0), (1, 0, 0, 0)]))
    assert tiling_problems(Octree(unit_cube(), (1, 1, 1), [(1, 0, 0, 0)]))
    assert tiling_problems(Octree(unit_cube(), (1, 1, 1), [(0, 1, 0, 0)]))


# -- the final mesh ------------------------------------------------------------------------
@pytest.mark.parametrize("surface", [True, False])
def test_sphere_level3_conforms_with_the_exact_volume(surface: bool) -> None:
    run = sphere_run(3, surface=surface)
    assert run.conformity.conforming and run.volume == 1
    assert validate3(run.mesh, volume=1) == []
    assert irregular_leaves(run.octree) == []
    assert replay(run.start, run.trace) == run.mesh


@pytest.mark.parametrize("final", [PatternPartition(), DelaunayPartition()])
def test_fast_assembly_equals_the_reference_steps(final: object) -> None:
    reference = sphere_run(3, final=final, trace=True)
    fast = sphere_run(3, final=final, trace=False)
    assert fast.mesh == reference.mesh and fast.trace is None
    assert np.array_equal(np.sort(np.sort(fast.leaf_mesh.tetrahedra, axis=1), axis=0),
                          np.sort(np.sort(reference.leaf_mesh.tetrahedra, axis=1), axis=0))


def test_delaunay_variant_flips_inside_leaves_only() -> None:
    run = sphere_run(3, final=DelaunayPartition())
    plain = sphere_run(3)
    flips = [step for step in run.trace.steps if step.op.startswith("flip")]
    assert flips and all(step.op != "flip22" for step in flips)
    assert run.mesh.boundary_faces() == plain.mesh.boundary_faces()
    assert validate3(run.mesh, volume=1) == []


def test_a_stretched_rational_domain_with_a_grid() -> None:
    domain = Box(("-1/3", 0, 2), (1, 2, "6.5"))  # x extent 4/3, y 2, z 9/2
    run = generate(domain, initial=BoxGrid(1, 2, 3),
                   refinement=RefineWhere(2, region=BallRegion((0, 1, 4), "0.7")))
    assert run.conformity.conforming and run.volume == domain.volume
    assert validate3(run.mesh, volume=domain.volume) == []
    assert replay(run.start, run.trace) == run.mesh


@pytest.mark.parametrize("stage", ["initial", "refinement", "improvement"])
def test_each_stage_swapped_for_its_identity_still_conforms(stage: str) -> None:
    stages = {"initial": BoxGrid(2, 1, 1),
              "refinement": RefineWhere(3, region=PointRegion(("0.3", "0.2", "0.1"))),
              "improvement": BalanceTwoToOne()}
    stages[stage] = {"initial": SingleBox(), "refinement": NoRefinement(),
                     "improvement": NoImprovement()}[stage]
    run = generate(unit_cube(), **stages)
    assert run.conformity.conforming and validate3(run.mesh, volume=1) == []
    if stage == "improvement":
        assert run.leaf_mesh.forced_splits > 0  # the final stage balanced it itself


def test_user_stages_are_plain_callables() -> None:
    def halves(domain: Box) -> Octree:
        return octree_of_grid(domain, (2, 1, 1))

    def first_octant(octree: Octree) -> Octree:
        return Octree(octree.domain, octree.grid,
                      [*octree.leaves[1:], *cell_children(octree.leaves[0])])

    run = generate(unit_cube(), initial=halves, refinement=first_octant)
    assert run.octree.leaf_count == 9 and run.conformity.conforming


def test_a_broken_user_stage_is_reported_not_meshed() -> None:
    def gap(octree: Octree) -> Octree:
        return Octree(octree.domain, octree.grid, octree.leaves[1:])

    with pytest.raises(InvalidMeshError):
        generate(unit_cube(), initial=BoxGrid(2, 1, 1), refinement=gap, trace=False)


def test_conformity_check_catches_a_missing_or_inverted_tetrahedron() -> None:
    run = sphere_run(2, trace=False)
    lattice = run.leaf_mesh.lattice
    tetrahedra = np.array(run.leaf_mesh.tetrahedra)
    assert lattice_conformity(lattice.vertices, tetrahedra, lattice.size).conforming
    assert not lattice_conformity(lattice.vertices, tetrahedra[1:], lattice.size).conforming
    inverted = tetrahedra.copy()
    inverted[0, [0, 1]] = inverted[0, [1, 0]]
    report = lattice_conformity(lattice.vertices, inverted, lattice.size)
    assert not report.conforming and "not positive" in report.problems[0]


def test_unbalanced_leaves_do_not_conform_without_the_balance() -> None:
    deep = refine_octree(octree_of_grid(unit_cube()), RefineToMaxLevel(),
                         PointRegion(("0.49", "0.01", "0.01")), 3)
    assert irregular_leaves(deep)
    lattice = octree_lattice(deep)
    report = lattice_conformity(lattice.vertices, assemble_tetrahedra(lattice), lattice.size)
    assert not report.conforming


def test_volume_report_is_exact_rational() -> None:
    run = generate(box_of_extents("1/3", 1, 1), refinement=RefineWhere(1), trace=False)
    assert run.volume == mpq(1, 3) and run.octree.leaf_count == 8


# -- property tests ------------------------------------------------------------------------
coordinates = st.fractions(0, 1, max_denominator=8).map(str)


@settings(max_examples=15)
@given(
    centre=st.tuples(coordinates, coordinates, coordinates),
    radius=st.fractions("1/16", "3/4", max_denominator=16).map(str),
    level=st.integers(0, 3),
    grid=st.tuples(st.integers(1, 2), st.integers(1, 2), st.integers(1, 2)),
    surface=st.booleans(),
    delaunay=st.booleans(),
)
def test_random_refinements_conform_and_replay(centre, radius, level, grid, surface,
                                                delaunay) -> None:
    region = (SphereSurfaceRegion if surface else BallRegion)(centre, radius)
    domain = box_of_extents(*grid)
    final = DelaunayPartition() if delaunay else PatternPartition()
    run = generate(domain, initial=BoxGrid(*grid), refinement=RefineWhere(level, region=region),
                   final=final)
    assert run.conformity.conforming and run.volume == domain.volume
    assert irregular_leaves(run.octree) == [] and tiling_problems(run.octree) == []
    assert validate3(run.mesh, volume=domain.volume) == []
    assert replay(run.start, run.trace) == run.mesh
    fast = generate(domain, initial=BoxGrid(*grid), refinement=RefineWhere(level, region=region),
                    final=final, trace=False)
    assert fast.mesh == run.mesh


# -- the building blocks -------------------------------------------------------------------
def test_bulk_build_equals_the_checked_build() -> None:
    from geomexact.mesh3d.transient import mesh3_from_positive_arrays, mesh3_from_tetrahedra

    run = sphere_run(2, trace=False)
    points = run.leaf_mesh.lattice.exact_points()
    tetrahedra = np.asarray(run.leaf_mesh.tetrahedra)
    assert mesh3_from_positive_arrays(points, tetrahedra) == mesh3_from_tetrahedra(
        points, tetrahedra.tolist())
    with pytest.raises(PreconditionError):
        mesh3_from_positive_arrays(points, np.concatenate((tetrahedra, tetrahedra[:1])))


@settings(max_examples=30)
@given(pattern=st.integers(0, (1 << 18) - 1), template=st.sampled_from([0, 1]),
       improve=st.booleans())
def test_vectorised_tables_equal_their_definitions(pattern, template, improve) -> None:
    from geomexact.mesh3d.cuboid.partition import partition_cuboid
    from geomexact.mesh3d.snapshot import canonical_tetrahedron, opposite_face, undirected

    mesh = partition_cuboid(pattern, box_of_extents(1, 2, 4), template=template,
                            improve=improve).mesh
    faces = mesh.faces
    assert mesh.tetrahedra() == sorted(canonical_tetrahedron(a, b, c, d)
                                       for (a, b, c), d in faces.items() if d < min(a, b, c))
    assert mesh.boundary_faces() == sorted(opposite_face(f) for f in faces
                                           if opposite_face(f) not in faces)
    assert mesh.interior_faces() == sorted(tuple(sorted(f)) for f in faces
                                           if opposite_face(f) in faces and f < opposite_face(f))
    assert mesh.edges() == sorted({undirected(u, v) for a, b, c in faces
                                   for u, v in ((a, b), (b, c), (c, a))})


def test_insert_cuboid_checks_its_box() -> None:
    from geomexact.kernel.points import point3
    from geomexact.mesh3d.cuboid.insertion import ABSENT, insert_cuboid_in
    from geomexact.mesh3d.cuboid.numbering import CORNER_POSITIONS
    from geomexact.mesh3d.cuboid.partition import partition_cuboid
    from geomexact.mesh3d.ops import apply
    from geomexact.mesh3d.snapshot import empty_mesh3
    from geomexact.trace.step import Step

    t = empty_mesh3().transient()
    for x, y, z in CORNER_POSITIONS:
        t.add_vertex(point3(2 * x, 3 * y, z))
    centre = t.add_vertex(point3(1, 0, "0.5"))  # the centre of face y=0 (bit 14)
    steiner = [ABSENT] * 18
    steiner[14] = centre
    start = t.seal()
    mesh = apply(start, Step("insert_cuboid", (1, *range(8), *steiner)))
    expected = partition_cuboid(1 << 14, box_of_extents(2, 3, 1), template=1).mesh
    assert mesh.tetrahedra() == expected.tetrahedra()  # the same ids: corners, then 8
    assert validate3(mesh, volume=6) == []
    with pytest.raises(PreconditionError, match="corner"):
        apply(start, Step("insert_cuboid", (1, 1, 0, *range(2, 8), *steiner)))
    wrong = list(steiner)
    wrong[14], wrong[15] = ABSENT, centre
    with pytest.raises(PreconditionError, match="Steiner"):
        apply(start, Step("insert_cuboid", (1, *range(8), *wrong)))
    with pytest.raises(PreconditionError, match="already"):
        apply(mesh, Step("insert_cuboid", (1, *range(8), *steiner)))
    with pytest.raises(PreconditionError):
        insert_cuboid_in(start.transient(), 2, list(range(8)), steiner)


def test_quality_of_the_regular_tetrahedron() -> None:
    from geomexact.mesh3d.quality import dihedral_angles, quality_summary, radius_edge_ratios

    points = [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)]
    tetrahedron = [[0, 1, 2, 3]]
    assert np.allclose(dihedral_angles(points, tetrahedron), np.degrees(np.arccos(1 / 3)))
    assert np.allclose(radius_edge_ratios(points, tetrahedron), np.sqrt(6) / 4)
    assert quality_summary(points, []).min_dihedral is None


def test_bulk_digest_equals_the_sum_of_the_element_hashes() -> None:
    import random

    import gmpy2

    from geomexact.kernel import digest as _digest
    from geomexact.kernel.points import Point3, point3
    from geomexact.mesh3d.cuboid.compiled import AVAILABLE, bulk_digest
    from geomexact.mesh3d.transient import _bulk_digest, _canonical_rows, reference_bulk_digest

    chooser = random.Random(7)
    rows = _canonical_rows(np.array([chooser.sample(range(3000), 4) for _ in range(5000)],
                                    dtype=np.int64))
    values = [0, 1, -1, "1/3", "-7/64", "123456789/1024", "1e-30", 2**70, mpq(-2**80, 3)]
    points = [point3(*chooser.choices(values, k=3)) for _ in range(3000)]
    expected = (sum(_digest.vertex_hash(v, p[:3]) for v, p in enumerate(points))
                + sum(_digest.cell_hash(row) for row in rows.tolist())) % _digest.MODULUS
    assert reference_bulk_digest(points, rows) == expected
    assert _bulk_digest(points, rows) == expected
    assert _bulk_digest(points[:0], rows[:0]) == 0
    assert _bulk_digest(points, rows[:0]) == sum(
        _digest.vertex_hash(v, p[:3]) for v, p in enumerate(points)) % _digest.MODULUS
    if AVAILABLE:  # the kernel itself, not the fallback
        assert bulk_digest(points, rows) == expected
        # a coordinate whose binary is beyond the kernel's 40 bytes: the reference's turn
        assert bulk_digest([point3(2**400, 0, 0)], rows[:0]) is None
        # an mpz beside an equal mpq encodes differently: the reference's turn too
        mixed = [point3(1, 0, 0), Point3(gmpy2.mpz(1), mpq(0), mpq(0), 1.0, 0.0, 0.0)]
        assert bulk_digest(mixed, rows[:0]) is None
        assert _bulk_digest(mixed, rows[:0]) == reference_bulk_digest(mixed, rows[:0])
        keys = __import__("geomexact.mesh3d.cuboid.cuboid_kernel",
                          fromlist=["vertex_keys"]).vertex_keys(0, 5000)
        assert keys == [_digest.vertex_key(v) for v in range(5000)]


def test_a_balanced_octree_is_not_balanced_again() -> None:
    tree = balance_two_to_one(refine_octree(octree_of_grid(unit_cube()), RefineToMaxLevel(),
                                            PointRegion(("0.49", "0.01", "0.01")), 3))
    assert tree.balanced and balance_two_to_one(tree) is tree
    assert tree == Octree(tree.domain, tree.grid, tree.leaves)  # the flag is not content


def _naive_face_report(tetrahedra: list[list[int]]) -> tuple[int, int, int, int]:
    """(interior faces, boundary faces, faces of more than two tetrahedra, faces with both
    tetrahedra on one side), by plain sets: each face's sorted ids, and its orientation
    as the parity of the sorting permutation."""
    seen: dict[tuple[int, ...], list[int]] = {}
    for a, b, c, d in tetrahedra:
        for face in ((a, b, c), (a, c, d), (a, d, b), (b, d, c)):
            inversions = sum(face[i] > face[j] for i in range(3) for j in range(i + 1, 3))
            seen.setdefault(tuple(sorted(face)), []).append(inversions % 2)
    return (sum(len(p) == 2 for p in seen.values()), sum(len(p) == 1 for p in seen.values()),
            sum(len(p) > 2 for p in seen.values()),
            sum(len(p) == 2 and sum(p) != 1 for p in seen.values()))


@settings(max_examples=25, deadline=None)
@given(st.data())
def test_conformity_counts_faces_as_plain_sets_do(data: st.DataObject) -> None:
    """The face counts and the problems the sorted keys find, on a real octree mesh with
    tetrahedra dropped, repeated or inverted, against a plain-set count."""
    run = sphere_run(2, trace=False)
    lattice = run.leaf_mesh.lattice
    tetrahedra = np.array(run.leaf_mesh.tetrahedra).tolist()
    for _ in range(data.draw(st.integers(0, 3))):
        row = data.draw(st.integers(0, len(tetrahedra) - 1))
        change = data.draw(st.sampled_from(["drop", "repeat", "invert"]))
        if change == "drop":
            del tetrahedra[row]
        elif change == "repeat":
            tetrahedra.append(list(tetrahedra[row]))
        else:
            tetrahedra[row] = [tetrahedra[row][1], tetrahedra[row][0], *tetrahedra[row][2:]]
    report = lattice_conformity(lattice.vertices, np.array(tetrahedra, dtype=np.int64),
                                lattice.size)
    interior, boundary, over, same_side = _naive_face_report(tetrahedra)
    assert (report.interior_faces, report.boundary_faces) == (interior, boundary)
    assert any("more than two" in p for p in report.problems) == (over > 0)
    assert any("on one side" in p for p in report.problems) == (same_side > 0)
    original = sorted(map(tuple, np.array(run.leaf_mesh.tetrahedra).tolist()))
    assert report.conforming == (sorted(map(tuple, tetrahedra)) == original)
    empty = lattice_conformity(lattice.vertices, np.zeros((0, 4), dtype=np.int64),
                               lattice.size)
    assert (empty.interior_faces, empty.boundary_faces) == (0, 0) and not empty.conforming


def test_conformity_kernel_pass_equals_numpy() -> None:
    """The compiled kernel's one pass (``lattice_faces``) gives the numpy determinants and
    face keys, bit for bit (wrapping int64 included); the reports agree either way."""
    from geomexact.mesh3d.cuboid import compiled
    from geomexact.mesh3d.octree import conformity

    if not compiled.AVAILABLE:
        pytest.skip("the compiled cuboid kernel is not built")
    run = sphere_run(3, trace=False)
    lattice = run.leaf_mesh.lattice
    tetrahedra = np.array(run.leaf_mesh.tetrahedra, dtype=np.int64)
    rng = np.random.default_rng(5)
    broken = tetrahedra.copy()
    broken[rng.integers(0, len(broken), 40), rng.integers(0, 4, 40)] = rng.integers(
        0, lattice.vertex_count, 40)
    huge = np.asarray(lattice.vertices, dtype=np.int64) * (1 << 50)  # products wrap
    for points, rows in ((lattice.vertices, tetrahedra), (lattice.vertices, broken),
                         (huge, tetrahedra), (lattice.vertices, tetrahedra[:, [1, 0, 2, 3]])):
        points, rows = np.asarray(points, dtype=np.int64), np.ascontiguousarray(rows)
        base = np.uint64(len(points))
        found = compiled.lattice_faces(points, rows, base)
        assert found is not None
        det, keys = found
        assert np.array_equal(det, conformity._det6(points, rows))
        assert np.array_equal(keys, conformity._face_keys(rows, base))
    kernel_report = lattice_conformity(lattice.vertices, broken, lattice.size)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(compiled, "lattice_faces", lambda *arrays: None)
        assert lattice_conformity(lattice.vertices, broken, lattice.size) == kernel_report


def test_regions_answer_many_boxes_as_each_box() -> None:
    """``answers_on_boxes`` (a region's ``answers_on_sides``: exact integer sums, int64 or Python
    integers; or a call per box) gives each box's own answer, for every region kind."""
    from fractions import Fraction
    from itertools import pairwise

    from geomexact.mesh3d.octree.regions import answers_on_boxes

    def sides_of(lines: list[Fraction]) -> list[tuple[Fraction, Fraction]]:
        return list(pairwise(lines))

    tiny = Fraction(1, 3 ** 40)  # scaled sums beyond int64: Python integers
    regions = [
        BallRegion(CENTRE, "0.3"), SphereSurfaceRegion(CENTRE, "0.3"),
        BallRegion(("1/3", "2/7", "0.5"), "1/5"), SphereSurfaceRegion((0, 0, 0), "0.5"),
        BallRegion((tiny, 0, 0), "0.25"), SphereSurfaceRegion((0, tiny, "1/7"), "0.4"),
        BoxRegion(("0.1", "0.2", "0.3"), ("0.4", "0.5", "0.6")), PointRegion(("0.5", 0, 1)),
        WholeDomain(), SegmentRegion((0, 0, 0), (1, "0.5", "0.25")),
        UnionRegion([BallRegion((0, 0, 0), "0.2"), SegmentRegion((1, 1, 0), (0, 1, 1))]),
        UnionRegion([PointRegion((1, 1, 1)), BoxRegion((0, 0, 0), ("0.1", "0.1", "0.1"))]),
    ]
    for steps in (8, 7):
        lines = [Fraction(n, steps) for n in range(steps + 1)]
        sides = [sides_of(lines), sides_of([x + tiny for x in lines]), sides_of(lines)]
        rows = np.array([(i, j, k) for i in range(steps) for j in range(steps)
                         for k in range(steps)], dtype=np.int64)
        boxes = [Box(tuple(sides[a][row[a]][0] for a in range(3)),
                     tuple(sides[a][row[a]][1] for a in range(3))) for row in rows.tolist()]
        for region in regions:
            expected = [region(box) for box in boxes]
            assert answers_on_boxes(region, sides, rows).tolist() == expected, region
            assert any(expected) or isinstance(region, PointRegion)


def test_refinement_asks_a_plain_region_and_a_criterion_box_by_box() -> None:
    """A region without ``answers_on_sides`` is called on each box; a criterion only where the
    region meets: the same octree as the vectorised regions make."""
    ball = BallRegion(CENTRE, "0.3")
    asked: list[Box] = []

    def plain(box: Box) -> bool:
        asked.append(box)
        return ball(box)

    start = octree_of_grid(unit_cube())
    vectorised = refine_octree(start, MaxEdgeLength("0.1"), ball, 5)
    assert refine_octree(start, MaxEdgeLength("0.1"), plain, 5) == vectorised
    assert len(asked) == len({(b.low, b.high) for b in asked})  # each box asked once
    assert refine_octree(start, RefineToMaxLevel(), ball, 3) == refine_octree(
        start, lambda box: False, plain, 3)


def test_balance_family_targets_are_the_leaves_targets() -> None:
    """Taking the leaves by parent (``families``) finds exactly the cells the leaves'
    own 18 neighbours find, on any set of leaves (a tiling or not)."""
    import random

    from geomexact.mesh3d.octree.balance import _by_level, _uncovered_targets

    rng = random.Random(3)
    for _ in range(60):
        leaves = list(octree_of_grid(unit_cube(), (2, 1, 1)).leaves)
        for _ in range(rng.randint(1, 30)):
            cell = leaves.pop(rng.randrange(len(leaves)))
            leaves.extend(cell_children(cell) if cell[0] < 4 else [cell])
        leaves += [(rng.randint(2, 4), rng.randint(-2, 20), rng.randint(0, 9),
                    rng.randint(-1, 9)) for _ in range(rng.randint(0, 3))]
        by_level = _by_level(leaves)
        for level in by_level:
            if level < 2:
                continue
            _, each = _uncovered_targets(by_level, (2, 1, 1), level)
            _, families = _uncovered_targets(by_level, (2, 1, 1), level, families=True)
            assert {tuple(t) for t in each.tolist()} == {tuple(t) for t in families.tolist()}
