"""Delaunay and constrained Delaunay triangulation of real data: Lake Superior (shipped in
the package, always tested), Pikachu, and the point sets and meshes of ``../shared/data``
(skipped when it is absent)."""

from __future__ import annotations

import importlib.resources
from pathlib import Path

import pytest
from helpers.delaunay_checks import (
    assert_sound,
    boundary_loops,
    components,
    convex_hull,
    coordinate_triangles,
    euler_characteristic,
    globally_non_empty,
    inside,
    locally_non_delaunay,
    mesh_area,
    point_set_triangle_count,
    polygon_area,
    segment_loops,
    triangles_containing,
)

from geomexact import PSLG, Mesh2, io, replay, validate
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.mesh2d.delaunay.triangulation import (
    Construction,
    is_delaunay,
    make_delaunay,
    non_delaunay_edges,
    triangulate,
    triangulate_points,
)


def _superior() -> PSLG:
    path = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(path) as real:
        pslg = io.read(real)
    assert isinstance(pslg, PSLG)
    return pslg


@pytest.fixture(scope="module")
def superior() -> tuple[PSLG, Construction]:
    pslg = _superior()
    return pslg, triangulate(pslg)


def _check_constrained_delaunay_of(pslg: PSLG, run: Construction, vertices: int,
                                   triangles: int) -> None:
    """The Must-show checks: counts, all segments constrained, holes empty, Delaunay except
    across constraints, valid, replayable; plus the exact area of the polygon with holes
    and Euler's formula."""
    mesh = run.mesh
    assert mesh.vertex_count == vertices
    assert mesh.triangle_count == triangles
    assert all(mesh.is_constrained(u, v) for u, v, _ in pslg.segments)
    assert len(mesh.segments) == len(pslg.segments)
    for seed in pslg.holes:
        assert triangles_containing(mesh, seed) == []
    assert non_delaunay_edges(mesh) == []
    assert locally_non_delaunay(mesh) == []
    assert validate(mesh) == []
    assert replay(run.start, run.trace) == mesh
    assert_sound(run)
    # the segments form nested loops: even depth bounds the domain, odd depth a hole
    loops = nested_loops(pslg)
    assert mesh_area(mesh) == sum(area if depth % 2 == 0 else -area
                                  for area, depth, _ in loops)
    domains = sum(1 for _, depth, _ in loops if depth % 2 == 0)
    assert sum(1 for *_, seeded in loops if seeded) == len(pslg.holes)
    assert all(seeded == (depth % 2 == 1) for _, depth, seeded in loops)
    assert euler_characteristic(mesh) == domains - (len(loops) - domains)
    assert components(mesh) == domains and boundary_loops(mesh) == len(loops)


def nested_loops(pslg: PSLG) -> list[tuple[Rational, int, bool]]:
    """Each segment loop: its exact unsigned area, how many loops contain it, and
    whether a hole seed lies in it but in no loop nested inside it."""
    polygons = [[pslg.vertices[v] for v in loop] for loop in segment_loops(pslg)]
    depths = [sum(1 for j, other in enumerate(polygons) if j != i and inside(poly[0], other))
              for i, poly in enumerate(polygons)]
    seeded = []
    for i, poly in enumerate(polygons):
        nested = [other for j, other in enumerate(polygons)
                  if j != i and depths[j] > depths[i] and inside(other[0], poly)]
        seeded.append(any(inside(seed, poly) and not any(inside(seed, n) for n in nested)
                          for seed in pslg.holes))
    return [(abs(polygon_area(poly)), depth, hole)
            for poly, depth, hole in zip(polygons, depths, seeded, strict=True)]


def test_superior_gives_518_vertices_528_triangles_constrained_delaunay(
    superior: tuple[PSLG, Construction]
) -> None:
    """Lake Superior (1-based .poly, 6 islands as holes): 518 vertices, 528 triangles,
    all 518 segments constrained, islands empty, Delaunay except across segments."""
    pslg, run = superior
    assert (len(pslg.vertices), len(pslg.segments), len(pslg.holes)) == (518, 518, 6)
    _check_constrained_delaunay_of(pslg, run, 518, 528)


def test_superior_keep_convex_hull_covers_the_hull_minus_the_islands(
    superior: tuple[PSLG, Construction]
) -> None:
    pslg, run = superior
    kept = triangulate(pslg, keep_convex_hull=True)
    assert_sound(kept)
    islands = sum(area for area, depth, _ in nested_loops(pslg) if depth == 1)
    assert mesh_area(kept.mesh) == polygon_area(convex_hull(pslg.vertices)) - islands
    assert coordinate_triangles(run.mesh) < coordinate_triangles(kept.mesh)
    assert locally_non_delaunay(kept.mesh) == []


