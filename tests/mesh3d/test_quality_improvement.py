"""Quality improvement by exact flips (issue 24, item 4): hand-made flip23 / flip32 /
edge-removal cases, octree domain fits with slivers, random jittered grids; each result
valid (validate3), its volume exactly the input's, its boundary faces the input's, its
trace replaying on the input, the input unchanged, the run the same in any process."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from helpers.mesh3d_cases import kuhn_tetrahedra
from helpers.surface_cases import notched_box, octahedron
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import mpq
from geomexact.errors import PreconditionError
from geomexact.kernel.points import Point3
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.ops import FLIP_OF_KIND, classify_face, flip
from geomexact.mesh3d.quality import dihedral_angles
from geomexact.mesh3d.quality_improvement import (
    QualityCriterion,
    QualityImprovement,
    improve_quality,
    tetrahedron_measures,
)
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra
from geomexact.mesh3d.validation import validate3
from geomexact.trace.playback import replay

TRIANGLE = [(0, 0, 0), (1, 0, 0), (mpq(1, 2), mpq(7, 8), 0)]
AXIS = (mpq(1, 2), mpq(7, 24))  # the triangle's centroid


def bipyramid(height: object, tetrahedra: list[tuple[int, int, int, int]]) -> Mesh3:
    """The triangle with apexes at ``height`` above and below its centroid (4, 3)."""
    points = [*TRIANGLE, (*AXIS, height), (*AXIS, -mpq(height))]  # type: ignore[call-overload]
    return mesh3_from_tetrahedra(points, tetrahedra, orient=True)


def two(height: object) -> Mesh3:
    return bipyramid(height, [(0, 1, 2, 3), (0, 2, 1, 4)])


def three(height: object) -> Mesh3:
    return bipyramid(height, [(3, 4, 0, 1), (3, 4, 1, 2), (3, 4, 2, 0)])


def worst(mesh: Mesh3) -> float:
    xyz = np.array([(p.fx, p.fy, p.fz) for p in mesh.point_list()])
    return float(dihedral_angles(xyz, mesh.tetrahedron_array()).min())


def check_result(start: Mesh3, result: QualityImprovement, *, boundary: bool = False) -> None:
    """Every invariant of a run: valid, exact volume, boundary kept, trace replays."""
    mesh = result.mesh
    assert validate3(mesh, volume=total_volume(start)) == []
    if not boundary:
        assert mesh.boundary_faces() == start.boundary_faces()
    else:  # the boundary's vertices and its area are kept; its triangles may change
        assert {v for f in mesh.boundary_faces() for v in f} == {
            v for f in start.boundary_faces() for v in f}
    assert mesh.vertex_count == start.vertex_count
    assert result.trace is not None
    assert len(result.trace) == result.flip_count
    assert replay(start, result.trace) == mesh
    assert result.trace.final_digest == mesh.digest
    # (the failing count may rise: hill climbing raises the worst, not the count)
    if result.worst_before is not None and result.worst_after is not None:
        assert worst(mesh) == result.worst_after


# -- the measures --------------------------------------------------------------------------
def test_the_regular_tetrahedron_has_ratio_one_and_its_dihedral_angle() -> None:
    root = mpq(1)
    points = [Point3(*c, *(float(x) for x in c)) for c in (  # type: ignore[misc]
        (root, root, root), (root, -root, -root), (-root, root, -root), (-root, -root, root))]
    angle, ratio = tetrahedron_measures(*points)
    assert angle == pytest.approx(70.528779, abs=1e-6)
    assert ratio == pytest.approx(1.0, abs=1e-12)


def test_measures_agree_with_the_display_measures() -> None:
    mesh = generate(octahedron, 3)
    xyz = np.array([(p.fx, p.fy, p.fz) for p in mesh.point_list()])
    angles = dihedral_angles(xyz, mesh.tetrahedron_array()).min(axis=1)
    for row, expected in zip(mesh.tetrahedron_array().tolist(), angles, strict=True):
        angle, ratio = tetrahedron_measures(*(mesh.point(v) for v in row))
        assert angle == pytest.approx(expected, abs=1e-7)
        assert 0 < ratio <= 1


def test_a_criterion_needs_a_threshold_in_range() -> None:
    with pytest.raises(PreconditionError):
        QualityCriterion()
    with pytest.raises(PreconditionError):
        QualityCriterion(min_dihedral=80.0)
    with pytest.raises(PreconditionError):
        QualityCriterion(min_radius_ratio=1.5)
    both = QualityCriterion(min_dihedral=20.0, min_radius_ratio=0.5)
    assert both.quality(10.0, 0.75) == 0.5 and both.quality(30.0, 0.25) == 0.5


# -- hand-made flips -----------------------------------------------------------------------
def test_two_flat_caps_become_three_by_one_flip23() -> None:
    start = two(mpq(1, 20))
    result = improve_quality(start, QualityCriterion(min_dihedral=15.0))
    check_result(start, result)
    assert result.flips == (1, 0, 0, 0) and result.edge_removals == 0
    assert result.worst_before is not None and result.worst_after is not None
    assert result.worst_before < 10 < 19 < result.worst_after
    assert (result.failing_before, result.failing_after) == (2, 0)
    assert result.mesh == flip(start, "flip23", (0, 1, 2))


def test_three_needles_around_a_long_edge_become_two_by_one_flip32() -> None:
    start = three(2)
    result = improve_quality(start, QualityCriterion(min_dihedral=40.0))
    check_result(start, result)
    assert result.flips == (0, 1, 0, 0)
    assert result.worst_before is not None and result.worst_after is not None
    assert result.worst_before < 31 and result.worst_after > 61
    assert result.failing_after == 0 and result.mesh.tetrahedron_count == 2


def test_a_good_mesh_is_left_alone_and_a_bad_flip_is_not_made() -> None:
    for start, criterion in ((three(mpq(1, 20)), 15.0), (two(2), 15.0)):
        result = improve_quality(start, QualityCriterion(min_dihedral=criterion))
        assert result.flip_count == 0 and result.mesh == start and result.rounds == 0
    # failing, but the flip23 would be worse: not made
    start = two(2)
    result = improve_quality(start, QualityCriterion(min_dihedral=65.0))
    assert result.failing_before == 2 and result.flip_count == 0 and result.mesh == start


def ring_of_four(height: object) -> Mesh3:
    """An interior edge (4, 5) from -height to +height with a ring of 4 around it (a
    square with two corners moved so that no two opposite ones are coplanar with the
    edge: no flip44)."""
    ring = [(1, 0, 0), (0, 1, 0), (-1, mpq(1, 10), 0), (mpq(1, 10), -1, 0)]
    points = [*ring, (0, 0, -mpq(height)), (0, 0, height)]  # type: ignore[call-overload]
    tetrahedra = [(4, 5, i, (i + 1) % 4) for i in range(4)]
    return mesh3_from_tetrahedra(points, tetrahedra, orient=True)


def test_an_edge_with_four_tetrahedra_is_removed_by_a_flip23_and_a_flip32() -> None:
    start = ring_of_four(2)
    result = improve_quality(start, QualityCriterion(min_dihedral=45.0))
    check_result(start, result)
    assert result.edge_removals == 1 and result.flips == (1, 1, 0, 0)
    assert [step.op for step in result.trace.steps] == ["flip23", "flip32"]  # type: ignore[union-attr]
    assert result.mesh.tetrahedron_count == 4
    assert result.worst_after > result.worst_before  # type: ignore[operator]
    assert not any(4 in row and 5 in row for row in result.mesh.tetrahedra())
    without = improve_quality(start, QualityCriterion(min_dihedral=45.0), edge_removal=False)
    assert without.flip_count == 0


# -- domain fits with slivers --------------------------------------------------------------
@cache
def generate(surface: object, level: int) -> Mesh3:
    from geomexact.mesh3d.octree.domain import generate_domain

    return generate_domain([surface()], level=level, warp=None).mesh  # type: ignore[operator]


@cache
def improved(surface: object, level: int) -> QualityImprovement:
    return improve_quality(generate(surface, level), QualityCriterion(min_dihedral=15.0))


@pytest.mark.parametrize("surface", [octahedron, notched_box])
def test_a_domain_fit_improves_and_stays_exact(surface: object) -> None:
    start = generate(surface, 4)
    before = (start.digest, start.tetrahedra(), start.point_list())
    result = improved(surface, 4)
    check_result(start, result)
    assert (start.digest, start.tetrahedra(), start.point_list()) == before  # not mutated
    assert result.failing_after < result.failing_before
    assert result.worst_after >= result.worst_before  # type: ignore[operator]
    assert result.flips_of("flip22") == 0 and result.flips_of("flip44") > 0
    assert result.edge_removals > 0


def test_the_octahedron_worst_angle_rises() -> None:
    result = improved(octahedron, 4)
    assert result.worst_before is not None and result.worst_after is not None
    assert result.worst_before < 12.3 and result.worst_after > 13.6


def test_the_sorted_qualities_rise() -> None:
    """Hill climbing: each move replaces tetrahedra by ones whose smallest quality is
    larger, so the sorted qualities of the whole mesh rise lexicographically."""
    start = generate(octahedron, 4)
    result = improved(octahedron, 4)
    criterion = QualityCriterion(min_dihedral=15.0)

    def qualities(mesh: Mesh3) -> list[float]:
        return sorted(criterion.quality(*tetrahedron_measures(*(mesh.point(v) for v in row)))
                      for row in mesh.tetrahedra())

    assert qualities(result.mesh) > qualities(start)


def test_a_region_limits_the_tetrahedra_worked_on() -> None:
    start = generate(octahedron, 4)
    criterion = QualityCriterion(min_dihedral=15.0)
    nowhere = improve_quality(start, criterion, region=lambda points: False)
    assert nowhere.mesh == start and nowhere.failing_before == 0 and not nowhere.trace

    def low_corner(points: tuple[Point3, ...]) -> bool:
        return all(p.x < mpq(1, 2) and p.y < mpq(1, 2) and p.z < mpq(1, 2) for p in points)

    part = improve_quality(start, criterion, region=low_corner, max_rounds=2)
    check_result(start, part)
    assert 0 < part.failing_before < improved(octahedron, 4).failing_before
    assert 0 < part.flip_count < improved(octahedron, 4).flip_count
    assert part.failing_after < part.failing_before


def test_boundary_flips_keep_the_domain() -> None:
    start = generate(octahedron, 3)
    result = improve_quality(start, QualityCriterion(min_dihedral=15.0), boundary=True)
    check_result(start, result, boundary=True)


def test_the_radius_ratio_criterion() -> None:
    start = generate(notched_box, 3)
    result = improve_quality(start, QualityCriterion(min_radius_ratio=0.3))
    check_result(start, result)
    assert result.failing_after < result.failing_before


def test_max_rounds_and_no_trace() -> None:
    start = generate(octahedron, 3)
    criterion = QualityCriterion(min_dihedral=15.0)
    zero = improve_quality(start, criterion, max_rounds=0)
    assert zero.mesh == start and zero.rounds == 0 and zero.failing_after == zero.failing_before
    one = improve_quality(start, criterion, max_rounds=1, trace=False)
    assert one.trace is None and one.rounds == 1
    full = improve_quality(start, criterion)
    assert full.rounds >= one.rounds
    with pytest.raises(PreconditionError):
        improve_quality(start, criterion, max_rounds=-1)


# -- determinism ---------------------------------------------------------------------------
_RUN = textwrap.dedent("""
    import sys
    sys.path.insert(0, {tests!r})
    from helpers.surface_cases import octahedron
    from geomexact.mesh3d.octree.domain import generate_domain
    from geomexact.mesh3d.quality_improvement import QualityCriterion, improve_quality
    mesh = generate_domain([octahedron()], level=3, warp=None).mesh
    result = improve_quality(mesh, QualityCriterion(min_dihedral=15.0))
    print(result.mesh.digest, [(s.op, s.args) for s in result.trace.steps])
