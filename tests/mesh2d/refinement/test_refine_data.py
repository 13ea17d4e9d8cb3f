"""Lepp refinement of real inputs: the Polylla meshes of ``../shared/data`` with max area,
average-area factor and every region type (the Pikachu with its ``polygon.off`` region),
and Lake Superior (constrained Delaunay of the bundled ``superior.poly``) at minimum
angles 20°…35° with the centroid and quasi-Delaunay methods."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from helpers.paths import read_superior

from geomexact import Mesh2, io, is_delaunay, replay, total_area, validate
from geomexact.kernel.angles import angle_degrees
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import Result, refine
from geomexact.mesh2d.refinement.criteria import AverageAreaFactor, Criterion, MaxArea, MinAngle
from geomexact.mesh2d.refinement.regions import Circle, Polygon, Rectangle, Region, Whole

MESHES = [
    "polylla-refinement/500poisson.off",
    "polylla-refinement/1500random.off",
    "polylla-refinement/pikachu_triangle.off",
    "polylla-dcel/pikachu.1.ele",
    "polylla-dcel/points50.1.ele",
]


def read_mesh(path: Path) -> Mesh2:
    mesh = io.read(path)
    assert isinstance(mesh, Mesh2)
    return mesh


def box_regions(mesh: Mesh2) -> dict[str, Region]:
    """A circle around the centre, the lower-left quarter, and a triangle in the upper
    right, sized from the bounding box (exact)."""
    xs = [p.x for p in mesh.vertices.values()]
    ys = [p.y for p in mesh.vertices.values()]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    width, height = x1 - x0, y1 - y0
    return {
        "whole": Whole(),
        "circle": Circle((x0 + x1) / 2, (y0 + y1) / 2, min(width, height) / 4),
        "rectangle": Rectangle(x0, y0, width / 2, height / 2),
        "polygon": Polygon([(x1, y1), (x1 - width / 2, y1), (x1, y1 - height / 2)]),
    }


def in_region(mesh: Mesh2, triangle: tuple[int, int, int], region: Region) -> bool:
    return any(region.contains(mesh.point(v)) for v in triangle)


def check(start: Mesh2, result: Result, criterion: Criterion, region: Region) -> None:
    assert result.status == "complete"
    mesh = result.mesh
    assert validate(mesh) == []
    assert total_area(mesh) == total_area(start)
    left = set(result.stats.left)
    for triangle in mesh.triangles():
        if in_region(mesh, triangle, region) and triangle not in left:
            assert criterion.rate(*(mesh.point(v) for v in triangle)) is None
    assert replay(start, result.trace).digest == mesh.digest


@pytest.mark.parametrize("name", MESHES)
@pytest.mark.parametrize("region_name", ["whole", "circle", "rectangle", "polygon"])
def test_polylla_meshes_max_area_in_each_region(
    shared_data: Path, name: str, region_name: str
) -> None:
    """Max area = half the mean triangle area (a quarter in the small regions), Lepp-
    bisection with legalization: every triangle of the region meets it; Delaunay inputs
    stay Delaunay."""
    start = read_mesh(shared_data / name)
    region = box_regions(start)[region_name]
    divisor = 2 if region_name == "whole" else 4
    criterion = MaxArea(total_area(start) / start.triangle_count / divisor)
    result = refine(start, criterion, region=region)
    check(start, result, criterion, region)
    if is_delaunay(start):
        assert is_delaunay(result.mesh)


@pytest.mark.parametrize("name", MESHES)
@pytest.mark.parametrize("method", ["bisection", "centroid", "quasi"])
def test_polylla_meshes_average_area_factor(shared_data: Path, name: str, method: Any) -> None:
    """Factor 0.5: the mean triangle area at least halves, with each method."""
    start = read_mesh(shared_data / name)
    result = refine(start, AverageAreaFactor("0.5"), method=method)
    assert result.status == "complete"
    mesh = result.mesh
    assert total_area(mesh) / mesh.triangle_count <= total_area(start) / start.triangle_count / 2
    assert validate(mesh) == []
    assert total_area(mesh) == total_area(start)


@pytest.mark.parametrize("method", ["bisection", "centroid", "quasi"])
def test_pikachu_refined_inside_its_polygon_region(shared_data: Path, method: Any) -> None:
    """The Pikachu mesh with the 5-gon of ``polygon.off`` as region: the region's
    triangles get under an eighth of the mean area, the rest of the mesh keeps larger
    ones."""
    start = read_mesh(shared_data / "polylla-refinement" / "pikachu_triangle.off")
    shape = io.read(shared_data / "polylla-refinement" / "polygon.off")
    assert isinstance(shape, PolygonMesh) and len(shape.polygons) == 1
    region = Polygon([shape.vertices[i] for i in shape.polygons[0]])
    criterion = MaxArea(total_area(start) / start.triangle_count / 8)
    result = refine(start, criterion, method=method, region=region)
    check(start, result, criterion, region)
    outside = [t for t in result.mesh.triangles() if not in_region(result.mesh, t, region)]
    assert any(criterion.rate(*(result.mesh.point(v) for v in t)) is not None for t in outside)


@pytest.mark.parametrize("name", ["polylla-refinement/500poisson.off",
                                  "polylla-dcel/points50.1.ele"])
@pytest.mark.parametrize("method", ["centroid", "quasi"])
def test_polylla_meshes_min_angle_30(shared_data: Path, name: str, method: Any) -> None:
    """Min angle 30° on the Delaunay point-set meshes (boundary angles are the only
    input angles)."""
    start = read_mesh(shared_data / name)
    result = refine(start, MinAngle(30), method=method)
    check(start, result, MinAngle(30), Whole())


# -- Lake Superior ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def superior() -> Mesh2:
    """The constrained Delaunay triangulation of the bundled Lake Superior PSLG."""
    pslg = read_superior()
    assert isinstance(pslg, PSLG)
    return triangulate(pslg).mesh


def input_corner_angles(mesh: Mesh2, vertex: int) -> list[float]:
    """The angles between consecutive constrained edges around ``vertex`` (degrees)."""
    ends = [b if a == vertex else a for a, b in mesh.segments if vertex in (a, b)]
    point = mesh.point(vertex)
    return [angle_degrees(mesh.point(ends[0]), point, mesh.point(ends[1]))] if len(ends) == 2 \
        else []


@pytest.mark.parametrize("method", ["centroid", "quasi"])
@pytest.mark.parametrize("degrees", [*range(20, 36), "33.3", "34.9"])
def test_superior_min_angle_terminates_with_every_angle_at_least_theta(
    superior: Mesh2, degrees: Any, method: Any
) -> None:
    """Every θ from 20° to 35°: the run completes; every triangle has all angles >= θ
    except the few left at input corners sharper than θ (the 15.02° corner of vertex 125
    and, inside the domain, any other), which are reported."""
    criterion = MinAngle(degrees)
    result = refine(superior, criterion, method=method)
    check(superior, result, criterion, Whole())
    mesh = result.mesh
    for triangle in result.stats.left:
        corners = [angle for v in triangle if v < superior.vertex_count
                   for angle in input_corner_angles(superior, v)]
        assert any(angle < float(degrees) for angle in corners), triangle
    assert 0 < len(result.stats.left) <= 4
    if method == "centroid":
        assert is_delaunay(mesh)
    smallest = min(
        min(angle_degrees(mesh.point(c), mesh.point(a), mesh.point(b)),
            angle_degrees(mesh.point(a), mesh.point(b), mesh.point(c)),
            angle_degrees(mesh.point(b), mesh.point(c), mesh.point(a)))
        for a, b, c in mesh.triangles() if (a, b, c) not in set(result.stats.left)
    )
    assert smallest >= float(degrees) - 1e-9


@pytest.mark.parametrize("method", ["centroid", "quasi"])
@pytest.mark.parametrize("degrees", [20, 25, 30, 33, 35])
def test_superior_fast_kernel_matches_the_reference_engine(
    superior: Mesh2, degrees: int, method: Any
) -> None:
    """The batch kernel and the ops on a transient record the same Superior run."""
    fast = refine(superior, MinAngle(degrees), method=method)
    reference = refine(superior, MinAngle(degrees), method=method, engine="reference")
    assert fast.trace == reference.trace
    assert fast.mesh == reference.mesh
