"""The octree's cell finals end to end (issue 23): the ``generate_cells`` pipeline and its
exact check, a template check that catches a broken template, the tetrahedral cut of a
mixed mesh, the control volumes of a polyhedral Delaunay mesh, and one cuboid's cells
with a trace that replays from the start rebuilt out of its parameters."""

from __future__ import annotations

import random

import attrs
import pytest

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.cell_templates import (
    cuboid_cells,
    cuboid_start_points,
    recorded_cell_start,
)
from geomexact.mesh3d.cuboid.numbering import pattern_of
from geomexact.mesh3d.cuboid.partition import recorded_start
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.mixed.cells import CellKind, standard_cell
from geomexact.mesh3d.mixed.conversion import box_grid_mesh, from_tetrahedral, to_tetrahedral
from geomexact.mesh3d.mixed.snapshot import mixed_volume
from geomexact.mesh3d.octree.cell_final import cell_conformity, cell_final
from geomexact.mesh3d.octree.pipeline import generate_cells
from geomexact.mesh3d.octree.regions import SphereSurfaceRegion
from geomexact.mesh3d.octree.stages import (
    BoxGrid,
    MixedPartition,
    PolyhedralPartition,
    RefineWhere,
)
from geomexact.mesh3d.octree.tree import octree_of_grid
from geomexact.mesh3d.validation import validate3
from geomexact.mesh3d.voronoi import control_volumes
from geomexact.trace.playback import replay

HALF = mpq(1, 2)
SHELL = RefineWhere(3, region=SphereSurfaceRegion((HALF, HALF, HALF), mpq(3, 10)))


@pytest.mark.parametrize("final", [MixedPartition(), PolyhedralPartition()],
                         ids=["mixed", "polyhedral"])
def test_generate_cells_checks_the_mesh_and_replays(final: object) -> None:
    traced = generate_cells(unit_cube(), final, refinement=SHELL)  # type: ignore[arg-type]
    bulk = generate_cells(unit_cube(), final, refinement=SHELL,  # type: ignore[arg-type]
                          trace=False)
    assert traced.conformity.conforming and traced.conformity.cells == traced.mesh.cell_count
    assert traced.mesh == bulk.mesh and bulk.trace is None
    assert traced.start is not None and traced.trace is not None
    assert replay(traced.start, traced.trace) == bulk.mesh
    assert mixed_volume(bulk.mesh) == 1
    assert list(traced.seconds) == ["initial", "refinement", "improvement", "final",
                                    "conformity"]
    assert traced.octree.leaf_count > 8


def test_the_template_check_catches_a_broken_template() -> None:
    result = cell_final(octree_of_grid(Box((0, 0, 0), (2, 1, 1)), (2, 1, 1)), "mixed")
    (hexahedron,) = result.distinct
    twisted = attrs.evolve(hexahedron, cells=(standard_cell(
        CellKind.HEXAHEDRON, (0, 1, 2, 3, 4, 5, 7, 6)),))  # corners 2, 3 swapped: not convex
    report = cell_conformity(result.mesh, 2, [twisted])
    assert not report.conforming and "template hexahedron" in report.problems[0]
    assert cell_conformity(result.mesh, 2, result.distinct).conforming


def test_to_tetrahedral_cuts_every_cell_on_its_own_vertices() -> None:
    result = cell_final(SHELL(octree_of_grid(unit_cube())), "polyhedral")
    cut = to_tetrahedral(result.mesh)
    assert validate3(cut, volume=1) == []
    assert cut.vertex_count == result.mesh.vertex_count
    grid = to_tetrahedral(box_grid_mesh(unit_cube(), 2, 1, 1))
    assert grid.tetrahedron_count == 12 and total_volume(grid) == 1
    # a tetrahedral mesh comes back as itself
    assert to_tetrahedral(from_tetrahedral(cut)).digest == cut.digest


@pytest.mark.parametrize("level", [2, 3])
def test_control_volumes_of_a_polyhedral_delaunay_mesh(level: int) -> None:
    octree = RefineWhere(level, region=SphereSurfaceRegion(
        (HALF, HALF, HALF), mpq(3, 10)))(octree_of_grid(unit_cube()))
    mesh = cell_final(octree, "polyhedral").mesh
    volumes = control_volumes(mesh)
    assert volumes.total == 1
    assert set(volumes.volumes) == set(range(mesh.vertex_count))
    edges = {(min(u, v), max(u, v)) for cell in mesh.cell_list() for face in cell.faces
             for u, v in zip(face, (*face[1:], face[0]), strict=True)}
    assert {face.edge for face in volumes.faces} <= edges
    assert volumes.inadequate_edges() == []


