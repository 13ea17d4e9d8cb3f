"""Polylla: exact labels, terminal-edge regions equal to those of ``lepp``, traversal,
repair (barrier-edge tips, pinch vertices), the polygon mesh partitioning the
triangulation, determinism.  Real data: ``test_polylla_data.py``; the polygon-mesh value
and its checker: ``test_polylla_polymesh.py``; CLI: ``test_polylla_cli.py``."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.polygon_checks import (
    any_meshes,
    assert_partition,
    assert_sound_run,
    constrained_meshes,
    is_convex,
    lattice_meshes,
    lepp_regions,
    polygon_edges,
    scattered_meshes,
    undirected,
)
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import Mesh2, empty_mesh, mesh_from_triangles, mpq, point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.longest_edge import longest_edge
from geomexact.mesh2d.polygonal.convex import convex_decomposition
from geomexact.mesh2d.polygonal.polylla_meshing import (
    HalfEdgeTable,
    PolyllaError,
    label_edges,
    polylla,
    polylla_run,
)
from geomexact.mesh2d.snapshot import canonical_triangle
from geomexact.mesh2d.transient import Transient2
from geomexact.strategies import triangulations

PROJECT = Path(__file__).resolve().parents[3]

# 59 random points (coordinates k / 10^6): the tip repair of vertex 27 joins it back to
# vertex 0, where its barrier tree hangs; the piece outside the new loop then touches
# itself at vertex 0 (a pinch) and is cut again.
PINCH_AFTER_TIP = [
    (634609, 887027), (614529, 889313), (671313, 646884), (918083, 170147), (277954, 406302),
    (603358, 332015), (905676, 99066), (493875, 752697), (678326, 17075), (211138, 11671),
    (763807, 605893), (452314, 710760), (625299, 476), (239748, 591957), (43451, 902590),
    (198721, 541339), (968135, 363732), (486237, 211021), (646090, 118915), (672155, 917482),
    (207370, 511904), (572321, 466912), (824844, 73770), (121246, 345013), (189822, 674587),
    (604752, 309194), (454233, 375784), (652687, 947520), (657833, 948857), (997784, 952366),
    (100455, 777913), (793630, 724626), (212889, 90455), (998116, 204121), (74723, 102903),
    (224237, 17362), (551912, 651369), (60604, 816720), (694468, 507986), (540545, 701019),
    (497908, 993462), (718134, 375163), (287343, 248808), (272377, 144270), (336987, 728186),
    (227774, 789458), (490509, 657977), (234179, 689546), (197110, 552747), (836232, 664521),
    (279897, 484169), (448223, 910280), (938858, 767697), (477414, 897238), (223499, 853007),
    (528971, 142184), (781809, 676545), (857924, 467767), (220069, 369806),
]
# 8 random points whose Delaunay triangulation has a barrier edge 4-1 with its tip at 1
BARRIER_TIP = [
    (496680, 684827), (548698, 315769), (804949, 569089), (976190, 440994), (741695, 242154),
    (99099, 392888), (648246, 70985), (353744, 674464),
]
# 8 points (k / 1000) with a barrier edge whose tip has an even number of internal edges
EVEN_TIP = [(160, 728), (627, 16), (626, 238), (97, 160), (697, 92), (546, 57), (45, 255),
            (391, 365)]


def delaunay_of(raw: list[tuple[int, int]], denominator: int = 10**6) -> Mesh2:
    return triangulate([point2(mpq(x, denominator), mpq(y, denominator)) for x, y in raw]).mesh


# -----------------------------------------------------------------------------------------
# small exact cases
# -----------------------------------------------------------------------------------------
def test_rectangle_split_by_its_diagonal_is_one_polygon() -> None:
    """The diagonal is the longest edge of both triangles: a terminal edge."""
    mesh = mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    run = polylla_run(mesh)
    assert run.mesh.polygons == ((0, 1, 2, 3),)
    assert run.mesh.sources == (((0, 1, 2), (0, 2, 3)),)
    assert run.terminal_edges == ((0, 2),)
    assert run.regions == 1 and run.barrier_tips == () and run.repair_edges == ()
    labels = label_edges(mesh)
    assert labels.internal == ((0, 2),)
    assert labels.frontier == ((0, 1), (0, 3), (1, 2), (2, 3))
    assert labels.terminal == ((0, 2),)


def test_boundary_terminal_edges_make_one_region_per_side() -> None:
    """Two triangles whose longest edges are boundary edges: two regions, the shared edge
    is frontier, each boundary longest edge is terminal."""
    mesh = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (0, 3, 1)])
    # (0, 1) has length 4: shared, the longest of both triangles -> interior terminal edge
    assert polylla(mesh).polygons == ((0, 3, 1, 2),)
    kite = mesh_from_triangles([(0, 0), (1, 0), (0, 3), (1, -3)], [(0, 1, 2), (0, 3, 1)])
    run = polylla_run(kite)  # longest edges (1, 2) and (3, 0) are boundary edges
    assert run.mesh.polygons == ((0, 1, 2), (0, 3, 1))
    assert run.terminal_edges == ((0, 3), (1, 2))
    assert label_edges(kite).frontier == ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3))


def test_tied_longest_edge_ends_only_one_lepp() -> None:
    """Exact tie: triangle (0, 1, 2) has longest edge {0, 2} (length² 10); the triangle
    across it, (0, 2, 3), has two longest edges of length² 10, {0, 2} and {2, 3}: the tie
    rule picks {0, 2} (smaller pair), so {0, 2} is a two-sided terminal edge.  With ids
    relabelled so that the neighbour's tie goes to its other edge, the shared edge ends the
    Lepp of one side only (as lepp.lepp says) and is a frontier edge between two regions.
    """
    points = [(0, 0), (2, -1), (3, 1), (0, 2)]
    mesh = mesh_from_triangles(points, [(0, 1, 2), (0, 2, 3)])
    assert longest_edge(mesh, (0, 2, 3)) == (0, 2)
    assert polylla(mesh).polygons == ((0, 1, 2, 3),)
    # old ids 0, 1, 2, 3 -> new ids 3, 0, 1, 2: the shared edge {0, 2} becomes {1, 3}, the
    # neighbour's other longest edge {2, 3} becomes {1, 2} < {1, 3}
    relabelled = mesh_from_triangles([points[1], points[2], points[3], points[0]],
                                     [(3, 0, 1), (3, 1, 2)])
    assert longest_edge(relabelled, (3, 1, 2)) == (1, 2)
    run = polylla_run(relabelled)
    assert run.mesh.polygons == ((0, 1, 3), (1, 2, 3))
    assert run.terminal_edges == ((1, 2), (1, 3))
    assert (1, 3) in label_edges(relabelled).frontier
    assert (1, 3) in label_edges(relabelled).terminal


def test_constrained_edge_is_frontier_even_when_terminal() -> None:
    transient = Transient2(mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)],
                                               [(0, 1, 2), (0, 2, 3)]))
    transient.set_segment(0, 2, 7)
    mesh = transient.seal()
    run = polylla_run(mesh)
    assert run.mesh.polygons == ((0, 1, 2), (0, 2, 3))
    assert run.terminal_edges == ((0, 2), (2, 0))  # one per side
    assert (0, 2) in label_edges(mesh).frontier


def test_attribute_change_is_a_frontier_edge() -> None:
    transient = Transient2(mesh_from_triangles([(0, 0), (2, 0), (2, 1), (0, 1)],
                                               [(0, 1, 2), (0, 2, 3)]))
    transient.set_triangle_attributes((0, 1, 2), (mpq(1),))
    mesh = transient.seal()
    assert polylla(mesh).polygons == ((0, 1, 2), (0, 2, 3))


def test_empty_mesh_has_no_polygons() -> None:
    run = polylla_run(empty_mesh())
    assert run.mesh.polygons == () and run.regions == 0
    assert label_edges(empty_mesh()).internal == ()


def test_isolated_vertices_are_kept_unused() -> None:
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1), (5, 5)], [(0, 1, 2)])
    result = polylla(mesh)
    assert len(result.vertices) == 4 and result.polygons == ((0, 1, 2),)


def test_barrier_edge_tip_is_split_at_its_middle_edge() -> None:
    """The raw region walks 4 -> 1 -> 4 (barrier edge {1, 4}, tip 1); the k = 5 other
    edges at the tip, clockwise from the barrier edge, go to 6, 5, 7, 0, 2; the
    ⌈5/2⌉ = 3rd, {1, 7}, becomes a frontier edge."""
    mesh = delaunay_of(BARRIER_TIP)
    raw = polylla_run(mesh, repair=False)
    assert raw.mesh.polygons == ((0, 7, 5, 6, 4, 1, 4, 3, 2), (3, 4, 6))
    star = [w for _, w, _ in mesh.star(1)]  # counter-clockwise neighbours of the tip
    start = star.index(4)
    clockwise = [star[(start - i) % len(star)] for i in range(1, len(star))]
    assert clockwise == [6, 5, 7, 0, 2]
    run = polylla_run(mesh)
    assert run.barrier_tips == (1,)
    assert run.repair_edges == ((1, 7),)
    assert run.mesh.polygons == ((0, 7, 1, 4, 3, 2), (1, 7, 5, 6, 4), (3, 4, 6))
    assert_sound_run(mesh, run)


def test_even_fan_at_a_tip_takes_the_first_middle_edge_clockwise() -> None:
    """Barrier edge {1, 5} with its tip at 5; the k = 4 other edges at the tip, clockwise
    from the barrier edge, go to 3, 7, 2, 4: of the two middle ones the first clockwise,
    {5, 7}, is chosen (the reference implementation's rule)."""
    mesh = delaunay_of(EVEN_TIP, 1000)
    raw = polylla_run(mesh, repair=False)
    assert (1, 4, 2, 7, 3, 1, 5) in raw.mesh.polygons
    star = [w for _, w, _ in mesh.star(5)]
    start = star.index(1)
    assert [star[(start - i) % len(star)] for i in range(1, len(star))] == [3, 7, 2, 4]
    run = polylla_run(mesh)
    assert run.barrier_tips == (5,) and run.repair_edges == ((5, 7),)
    assert run.mesh.polygons == ((0, 6, 3, 7), (0, 7, 2), (1, 4, 2, 7, 5), (1, 5, 7, 3))
    assert_sound_run(mesh, run)


def lcg_points(seed: int, count: int) -> list[tuple[int, int]]:
    """``count`` lattice points in [0, 2^20)² from a 64-bit linear congruential generator
    (stable across Python versions, unlike ``random``), duplicates dropped."""
    state = seed
    values = []
    for _ in range(2 * count):
        state = (6364136223846793005 * state + 1442695040888963407) % 2**64
        values.append(state >> 44)
    return list(dict.fromkeys(zip(values[::2], values[1::2], strict=True)))


def test_raw_region_touching_itself_at_a_vertex_is_cut() -> None:
    """A terminal-edge region without any barrier edge whose boundary visits vertex 37
    twice: it wraps around other regions.  The shortest edge on the path of triangles
    between the two visits, (32, 54), is cut."""
    mesh = delaunay_of(lcg_points(4566, 60), 2**20)
    raw = polylla_run(mesh, repair=False)
    pinched = [p for p in raw.mesh.polygons if p.count(37) == 2]
    assert len(pinched) == 1
    edges = set(polygon_edges(pinched[0]))
    assert not any((v, u) in edges for u, v in edges)  # no barrier edge
    run = polylla_run(mesh)
    assert (32, 54) in run.repair_edges
    assert all(p.count(37) <= 1 for p in run.mesh.polygons)
    assert_sound_run(mesh, run)


def test_pinch_after_a_tip_repair_is_cut() -> None:
    mesh = delaunay_of(PINCH_AFTER_TIP)
    raw = polylla_run(mesh, repair=False)
    assert sum(len(set(p)) != len(p) for p in raw.mesh.polygons) == 2
    run = polylla_run(mesh)
    assert run.barrier_tips == (54, 27)
    # (14, 54): tip 54; (0, 27): tip 27, joining it to where its barrier tree hangs; the
    # outer piece then visits 0 twice and the shortest edge between the visits, (1, 27),
    # is cut
    assert run.repair_edges == ((0, 27), (1, 27), (14, 54))
    assert len(run.mesh.polygons) == run.regions + 3
    assert_sound_run(mesh, run)


# -----------------------------------------------------------------------------------------
# properties
# -----------------------------------------------------------------------------------------
@given(any_meshes())
def test_polylla_partitions_the_triangulation_into_simple_polygons(mesh: Mesh2) -> None:
    """Union area equals the input exactly, every triangle in exactly one polygon, every
    polygon simple and counter-clockwise; validate agrees."""
    assert_sound_run(mesh, polylla_run(mesh))


@given(any_meshes())
def test_regions_are_the_lepp_terminal_edge_classes(mesh: Mesh2) -> None:
    """The unrepaired polygons are exactly the classes of triangles whose Lepp (computed
    independently by geomexact.mesh2d.longest_edge) ends at the same terminal edge."""
    raw = polylla_run(mesh, repair=False)
    assert_partition(mesh, raw.mesh, simple=False)
    regions = sorted((frozenset(canonical_triangle(*t) for t in source)
                      for source in raw.mesh.sources), key=min)
    assert regions == lepp_regions(mesh)
    assert raw.regions == len(raw.mesh.polygons) == len(regions)


@given(any_meshes())
def test_labels_partition_edges_and_agree_with_the_polygons(mesh: Mesh2) -> None:
    labels = label_edges(mesh)
    assert set(labels.internal).isdisjoint(labels.frontier)
    assert sorted(labels.internal + labels.frontier) == mesh.edges()
    assert set(labels.terminal) <= set(mesh.edges())
    raw = polylla_run(mesh, repair=False).mesh
    walked = {undirected(e) for polygon in raw.polygons for e in polygon_edges(polygon)}
    assert walked == set(labels.frontier)
    # an edge is internal exactly when it is the longest edge of a triangle whose Lepp
    # crosses it; in particular an internal edge is the longest edge of some triangle
    for u, v in labels.internal:
        sides = [t for t in (mesh.apex(u, v), mesh.apex(v, u)) if t is not None]
        assert len(sides) == 2
        assert any(undirected(longest_edge(mesh, (a, b, c))) == (u, v)
                   for a, b, c in ((u, v, sides[0]), (v, u, sides[1])))


@given(any_meshes())
def test_polylla_is_deterministic_under_triangle_order(mesh: Mesh2) -> None:
    """Rebuilding the same mesh from its triangles in reverse order gives the same
    result."""
    transient = Transient2(empty_mesh())
    for vertex in range(mesh.vertex_count):
        transient.add_vertex(mesh.point(vertex), mesh.vertex_markers.get(vertex, 0),
                             mesh.vertex_attributes.get(vertex, ()))
    for triangle in reversed(mesh.triangles()):
        transient.add_triangle(*triangle, attributes=mesh.triangle_attributes.get(triangle))
    for u, v, marker in reversed(mesh.segment_list()):
        transient.set_segment(v, u, marker)
    rebuilt = transient.seal()
    assert rebuilt == mesh
    assert polylla_run(rebuilt) == polylla_run(mesh)


@settings(max_examples=10)
@given(lattice_meshes(max_points=40, side=8))
def test_tip_and_pinch_repairs_on_tie_heavy_meshes(mesh: Mesh2) -> None:
    assert_sound_run(mesh, polylla_run(mesh))


@given(st.one_of(scattered_meshes(), constrained_meshes(), triangulations()))
def test_longest_edges_of_the_label_phase_are_those_of_lepp(mesh: Mesh2) -> None:
    """The vectorised filter never disagrees with lepp.edge_order (coordinates of every
    magnitude, including beyond the double range)."""
    table = HalfEdgeTable.from_mesh(mesh)
    labels = label_edges(mesh)
    internal = set(labels.internal)
    for t, triangle in enumerate(table.triangles):
        edge = undirected(longest_edge(mesh, triangle))
        # the longest edge of every triangle is internal or ends a Lepp
        assert edge in internal or edge in labels.terminal, (t, triangle)


# -----------------------------------------------------------------------------------------
# errors and determinism across processes
# -----------------------------------------------------------------------------------------
def test_overlapping_triangles_raise_polylla_error() -> None:
    points = [point2(0, 0), point2(1, 0), point2(0, 1)]
    with pytest.raises(PolyllaError, match="share a directed edge"):
        HalfEdgeTable(points, [(0, 1, 2), (0, 1, 2)])


_SCRIPT = """
import hashlib, random
from geomexact import point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.polylla_meshing import polylla_run
from geomexact.mesh2d.polygonal.convex import convex_decomposition
rng = random.Random(7)
points = list(dict.fromkeys(point2(rng.randint(0, 40), rng.randint(0, 40)) for _ in range(300)))
mesh = triangulate(points).mesh
run = polylla_run(mesh)
convex = convex_decomposition(run.mesh)
text = repr((run.mesh.polygons, run.mesh.sources, run.repair_edges, convex.mesh.polygons,
             convex.inserted_edges))
print(hashlib.sha256(text.encode()).hexdigest())
"""


def test_results_are_identical_across_processes_and_hash_seeds() -> None:
    digests = set()
    for seed in ("0", "12345"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        done = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True,
                              text=True, env=env, cwd=PROJECT, check=True)
        digests.add(done.stdout.strip())
    assert len(digests) == 1
    assert len(next(iter(digests))) == len(hashlib.sha256().hexdigest())


# -----------------------------------------------------------------------------------------
# larger meshes: barrier-edge tips and pinches are common there
# -----------------------------------------------------------------------------------------
def _check_everything(mesh: Mesh2) -> None:
    run = polylla_run(mesh)
    assert_sound_run(mesh, run)
    raw = polylla_run(mesh, repair=False)
    regions = sorted((frozenset(canonical_triangle(*t) for t in source)
                      for source in raw.mesh.sources), key=min)
    assert regions == lepp_regions(mesh)
    for criterion_one in (True, False):
        result = convex_decomposition(run.mesh, criterion_one=criterion_one)
        assert all(is_convex(result.mesh.vertices, p) for p in result.mesh.polygons)
        assert all(mesh.is_edge(*edge) for edge in result.inserted_edges)
        assert_partition(mesh, result.mesh)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_meshes_of_300_points(seed: int) -> None:
    _check_everything(delaunay_of(lcg_points(seed, 300), 2**20))


def test_lattice_mesh_full_of_ties() -> None:
    """All 15 x 15 lattice points but every third one: right isosceles triangles and
    cocircular squares everywhere."""
    points = [(x, y) for x in range(15) for y in range(15) if (x * 7 + y * 3) % 5]
    _check_everything(delaunay_of(points, 1))


@pytest.mark.parametrize("seed", range(100, 120))
def test_many_random_meshes(seed: int) -> None:
    _check_everything(delaunay_of(lcg_points(seed, 150 + 7 * (seed % 50)), 2**20))


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(200, 400))
def test_very_many_random_meshes(seed: int) -> None:
    _check_everything(delaunay_of(lcg_points(seed, 100 + 9 * (seed % 100)), 2**20))
