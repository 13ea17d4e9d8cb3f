"""The vectorised mesh summary (``geomexact.mesh2d.mesh_arrays``, ``mesh_summary``) and
checker (``validation`` on arrays) give the answers of the scalar definitions
(``scalar_mesh_summary``: ``measures``, ``non_delaunay_edges``; ``scalar_validate``), key
for key and bit for bit: on the shared data meshes, on
refinements of them, on random meshes of the strategies, and on grids of cocircular
squares (every edge undecided by the float filter) scaled and moved to every magnitude,
exactly or nearly cocircular."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from geomexact.io import read
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d import mesh_arrays as mesh_arrays_module
from geomexact.mesh2d import validation
from geomexact.mesh2d.delaunay.triangulation import (
    make_delaunay,
    non_delaunay_edges,
    triangulate,
    triangulate_points,
)
from geomexact.mesh2d.measures import total_area
from geomexact.mesh2d.mesh_arrays import mesh_arrays
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement import criteria
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary, scalar_mesh_summary
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.strategies import coordinates, meshes_with_traces
from tests.helpers.paths import SHARED_DATA, SUPERIOR

FEW = settings(max_examples=min(settings().max_examples, 60), deadline=None,
               suppress_health_check=[HealthCheck.too_slow])


def same_answers(mesh: Mesh2) -> None:
    """The vectorised summary and Delaunay check equal the scalar ones."""
    assert mesh_summary(mesh) == scalar_mesh_summary(mesh)
    arrays = mesh_arrays(mesh)
    assert arrays is not None
    assert arrays.non_delaunay_edges() == non_delaunay_edges(mesh)
    assert arrays.total_area() == total_area(mesh)
    assert mesh_summary(mesh, check_delaunay=False)["is_delaunay"] is None
    for allow in (True, False):
        assert validation._validate_arrays(mesh, arrays, check_digest=True,
                                           allow_isolated=allow) == validation.scalar_validate(
            mesh, allow_isolated=allow)


def _meshes_of(path: Path) -> Mesh2:
    value = read(path)
    if isinstance(value, PSLG):
        return triangulate(value).mesh
    assert isinstance(value, Mesh2)
    return value


SHARED = sorted(
    p for p in SHARED_DATA.rglob("*")
    if p.suffix in (".off", ".ele") and "polygon" not in p.name and p.name != "pikachu_poly"
) if SHARED_DATA.is_dir() else []


@pytest.mark.parametrize("path", SHARED, ids=lambda p: p.name)
def test_shared_data_meshes(path: Path) -> None:
    try:
        mesh = _meshes_of(path)
    except AssertionError:
        pytest.skip("not a triangle mesh")
    same_answers(mesh)
    if mesh.triangle_count:
        area = total_area(mesh) / mesh.triangle_count / 2
        refined = refine(mesh, criteria.MaxArea(area), method="bisection").mesh
        same_answers(refined)
        same_answers(refine(mesh, criteria.MinAngle(mpq(25)), method="centroid",
                            max_steps=150).mesh)


def test_superior_and_its_refinements() -> None:
    pslg = read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    mesh = triangulate(pslg).mesh
    same_answers(mesh)
    same_answers(refine(mesh, criteria.MinAngle(mpq(30)), method="quasi", max_steps=500).mesh)


def test_a_uniform_refinement_of_the_square() -> None:
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    same_answers(refine(square, criteria.MaxArea(mpq(1, 500)), method="bisection").mesh)


def test_small_blocks_give_the_same_answers(monkeypatch: pytest.MonkeyPatch) -> None:
    """Areas and angles are computed block by block: blocks of 5 triangles (the extremes
    spread over many blocks) give the same answers."""
    monkeypatch.setattr(mesh_arrays_module, "_BLOCK", 5)
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    same_answers(refine(square, criteria.MaxArea(mpq(1, 300)), method="bisection").mesh)
    pslg = read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    same_answers(triangulate(pslg).mesh)


def test_a_non_delaunay_mesh_and_regions() -> None:
    kite = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (1, 0, 3)])
    same_answers(kite)
    assert mesh_summary(kite)["is_delaunay"] is False
    regions = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (1, 0, 3)],
                                  triangle_attributes=[(mpq(1),), (mpq(2),)])
    same_answers(regions)
    assert mesh_summary(regions)["is_delaunay"] is True
    constrained = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)],
                                      [(0, 1, 2), (1, 0, 3)], [(0, 1, 5)])
    same_answers(constrained)


def test_an_empty_mesh_and_isolated_vertices() -> None:
    same_answers(mesh_from_triangles([], []))
    same_answers(mesh_from_triangles([(0, 0), (1, 0), (0, 1), (5, 5)], [(0, 1, 2)]))
    same_answers(triangulate_points([point2(0, 0), point2(1, 0), point2(0, 1)]).mesh)


def test_inconsistent_tables_use_the_scalar_definitions() -> None:
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    broken = Mesh2(mesh.vertices, mesh.halfedges.delete((1, 2)), mesh.outgoing,
                   mesh.segments, mesh.vertex_markers, mesh.vertex_attributes,
                   mesh.triangle_attributes, mesh.triangle_count, mesh.digest)
    assert mesh_arrays(broken) is None
    assert mesh_summary(broken) == scalar_mesh_summary(broken)


@FEW
@given(meshes_with_traces(max_steps=25))
def test_random_meshes(case: tuple[Mesh2, Mesh2, object]) -> None:
    start, end, _ = case
    same_answers(start)
    same_answers(end)


_MAGNITUDES = ("ordinary", "decimal", "dyadic", "huge", "tiny", "beyond_double")


@st.composite
def cocircular_grids(draw: st.DrawFn) -> Mesh2:
    """A k x l grid of squares (cocircular corners), each cut by a random diagonal, mapped
    by x -> scale * (rotation x) + offset of any magnitude; one vertex maybe nudged by a
    relative 2^-j (nearly cocircular, nearly collinear)."""
    columns, rows = draw(st.integers(1, 5)), draw(st.integers(1, 5))
    scale = draw(coordinates(_MAGNITUDES).filter(lambda s: s != 0))
    ox, oy = draw(coordinates(_MAGNITUDES)), draw(coordinates(_MAGNITUDES))
    m, n = draw(st.integers(1, 6)), draw(st.integers(0, 6))
    cos, sin = mpq(m * m - n * n, m * m + n * n), mpq(2 * m * n, m * m + n * n)

    def place(i: int, j: int) -> tuple[Rational, Rational]:
        return ox + scale * (cos * i - sin * j), oy + scale * (sin * i + cos * j)

    points = [place(i, j) for j in range(rows + 1) for i in range(columns + 1)]
    if draw(st.booleans()):
        k = draw(st.integers(0, len(points) - 1))
        shift = abs(scale) * mpq(1, 2 ** draw(st.integers(3, 110)))
        x, y = points[k]
        points[k] = (x + shift, y - shift) if draw(st.booleans()) else (x, y + shift)
    triangles = []
    for j in range(rows):
        for i in range(columns):
            a = j * (columns + 1) + i
            b, c, d = a + 1, a + columns + 2, a + columns + 1
            if draw(st.booleans()):
                triangles += [(a, b, c), (a, c, d)]
            else:
                triangles += [(a, b, d), (b, c, d)]
    return mesh_from_triangles(points, triangles, orient=True)


@FEW
@given(cocircular_grids())
def test_cocircular_grids_at_every_magnitude(mesh: Mesh2) -> None:
    same_answers(mesh)


@FEW
@given(cocircular_grids())
def test_the_delaunay_grids_of_the_same_points(mesh: Mesh2) -> None:
    same_answers(make_delaunay(mesh)[0])