@pytest.mark.parametrize("kind", ["mixed", "polyhedral"])
def test_cell_finals_of_cubes_are_delaunay_and_of_tall_leaves_may_not_be(kind: str) -> None:
    """Every leaf's cells are Delaunay; over cube leaves their union is too (the mixed
    final's added points, midpoints of co-spherical cells, keep it so), over leaves three
    times as tall as wide it is not: the control volumes are refused."""
    for domain in (unit_cube(), Box((0, 0, 0), (1, 1, 3))):
        octree = RefineWhere(3, region=SphereSurfaceRegion(
            (0, 0, 0), HALF))(octree_of_grid(domain))
        mesh = cell_final(octree, kind).mesh  # type: ignore[arg-type]
        if domain == unit_cube():
            assert control_volumes(mesh).total == 1
            continue
        with pytest.raises(PreconditionError, match="not Delaunay"):
            control_volumes(mesh)
        assert control_volumes(mesh, require_delaunay=False).total == 3


def test_one_midpoint_on_one_edge_gives_four_pyramids() -> None:
    run = cuboid_cells(pattern_of([0]), unit_cube(), "mixed")
    assert sorted(cell.kind for cell in run.mesh.cell_list()) == [CellKind.PYRAMID] * 4
    assert run.mesh.vertex_count == 9 and mixed_volume(run.mesh) == 1


@pytest.mark.parametrize("seed", range(8))
def test_a_cuboid_trace_replays_from_its_rebuilt_start(seed: int) -> None:
    rng = random.Random(seed)
    pattern = rng.randrange(1 << 18)
    box = Box((1, mpq(1, 3), 0), (3, 2, mpq(5, 7)))
    kind = ("mixed", "polyhedral")[seed % 2]
    parameters = {"algorithm": "cuboid", "final": kind, "pattern": pattern,
                  "box": {"low": ["1", "1/3", "0"], "high": ["3", "2", "5/7"]}}
    run = cuboid_cells(pattern, box, kind, trace=True, parameters=parameters)
    assert run.trace is not None
    start = recorded_cell_start(run.trace)
    assert start == run.start and start.vertex_count == len(cuboid_start_points(pattern, box))
    assert replay(start, run.trace) == run.mesh
    assert mixed_volume(run.mesh) == box.volume
    assert run.mesh == cuboid_cells(pattern, box, kind).mesh
    with pytest.raises(PreconditionError, match="cell final"):
        recorded_start(run.trace)


def test_a_cuboid_trace_with_a_bad_pattern_is_refused() -> None:
    run = cuboid_cells(3, box_of_extents(1, 1, 1), "mixed", trace=True, parameters={
        "algorithm": "cuboid", "final": "mixed", "pattern": -1,
        "box": {"low": ["0", "0", "0"], "high": ["1", "1", "1"]}})
    assert run.trace is not None
    with pytest.raises(PreconditionError, match="pattern -1"):
        recorded_cell_start(run.trace)
    with pytest.raises(PreconditionError, match="mixed or polyhedral"):
        cuboid_cells(3, unit_cube(), "hexes")


def test_an_initial_grid_is_kept() -> None:
    run = generate_cells(Box((0, 0, 0), (3, 1, 1)), MixedPartition(),
                         initial=BoxGrid(3, 1, 1), trace=False)
    assert [cell.kind for cell in run.mesh.cell_list()] == [CellKind.HEXAHEDRON] * 3


def test_derefinement_merges_siblings_where_accepted_and_is_inverse_of_refinement() -> None:
    from geomexact.mesh3d.octree.refinement import derefine_octree
    from geomexact.mesh3d.octree.regions import BoxRegion
    from geomexact.mesh3d.octree.stages import DerefineWhere

    coarse = octree_of_grid(unit_cube())
    fine = RefineWhere(3)(coarse)
    assert derefine_octree(fine, lambda box: True) == coarse
    assert derefine_octree(fine, lambda box: True, min_level=2) == RefineWhere(2)(coarse)
    assert derefine_octree(fine, lambda box: False) == fine
    # away from the corner box only: fine leaves stay there, balanced 2:1 around
    corner = BoxRegion((0, 0, 0), (mpq(1, 8), mpq(1, 8), mpq(1, 8)))
    kept = DerefineWhere(lambda box: not corner(box))(fine)
    assert kept.balanced and (3, 0, 0, 0) in kept.leaves
    assert kept.leaf_count < fine.leaf_count and (0, 0, 0, 0) not in kept.leaves
    mesh = generate_cells(unit_cube(), MixedPartition(), refinement=RefineWhere(3),
                          improvement=DerefineWhere(lambda box: not corner(box)),
                          trace=False)
    assert mesh.conformity.conforming and mixed_volume(mesh.mesh) == 1
