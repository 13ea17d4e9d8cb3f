"""The octree's mixed and polyhedral finals (issue 23): each template valid in its cuboid
and cutting its faces by the face rule; met's named template (one midpoint on one edge:
four pyramids); replay of the reference trace = the bulk build; the exact validation; and
an independent check (``fractions`` only, no geomexact mesh code) on a few hundred random
octrees."""

from __future__ import annotations

import random
from collections import Counter
from fractions import Fraction

import pytest
from helpers.fraction_cells import first_problem, newell, volume

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.cell_templates import (
    POSITIONS,
    face_polygons,
    mixed_template,
    polyhedral_template,
)
from geomexact.mesh3d.cuboid.numbering import PATTERN_COUNT, pattern_of
from geomexact.mesh3d.mixed.cells import CellKind, polygon_key
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed
from geomexact.mesh3d.octree.cell_final import cell_conformity, cell_final
from geomexact.mesh3d.octree.lattice import octree_lattice
from geomexact.mesh3d.octree.stages import PATTERN_PARTITION
from geomexact.mesh3d.octree.tree import Octree, cell_children, octree_of_grid
from geomexact.trace.playback import replay

SAMPLE = [0, 1, 3, 17, 4096, 4111, 69391, PATTERN_COUNT - 1,
          *random.Random(23).sample(range(PATTERN_COUNT), 120)]


def _kinds(cells: object) -> Counter[str]:
    return Counter(cell.kind.name for cell in cells)  # type: ignore[attr-defined]


SHAPES = [unit_cube(), box_of_extents(2, 1, 1), box_of_extents(1, 3, 2)]


@pytest.mark.parametrize("pattern", SAMPLE)
@pytest.mark.parametrize("shape", SHAPES[:2], ids=["cube", "2x1x1"])
def test_mixed_template_fills_the_cuboid_and_cuts_each_face_by_the_face_rule(
        pattern: int, shape: Box) -> None:
    template = mixed_template(pattern, shape)
    mesh = mixed_mesh_from_cells([*POSITIONS, *template.points], template.cells)
    assert validate_mixed(mesh, volume=8) == []  # half-lattice: the cuboid's volume is 8
    cut = {polygon_key(p) for face in range(6) for p in face_polygons(pattern, face, shape)}
    assert {polygon_key(face) for face in mesh.boundary_faces()} == cut
    assert all(cell.kind != CellKind.POLYHEDRON for cell in template.cells)



@pytest.mark.parametrize("pattern", SAMPLE[:40])
@pytest.mark.parametrize("shape", SHAPES, ids=["cube", "2x1x1", "1x3x2"])
def test_polyhedral_template_fills_the_cuboid(pattern: int, shape: Box) -> None:
    template = polyhedral_template(pattern, shape)
    mesh = mixed_mesh_from_cells(POSITIONS, template.cells)
    assert validate_mixed(mesh, volume=8) == []


def test_the_named_templates() -> None:
    """met's Patterns: one Steiner point on one edge gives four pyramids; no Steiner point
    a hexahedron; the midpoints of two parallel edges of a face, three wedges."""
    cube = unit_cube()
    for bit in range(12):
        assert _kinds(mixed_template(1 << bit, cube).cells) == {"PYRAMID": 4}
    assert _kinds(mixed_template(0, cube).cells) == {"HEXAHEDRON": 1}
    assert _kinds(polyhedral_template(0, cube).cells) == {"HEXAHEDRON": 1}
    both_rings = pattern_of([0, 4])  # y=0 on the bottom and the top: an extrusion along z
    assert mixed_template(both_rings, cube).name == "extrusion-z"
    assert _kinds(mixed_template(both_rings, cube).cells) == {"WEDGE": 3}
    # a face against four finer leaves: four pyramids on its quads, a fifth on the far
    # face, four tetrahedra (the Delaunay cells; the cone from the body centre needs 17)
    split = pattern_of([0, 1, 2, 3, 16, 8, 9, 10, 11][:5])
    assert _kinds(mixed_template(split, cube).cells) == {"PYRAMID": 5, "TETRA": 4}


def test_a_coarse_face_against_four_leaves_is_cut_into_their_four_quads() -> None:
    split = pattern_of([0, 1, 2, 3, 16])  # z=0: four midpoints and the centre
    assert sorted(len(p) for p in face_polygons(split, 4, unit_cube())) == [4, 4, 4, 4]
    one = pattern_of([0])  # one midpoint: the fan of three triangles from it
    assert [p for p in face_polygons(one, 4, unit_cube()) if 8 not in p] == []


def _random_octree(rng: random.Random, splits: int, depth: int) -> Octree:
    grid = (rng.randint(1, 2), rng.randint(1, 2), 1)
    domain = Box((0, 0, 0), (grid[0] * rng.choice([1, 2]), grid[1], rng.choice([1, 3])))
    leaves = set(octree_of_grid(domain, grid).leaves)
    for _ in range(splits):
        leaf = rng.choice(sorted(leaves))
        if leaf[0] < depth:
            leaves.remove(leaf)
            leaves.update(cell_children(leaf))
    return Octree(domain, grid, tuple(leaves))