""")


def test_the_same_run_in_other_processes() -> None:
    tests = str(Path(__file__).resolve().parents[1])
    start = generate(octahedron, 3)
    result = improve_quality(start, QualityCriterion(min_dihedral=15.0))
    assert result.trace is not None and len(result.trace) > 0
    here = f"{result.mesh.digest} {[(s.op, s.args) for s in result.trace.steps]}"
    for seed in ("1", "987"):
        environment = {**os.environ, "PYTHONHASHSEED": seed}
        out = subprocess.run([sys.executable, "-c", _RUN.format(tests=tests)], check=True,
                             capture_output=True, text=True, env=environment).stdout.strip()
        assert out == here
    again = improve_quality(start, QualityCriterion(min_dihedral=15.0))
    assert again.trace == result.trace and again.mesh == result.mesh


# -- random jittered grids -----------------------------------------------------------------
GRID = [(x, y, z) for x in range(3) for y in range(3) for z in range(3)]


def _grid_tetrahedra() -> list[tuple[int, int, int, int]]:
    return kuhn_tetrahedra(2, 2, 2)


@st.composite
def jittered_grids(draw: st.DrawFn) -> Mesh3:
    """The 2x2x2 grid of Kuhn cubes, its centre moved by up to 9/20 along each axis and
    then some valid flips made (slivers and caps)."""
    offset = [mpq(draw(st.integers(-9, 9)), 20) for _ in range(3)]
    points = [(x + offset[0], y + offset[1], z + offset[2]) if (x, y, z) == (1, 1, 1)
              else (x, y, z) for x, y, z in GRID]
    mesh = mesh3_from_tetrahedra(points, _grid_tetrahedra(), orient=True)
    for choice in draw(st.lists(st.integers(0, 10**6), max_size=6)):
        flippable = [(FLIP_OF_KIND[c.kind], face) for face in mesh.interior_faces()
                     if (c := classify_face(mesh, face)).kind.value in ("T23", "T32")]
        if not flippable:
            break
        op, face = flippable[choice % len(flippable)]
        mesh = flip(mesh, op, face)
    return mesh


@settings(max_examples=20, deadline=None)
@given(jittered_grids(), st.sampled_from([20.0, 30.0]))
def test_random_grids_improve_exactly_and_deterministically(mesh: Mesh3, angle: float) -> None:
    before = (mesh.digest, mesh.tetrahedra())
    criterion = QualityCriterion(min_dihedral=angle)
    result = improve_quality(mesh, criterion)
    check_result(mesh, result)
    assert total_volume(result.mesh) == 8
    assert (mesh.digest, mesh.tetrahedra()) == before
    assert result.worst_after >= result.worst_before  # type: ignore[operator]
    assert improve_quality(mesh, criterion).trace == result.trace