def test_superior_matches_triangle(superior: tuple[PSLG, Construction]) -> None:
    """Triangle ("pQ", same segments and holes) gives the same 528 triangles."""
    triangle = pytest.importorskip("triangle")
    numpy = pytest.importorskip("numpy")
    pslg, run = superior
    result = triangle.triangulate({
        "vertices": numpy.array([[p.fx, p.fy] for p in pslg.vertices]),
        "segments": numpy.array([[u, v] for u, v, _ in pslg.segments]),
        "holes": numpy.array([[p.fx, p.fy] for p in pslg.holes]),
    }, "pQ")
    assert len(result["vertices"]) == 518
    theirs = {tuple(sorted(t)) for t in result["triangles"].tolist()}
    assert theirs == {tuple(sorted(t)) for t in run.mesh.triangles()}


def test_superior_in_shared_data_is_the_packaged_file(
    shared_data: Path, superior: tuple[PSLG, Construction]
) -> None:
    pslg = io.read(shared_data / "triangle-net" / "superior.poly")
    assert isinstance(pslg, PSLG)
    assert triangulate(pslg).mesh == superior[1].mesh


def test_pikachu_gives_152_vertices_154_triangles_like_triangle(shared_data: Path) -> None:
    """Pikachu PSLG (0-based, 4 holes): 152 vertices, 154 triangles, the same triangles as
    Triangle's own output ``pikachu.1.ele`` beside it."""
    folder = shared_data / "polylla-unified"
    pslg = io.read(folder / "pikachu_poly.poly")
    assert isinstance(pslg, PSLG)
    run = triangulate(pslg)
    _check_constrained_delaunay_of(pslg, run, 152, 154)
    reference = io.read(folder / "pikachu.1.ele")
    assert isinstance(reference, Mesh2)
    assert coordinate_triangles(run.mesh) == coordinate_triangles(reference)
    # its one region seed, (5000, 5000), lies outside the domain: ignored, as by Triangle
    (region,) = pslg.regions
    assert triangles_containing(run.mesh, region.point) == []
    assert dict(run.mesh.triangle_attributes.items()) == {}


# -- point sets ----------------------------------------------------------------------------
POINT_FILES = [
    "polylla-dcel/pikachu.1.node",
    "polylla-dcel/points50.1.node",
    "polylla-refinement/500poisson.off",
    "polylla-refinement/1500random.off",
    "polylla-refinement/pikachu_triangle.off",
    "qlepp2d/A.off",
    "qlepp2d/B.off",
    "lepp-delaunay-course/Triangles1.txt",
    "lepp-delaunay-course/Triangles4.txt",
]


def _points_of(value: object) -> list[Point2]:
    if isinstance(value, PSLG):
        return list(value.vertices)
    assert isinstance(value, Mesh2)
    return [value.point(v) for v in range(value.vertex_count)]


@pytest.mark.parametrize("name", POINT_FILES)
def test_real_point_sets_give_delaunay_triangulations_of_their_hull(
    shared_data: Path, name: str
) -> None:
    """Each file's vertices as a point set (duplicates merged): Delaunay, 2n - 2 - h
    triangles, and the union of triangles is exactly the convex hull."""
    points = _points_of(io.read(shared_data / name))
    run = triangulate_points(points, merge_duplicates=True)
    assert_sound(run)
    mesh = run.mesh
    assert is_delaunay(mesh) and locally_non_delaunay(mesh) == []
    assert len(points) - len(run.duplicates) == len(set(points))
    assert mesh.triangle_count == point_set_triangle_count(points)
    assert mesh_area(mesh) == polygon_area(convex_hull(points))
    if len(points) <= 400:
        assert globally_non_empty(mesh) == []


@pytest.mark.parametrize("name", ["polylla-refinement/500poisson.off",
                                  "polylla-refinement/1500random.off"])
def test_delaunay_meshes_made_elsewhere_are_reproduced(shared_data: Path, name: str) -> None:
    """These files are Delaunay triangulations of their points; ours has the same
    triangles (the files' duplicate points merged)."""
    reference = io.read(shared_data / name)
    assert isinstance(reference, Mesh2) and is_delaunay(reference)
    run = triangulate_points(_points_of(reference), merge_duplicates=True)
    assert coordinate_triangles(run.mesh) == coordinate_triangles(reference)


@pytest.mark.parametrize("name", [f"lepp-delaunay-course/Triangles{i}.txt" for i in (1, 2, 3, 4)])
def test_make_delaunay_repairs_real_non_delaunay_meshes(shared_data: Path, name: str) -> None:
    """The course meshes are not Delaunay; Lawson flips make them Delaunay, the flips
    replay, the input is unchanged, and the result is the Delaunay triangulation of the
    same points."""
    mesh = io.read(shared_data / name)
    assert isinstance(mesh, Mesh2)
    before = non_delaunay_edges(mesh)
    assert before and not is_delaunay(mesh)
    digest = mesh.digest
    result, trace = make_delaunay(mesh)
    assert mesh.digest == digest and non_delaunay_edges(mesh) == before
    assert validate(result) == []
    assert is_delaunay(result) and locally_non_delaunay(result) == []
    assert globally_non_empty(result) == []
    assert len(trace) >= len(before)
    assert all(step.op == "flip" for step in trace.steps)
    assert replay(mesh, trace) == result
    assert mesh_area(result) == mesh_area(mesh)
    points = _points_of(mesh)
    assert coordinate_triangles(result) == coordinate_triangles(triangulate_points(points).mesh)