def _fractions(mesh: MixedMesh3) -> dict[int, tuple[Fraction, Fraction, Fraction]]:
    return {v: (Fraction(p.x.numerator, p.x.denominator),
                Fraction(p.y.numerator, p.y.denominator),
                Fraction(p.z.numerator, p.z.denominator))
            for v, p in mesh.vertices.items()}


def independent_problems(mesh: MixedMesh3, domain: Box) -> list[str]:
    """Every cell passes the fraction checks; each directed face is matched by its
    reverse in exactly one other cell, or lies on the domain's surface; the surface
    faces cover each side of the box exactly; the volumes sum to the box's."""
    points = _fractions(mesh)
    low = [Fraction(str(v)) for v in domain.low]
    high = [Fraction(str(v)) for v in domain.high]
    problems: list[str] = []
    directed: Counter[tuple[int, ...]] = Counter()
    total = Fraction(0)
    for cell in mesh.cell_list():
        faces = tuple(tuple(face) for face in cell.faces)
        found = first_problem(faces, points)
        if found:
            problems.append(f"{cell}: {found}")
        total += volume(faces, points)
        for face in faces:
            start = face.index(min(face))
            directed[face[start:] + face[:start]] += 1
    side_area: Counter[tuple[int, int]] = Counter()
    for face, times in directed.items():
        back = tuple(reversed(face))
        start = back.index(min(back))
        if times != 1:
            problems.append(f"face {face} on one side of {times} cells")
        elif back[start:] + back[:start] in directed:
            continue
        else:
            sides = [(axis, end) for axis in range(3) for end, value in ((0, low[axis]),
                                                                         (1, high[axis]))
                     if all(points[v][axis] == value for v in face)]
            if len(sides) != 1:
                problems.append(f"face {face} has no cell behind it inside the domain")
                continue
            axis, end = sides[0]
            area2 = newell([points[v] for v in face])[axis]
            side_area[(axis, end)] += area2 if end else -area2
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        area = (high[others[0]] - low[others[0]]) * (high[others[1]] - low[others[1]])
        for end in (0, 1):
            if side_area[(axis, end)] != 2 * area:
                problems.append(f"side {axis},{end} covered {side_area[(axis, end)] / 2}")
    box_volume = (high[0] - low[0]) * (high[1] - low[1]) * (high[2] - low[2])
    if total != box_volume:
        problems.append(f"volume {total} != {box_volume}")
    return problems


@pytest.mark.parametrize("seed", [*range(50),
                                  *(pytest.param(s, marks=pytest.mark.slow)
                                    for s in range(50, 200))])
def test_random_octree_finals_pass_the_exact_and_the_independent_checks(seed: int) -> None:
    rng = random.Random(seed)
    octree = _random_octree(rng, rng.randint(0, 12), rng.randint(1, 3))
    kind = "mixed" if seed % 2 == 0 else "polyhedral"
    result = cell_final(octree, kind)  # type: ignore[arg-type]
    assert independent_problems(result.mesh, octree.domain) == []
    assert cell_conformity(result.mesh, octree.domain.volume).conforming
    # the fast check (each template once, then the faces) agrees with the full one
    assert cell_conformity(result.mesh, octree.domain.volume, result.distinct).conforming
    assert len(result.levels) == result.mesh.cell_count
    assert sum(result.templates.values()) == result.octree.leaf_count


@pytest.mark.parametrize("seed", range(12))
def test_replay_of_the_reference_equals_the_bulk_build(seed: int) -> None:
    rng = random.Random(1000 + seed)
    octree = _random_octree(rng, rng.randint(1, 10), 3)
    for kind in ("mixed", "polyhedral"):
        traced = cell_final(octree, kind, trace=True)  # type: ignore[arg-type]
        bulk = cell_final(octree, kind)  # type: ignore[arg-type]
        assert traced.start is not None and traced.trace is not None
        assert traced.mesh == bulk.mesh
        assert replay(traced.start, traced.trace) == bulk.mesh
        assert traced.trace.final_digest == bulk.mesh.digest


def test_a_mixed_mesh_needs_fewer_cells_than_the_pattern_partition() -> None:
    octree = _random_octree(random.Random(5), 30, 3)
    tetrahedra = PATTERN_PARTITION(octree).mesh.tetrahedron_count
    for kind in ("mixed", "polyhedral"):
        assert cell_final(octree, kind).mesh.cell_count < tetrahedra  # type: ignore[arg-type]


def test_added_points_are_new_vertices_after_the_lattice() -> None:
    octree = _random_octree(random.Random(8), 20, 2)
    result = cell_final(octree, "mixed")
    lattice = octree_lattice(result.octree)
    assert result.mesh.vertex_count == lattice.vertex_count + result.added
    assert all(cell.kind != CellKind.POLYHEDRON for cell in result.mesh.cell_list())


def test_an_unknown_cell_final_is_refused() -> None:
    with pytest.raises(PreconditionError, match="mixed"):
        cell_final(octree_of_grid(unit_cube()), "hexes")  # type: ignore[arg-type]
