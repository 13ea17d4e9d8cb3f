"""The compiled Lepp-bisection kernel (``geomexact.mesh2d.refinement.engines.lepp_kernel`` through
``geomexact.mesh2d.refinement.engines.compiled``) against the Python engine (``BatchRefinement``, run
directly): the same steps, the same digest after every step, the same progress reports,
the same final snapshot (every table) and the same stats.  Skipped when the extension is
not built."""

from __future__ import annotations

import importlib.resources
from typing import Any

import attrs
import pytest
from hypothesis import given
from hypothesis import strategies as st

import geomexact.mesh2d.refinement.api as refinement_api
from geomexact import Mesh2, io, mesh_from_triangles, mpq, replay, total_area
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.refinement.api import Progress, refine
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    CallableCriterion,
    Criterion,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
    doubled_area,
)
from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
from geomexact.mesh2d.refinement.engines.compiled import CompiledRun, run_compiled
from geomexact.mesh2d.refinement.engines.batch import BatchRefinement
from geomexact.mesh2d.refinement.regions import Circle, Polygon, Rectangle, Region, as_region
from geomexact.mesh2d.validation import check
from geomexact.strategies import meshes_with_traces, pslgs

pytestmark = pytest.mark.skipif(
    not compiled_engine.AVAILABLE, reason="the compiled kernel is not built")


def square() -> Mesh2:
    return mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                               [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)])


def options(criterion: Criterion, region: Region | None = None, delaunay: bool = True,
            method: str = "bisection", on_step: Any = None, centroid: str = "area",
            constraint_midpoints: bool = True) -> dict[str, Any]:
    """The options ``refine()`` gives the engines."""
    return {"criterion": criterion, "region": as_region(region), "method": method,
            "delaunay": delaunay, "centroid": centroid,
            "constraint_midpoints": constraint_midpoints, "on_step": on_step}


def python_run(mesh: Mesh2, max_steps: int | None, **kw: Any) -> CompiledRun:
    """The Python fast engine, exactly as ``refine()`` drives it."""
    run = BatchRefinement(mesh, max_steps, **kw)
    run.start_queue(sorted(mesh.iter_triangles()))
    status = run.run()
    result, steps, digests = run.finish(mesh)
    return CompiledRun(result, steps, digests, status, run.left_triangles(), run.targets,
                       run.searches, run.hops)


def same(mesh: Mesh2, criterion: Criterion, max_steps: int | None = None,
         **kw: Any) -> CompiledRun:
    """Run both engines (with progress reports) and assert they agree on everything."""
    reports: dict[str, list[Progress]] = {"compiled": [], "python": []}
    compiled = run_compiled(mesh, max_steps, **options(
        criterion, on_step=reports["compiled"].append, **kw))
    assert compiled is not None
    python = python_run(mesh, max_steps, **options(
        criterion, on_step=reports["python"].append, **kw))
    assert compiled.steps == python.steps
    assert compiled.digests == python.digests
    assert reports["compiled"] == reports["python"]
    assert compiled.status == python.status
    assert compiled.left == python.left
    assert (compiled.targets, compiled.searches, compiled.hops) == (
        python.targets, python.searches, python.hops)
    a, b = compiled.mesh, python.mesh
    assert a == b
    assert a.digest == b.digest and a.triangle_count == b.triangle_count
    for table in ("vertices", "halfedges", "outgoing", "segments", "vertex_markers",
                  "vertex_attributes", "triangle_attributes"):
        assert getattr(a, table) == getattr(b, table), table
    # and without progress reports (steps built at the end)
    quiet = run_compiled(mesh, max_steps, **options(criterion, **kw))
    assert quiet is not None
    assert quiet.steps == compiled.steps and quiet.digests == compiled.digests
    assert quiet.mesh == compiled.mesh
    return compiled


# --- the unit square (the dyadic grid: exact integer paths) -------------------------------
@pytest.mark.parametrize("area", ["1/8", "0.01", "0.001", "3e-4"])
@pytest.mark.parametrize("delaunay", [True, False])
def test_square(area: str, delaunay: bool) -> None:
    run = same(square(), MaxArea(area), delaunay=delaunay)
    assert run.status == "complete"
    check(run.mesh)


@pytest.mark.parametrize("region", [
    Circle(mpq(1, 3), mpq(1, 2), mpq(1, 4)), Rectangle(0, 0, mpq(1, 2), mpq(1, 5)),
    Polygon([(0, 0), (1, 0), (0, 1)]), Circle(5, 5, 1),
])
def test_square_regions(region: Region) -> None:
    same(square(), MaxArea("1e-3"), region=region)


@pytest.mark.parametrize("limit", [0, 1, 2, 7, 100, 333])
def test_square_step_limits(limit: int) -> None:
    run = same(square(), MaxArea("1e-3"), max_steps=limit)
    assert run.status == "step-limit" and len(run.steps) == limit


def test_square_replays() -> None:
    start = square()
    result = refine(start, MaxArea("1e-3"))
    run = run_compiled(start, None, **options(MaxArea("1e-3")))
    assert run is not None
    assert run.steps == list(result.trace.steps) and run.mesh == result.mesh
    assert replay(start, result.trace) == run.mesh


def test_generic_criteria_on_the_grid() -> None:
    """Criteria rated through their Python ``rate`` (tuple keys, edge lengths)."""
    start = square()
    same(start, MaxEdgeLength("0.05"))
    same(start, CallableCriterion(lambda a, b, c: doubled_area(a, b, c) > mpq(1, 500),
                                  priority=lambda a, b, c: (a.x + a.y, -doubled_area(a, b, c))))


def test_non_dyadic_square() -> None:
    """Coordinates off the grid (thirds, tenths): float filters and exact fallbacks;
    midpoints of non-grid vertices that land on the grid (1/3 + 2/3)."""
    start = mesh_from_triangles(
        [(mpq(1, 3), 0), (mpq(2, 3), 0), (mpq(2, 3), 1), (mpq(1, 3), 1), ("0.1", "0.5")],
        [(0, 1, 2), (0, 2, 3), (4, 0, 3)], [(0, 1, 7), (1, 2, 7), (2, 3, 7)])
    same(start, MaxArea("2e-3"))
    same(start, MaxArea("2e-3"), delaunay=False)
    same(start, MaxArea("2e-3"), region=Circle(mpq(1, 2), 0, mpq(1, 3)), max_steps=150)


def test_huge_and_tiny_coordinates() -> None:
    """Beyond the grid's range (integers above 2^60) and far below it."""
    big = 1 << 70
    start = mesh_from_triangles([(0, 0), (big, 0), (big, big), (0, big)],
                                [(0, 1, 2), (0, 2, 3)])
    same(start, MaxArea(mpq(big * big, 100)))
    tiny = mpq(1, 1 << 80)
    start = mesh_from_triangles([(0, 0), (tiny, 0), (tiny, tiny), (0, tiny)],
                                [(0, 1, 2), (0, 2, 3)])
    same(start, MaxArea(tiny * tiny / 50))


# --- Lake Superior (decimal coordinates: float filters) ------------------------------------
@pytest.fixture(scope="module")
def superior() -> Mesh2:
    source = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(source) as path:
        pslg = io.read(path, format="poly")
    return triangulate(pslg).mesh


def test_superior(superior: Mesh2) -> None:
    area = total_area(superior)
    run = same(superior, MaxArea(area / 2000))
    assert run.status == "complete"
    same(superior, MaxArea(area / 500), delaunay=False)
    same(superior, MaxEdgeLength(mpq(1, 20)), max_steps=300)


# --- random inputs ----------------------------------------------------------------------------
REGIONS = st.sampled_from([
    None, Circle(0, 0, 3), Circle(100, 100, 90), Rectangle(-2, -2, 6, 3),
    Polygon([(0, 0), (300, 0), (0, 300)]),
])


@given(meshes_with_traces(max_steps=10), st.booleans(), REGIONS,
       st.sampled_from([None, 0, 3, 25]), st.sampled_from(["area", "edge"]))
def test_random_meshes(case: tuple[Mesh2, Mesh2, Any], delaunay: bool, region: Region | None,
                       limit: int | None, kind: str) -> None:
    _, start, _ = case
    area = total_area(start)
    criterion = MaxArea(area / 30) if kind == "area" else MaxEdgeLength(mpq(1, 4) * 256)
    same(start, criterion, max_steps=limit, delaunay=delaunay, region=region)


@given(pslgs(max_boundary=9, max_points=8), st.booleans(), st.sampled_from([None, 40]))
def test_random_pslgs(pslg: Any, delaunay: bool, limit: int | None) -> None:
    start = triangulate(pslg).mesh
    same(start, MaxArea(total_area(start) / 60), max_steps=limit, delaunay=delaunay)


@given(st.lists(st.tuples(st.integers(0, 64), st.integers(0, 64)), min_size=3, max_size=30,
                unique=True), st.sampled_from([1, 8, 3]))
def test_random_point_sets(raw: list[tuple[int, int]], denominator: int) -> None:
    """Delaunay triangulations of lattice points: many cocircular quadruples, so the
    legalization's exact incircle decides ties (the grid path for dyadic scales)."""
    points = [point2(mpq(x, denominator), mpq(y, denominator)) for x, y in raw]
    try:
        start = triangulate(points).mesh
    except Exception:  # collinear input: nothing to refine
        return
    if start.triangle_count == 0:
        return
    same(start, MaxArea(total_area(start) / 40))


# --- AverageAreaFactor (region-wide: the mean area of the region's triangles) ----------------
@attrs.frozen(slots=True)
class Wide(AverageAreaFactor):
    """A region-wide criterion that is not exactly ``AverageAreaFactor`` (Python only)."""


def mean_state(start: Mesh2, criterion: Criterion, **kw: Any) -> tuple[Any, ...]:
    """The Python engine's (area2, count, target_area2) after ``start_queue``."""
    run = BatchRefinement(start, None, **options(criterion, **kw))
    run.start_queue(sorted(start.iter_triangles()))
    return run.area2, run.count, run.target_area2


@pytest.mark.parametrize("factor", ["1/2", "1/10", "0.3", "1/300", "1/2000", "7/12345"])
@pytest.mark.parametrize("delaunay", [True, False])
def test_factor_square(factor: str, delaunay: bool) -> None:
    run = same(square(), AverageAreaFactor(factor), delaunay=delaunay)
    assert run.status == "complete"
    check(run.mesh)
    triangles = run.mesh.triangle_count
    assert total_area(run.mesh) <= mpq(factor) * mpq(1, 2) * triangles  # the mean is met
    assert len(run.steps) > 0


def test_factor_exact_tie() -> None:
    """Factor 1/2: one bisection of the diagonal makes 4 triangles of mean exactly 1/4,
    the target (the float filter cannot decide a tie; the exact test does)."""
    run = same(square(), AverageAreaFactor("1/2"))
    assert len(run.steps) == 1 and run.mesh.triangle_count == 4
    just_below = same(square(), AverageAreaFactor(mpq(1, 2) - mpq(1, 10**30)))
    assert len(just_below.steps) > 1


@pytest.mark.parametrize("factor", ["1", "3", "1e9"])
def test_factor_at_least_one_is_met_at_once(factor: str) -> None:
    run = same(square(), AverageAreaFactor(factor))
    assert run.status == "complete" and run.steps == [] and run.targets == 0


@pytest.mark.parametrize("region", [
    Circle(mpq(1, 3), mpq(1, 2), mpq(1, 4)),  # no vertex inside: no triangle in the region
    Circle(5, 5, 1),
    Circle(mpq(1, 2), mpq(1, 2), mpq(1, 3)),
    Rectangle(0, 0, mpq(1, 2), mpq(1, 5)),
    Polygon([(0, 0), (1, 0), (0, 1)]),
])
@pytest.mark.parametrize("delaunay", [True, False])
def test_factor_regions(region: Region, delaunay: bool) -> None:
    """Regions: triangles enter and leave the region as vertices are added and edges
    flipped; a region with no triangle is met at once."""
    start = square()
    refined = refine(start, MaxArea("0.02")).mesh  # vertices inside the small circles
    for mesh in (start, refined):
        criterion = AverageAreaFactor("1/40")
        run = same(mesh, criterion, region=region, delaunay=delaunay)
        _, count, _ = mean_state(mesh, criterion, region=region)
        if count == 0:
            assert run.steps == []


@pytest.mark.parametrize("limit", [0, 1, 2, 7, 100, 333])
@pytest.mark.parametrize("delaunay", [True, False])
def test_factor_step_limits(limit: int, delaunay: bool) -> None:
    run = same(square(), AverageAreaFactor("1/2000"), max_steps=limit, delaunay=delaunay)
    assert run.status == "step-limit" and len(run.steps) == limit


def test_factor_limit_after_completion() -> None:
    run = same(square(), AverageAreaFactor("1/10"), max_steps=1000)
    assert run.status == "complete" and 0 < len(run.steps) < 1000


def test_factor_non_dyadic() -> None:
    """Off-grid triangles in the region: their areas summed as rationals (with grid
    triangles among them: 1/3 + 2/3 midpoints)."""
    start = mesh_from_triangles(
        [(mpq(1, 3), 0), (mpq(2, 3), 0), (mpq(2, 3), 1), (mpq(1, 3), 1), ("0.1", "0.5")],
        [(0, 1, 2), (0, 2, 3), (4, 0, 3)], [(0, 1, 7), (1, 2, 7), (2, 3, 7)])
    for delaunay in (True, False):
        same(start, AverageAreaFactor("1/50"), delaunay=delaunay)
    same(start, AverageAreaFactor("1/50"), region=Circle(mpq(1, 2), 0, mpq(1, 3)))
    same(start, AverageAreaFactor("1/200"), max_steps=150)
    # a grid triangle mixed with off-grid ones
    mixed = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1), (mpq(1, 3), 2)],
                                [(0, 1, 2), (0, 2, 3), (3, 2, 4)])
    same(mixed, AverageAreaFactor("1/60"))
    same(mixed, AverageAreaFactor("1/60"), region=Rectangle(0, 0, 1, 1), delaunay=False)


def test_factor_huge_and_tiny_coordinates() -> None:
    big = 1 << 70
    start = mesh_from_triangles([(0, 0), (big, 0), (big, big), (0, big)],
                                [(0, 1, 2), (0, 2, 3)])
    same(start, AverageAreaFactor("1/100"))
    tiny = mpq(1, 1 << 80)
    start = mesh_from_triangles([(0, 0), (tiny, 0), (tiny, tiny), (0, tiny)],
                                [(0, 1, 2), (0, 2, 3)])
    same(start, AverageAreaFactor("1/100"))
    # an extreme factor: the target outside the float filter's range (exact test)
    same(square(), AverageAreaFactor(mpq(1, 1 << 600)), max_steps=50)
    same(square(), AverageAreaFactor(mpq(1 << 600)))


def test_factor_superior(superior: Mesh2) -> None:
    run = same(superior, AverageAreaFactor("1/4"))
    assert run.status == "complete"
    same(superior, AverageAreaFactor("1/3"), delaunay=False)
    same(superior, AverageAreaFactor("1/20"), max_steps=300)
    same(superior, AverageAreaFactor("1/2"), region=Circle(-88, 47, 1))


def test_factor_kernel_state() -> None:
    """The kernel's region area, count and target equal the Python engine's."""
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    start = square()
    for region in (None, Rectangle(0, 0, mpq(1, 2), mpq(1, 5)), Circle(5, 5, 1)):
        criterion = AverageAreaFactor("1/7")
        reg = as_region(region)
        kernel = lepp_kernel.Kernel(start, criterion, reg, region is None, True, None, None,
                                    Progress, None, True)
        assert kernel.mean_state() == mean_state(start, criterion, region=region)
        kernel.run()
    assert lepp_kernel.Kernel(start, MaxArea("0.1"), as_region(None), True, True, None, None,
                              Progress, None).mean_state() is None


def test_factor_default_engine_matches_python() -> None:
    start = square()
    for factor in ("1/64", "1/5000"):
        fast = refine(start, AverageAreaFactor(factor))
        python = refine(start, AverageAreaFactor(factor), engine="python")
        assert fast.trace == python.trace and fast.mesh == python.mesh
        assert attrs.evolve(fast.stats, seconds=0) == attrs.evolve(python.stats, seconds=0)


@given(meshes_with_traces(max_steps=10), st.booleans(), REGIONS,
       st.sampled_from([None, 0, 3, 25]), st.sampled_from(["1/2", "1/7", "1/40", "2"]))
def test_factor_random_meshes(case: tuple[Mesh2, Mesh2, Any], delaunay: bool,
                              region: Region | None, limit: int | None, factor: str) -> None:
    _, start, _ = case
    same(start, AverageAreaFactor(factor), max_steps=limit, delaunay=delaunay, region=region)


@given(pslgs(max_boundary=9, max_points=8), st.booleans(), st.sampled_from([None, 40]),
       st.sampled_from(["1/3", "1/25"]), REGIONS)
def test_factor_random_pslgs(pslg: Any, delaunay: bool, limit: int | None, factor: str,
                             region: Region | None) -> None:
    start = triangulate(pslg).mesh
    same(start, AverageAreaFactor(factor), max_steps=limit, delaunay=delaunay, region=region)


# --- methods centroid and quasi (centroid="area": insert_in_quadrilateral) ------------------
METHODS = ["centroid", "quasi"]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("area", ["1/8", "0.01", "0.001"])
@pytest.mark.parametrize("delaunay", [True, False])
@pytest.mark.parametrize("midpoints", [True, False])
def test_methods_square(method: str, area: str, delaunay: bool, midpoints: bool) -> None:
    run = same(square(), MaxArea(area), method=method, delaunay=delaunay,
               constraint_midpoints=midpoints)
    assert run.status == "complete"
    check(run.mesh)
    ops = {step.op for step in run.steps}
    if area != "1/8":
        assert "insert_in_quadrilateral" in ops
    if method == "quasi" and delaunay and midpoints and area == "0.001":
        assert "flip" in ops


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("region", [
    Circle(mpq(1, 3), mpq(1, 2), mpq(1, 4)), Rectangle(0, 0, mpq(1, 2), mpq(1, 5)),
    Polygon([(0, 0), (1, 0), (0, 1)]), Circle(5, 5, 1),
])
def test_methods_regions(method: str, region: Region) -> None:
    same(square(), MaxArea("1e-3"), method=method, region=region)
    same(square(), AverageAreaFactor("1/60"), method=method, region=region, delaunay=False)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("limit", [0, 1, 2, 7, 100, 333])
@pytest.mark.parametrize("delaunay", [True, False])
def test_methods_step_limits(method: str, limit: int, delaunay: bool) -> None:
    run = same(square(), MaxArea("1e-3"), max_steps=limit, method=method, delaunay=delaunay)
    assert run.status == "step-limit" and len(run.steps) == limit


@pytest.mark.parametrize("method", METHODS)
def test_methods_criteria(method: str) -> None:
    """Criteria rated in Python, the average-area factor, non-dyadic and huge inputs."""
    start = square()
    same(start, MaxEdgeLength("0.05"), method=method)
    same(start, CallableCriterion(lambda a, b, c: doubled_area(a, b, c) > mpq(1, 500),
                                  priority=lambda a, b, c: (a.x + a.y, -doubled_area(a, b, c))),
         method=method, constraint_midpoints=False)
    for factor in ("1/2", "1/300", "7/12345"):
        same(start, AverageAreaFactor(factor), method=method)
    same(start, AverageAreaFactor("1/2000"), method=method, max_steps=150)
    off_grid = mesh_from_triangles(
        [(mpq(1, 3), 0), (mpq(2, 3), 0), (mpq(2, 3), 1), (mpq(1, 3), 1), ("0.1", "0.5")],
        [(0, 1, 2), (0, 2, 3), (4, 0, 3)], [(0, 1, 7), (1, 2, 7), (2, 3, 7)])
    for delaunay in (True, False):
        same(off_grid, MaxArea("2e-3"), method=method, delaunay=delaunay)
        same(off_grid, AverageAreaFactor("1/50"), method=method, delaunay=delaunay)
    same(off_grid, MaxArea("2e-3"), region=Circle(mpq(1, 2), 0, mpq(1, 3)), max_steps=150,
         method=method, constraint_midpoints=False)
    big = 1 << 70
    huge = mesh_from_triangles([(0, 0), (big, 0), (big, big), (0, big)],
                               [(0, 1, 2), (0, 2, 3)])
    same(huge, MaxArea(mpq(big * big, 100)), method=method)
    tiny = mpq(1, 1 << 80)
    small = mesh_from_triangles([(0, 0), (tiny, 0), (tiny, tiny), (0, tiny)],
                                [(0, 1, 2), (0, 2, 3)])
    same(small, MaxArea(tiny * tiny / 50), method=method)


def test_methods_deep_refinement() -> None:
    """Centroids far below the input's scale leave the kernel's integer grid (float
    filters and exact fallbacks on the rounded centroids)."""
    start = square()
    region = Rectangle(0, 0, mpq(1, 10**9), mpq(1, 10**9))  # at the corner (0, 0)
    for method in METHODS:
        run = same(start, MaxArea(mpq(1, 10**30)), method=method, region=region,
                   max_steps=3000)
        assert run.status == "step-limit"
        # the kernel's grid here is 2^-58 (coordinates below 2^2)
        assert max(run.mesh.point(v).x.denominator
                   for v in range(4, run.mesh.vertex_count)) > 2**58


@given(st.lists(st.tuples(st.integers(-40, 40), st.integers(-40, 40)), min_size=4,
                max_size=4, unique=True), st.sampled_from([1, 2, 64, 3, 1 << 40]),
       st.integers(-(1 << 20), 1 << 20))
def test_grid_centroid_is_rounded_area_centroid(raw: list[tuple[int, int]], denominator: int,
                                               shift: int) -> None:
    """The kernel's integer path of ``rounded_area_centroid`` (grid quadrilaterals) gives
    exactly the Python function's point, or defers to it (ties round half up; negative
    coordinates floor)."""
    from geomexact.kernel.predicate_results import Orientation
    from geomexact.kernel.predicates2d import orient2d
    from geomexact.mesh2d.refinement.centroids import rounded_area_centroid
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    pu, pv, pw, px = (point2(mpq(x, denominator) + shift, mpq(y, denominator))
                      for x, y in raw)
    ccw = Orientation.COUNTERCLOCKWISE
    if not all(orient2d(p, q, r) == ccw for p, q, r in (
            (pu, px, pv), (px, pv, pw), (pv, pw, pu), (pw, pu, px))):
        return  # not a strictly convex quadrilateral u, x, v, w
    start = mesh_from_triangles([pu, pv, pw, px], [(0, 1, 2), (1, 0, 3)])
    kernel = lepp_kernel.Kernel(start, MaxArea(1), as_region(None), True, True, None, None,
                                Progress, None)
    point = kernel.grid_centroid(0, 1, 2, 3)
    if denominator != 3:
        assert point is not None or denominator == 1 << 40
    if point is not None:
        assert point == rounded_area_centroid(pu, pv, pw, px)


@pytest.mark.parametrize("method", METHODS)
def test_methods_superior(superior: Mesh2, method: str) -> None:
    area = total_area(superior)
    run = same(superior, MaxArea(area / 2000), method=method)
    assert run.status == "complete"
    assert "insert_in_quadrilateral" in {step.op for step in run.steps}
    same(superior, MaxArea(area / 500), method=method, delaunay=False)
    same(superior, MaxArea(area / 500), method=method, constraint_midpoints=False)
    same(superior, MaxEdgeLength(mpq(1, 20)), max_steps=300, method=method)
    same(superior, AverageAreaFactor("1/4"), method=method)
    same(superior, AverageAreaFactor("1/2"), region=Circle(-88, 47, 1), method=method)


@pytest.mark.parametrize("method", METHODS)
def test_methods_default_engine_matches_python(method: str) -> None:
    start = square()
    for criterion in (MaxArea("1/500"), AverageAreaFactor("1/700")):
        fast = refine(start, criterion, method=method)
        python = refine(start, criterion, method=method, engine="python")
        assert fast.trace == python.trace and fast.mesh == python.mesh
        assert attrs.evolve(fast.stats, seconds=0) == attrs.evolve(python.stats, seconds=0)
        assert replay(start, fast.trace) == fast.mesh


@given(meshes_with_traces(max_steps=10), st.sampled_from(METHODS), st.booleans(),
       st.booleans(), REGIONS, st.sampled_from([None, 0, 3, 25]),
       st.sampled_from(["area", "edge", "factor"]))
def test_methods_random_meshes(case: tuple[Mesh2, Mesh2, Any], method: str, delaunay: bool,
                               midpoints: bool, region: Region | None, limit: int | None,
                               kind: str) -> None:
    _, start, _ = case
    area = total_area(start)
    criterion: Criterion = (
        MaxArea(area / 30) if kind == "area"
        else MaxEdgeLength(mpq(1, 4) * 256) if kind == "edge"
        else AverageAreaFactor("1/7")
    )
    same(start, criterion, max_steps=limit, delaunay=delaunay, region=region, method=method,
         constraint_midpoints=midpoints)


@given(pslgs(max_boundary=9, max_points=8), st.sampled_from(METHODS), st.booleans(),
       st.booleans(), st.sampled_from([None, 40]))
def test_methods_random_pslgs(pslg: Any, method: str, delaunay: bool, midpoints: bool,
                              limit: int | None) -> None:
    start = triangulate(pslg).mesh
    same(start, MaxArea(total_area(start) / 60), max_steps=limit, delaunay=delaunay,
         method=method, constraint_midpoints=midpoints)


@given(st.lists(st.tuples(st.integers(0, 64), st.integers(0, 64)), min_size=3, max_size=30,
                unique=True), st.sampled_from([1, 8, 3]), st.sampled_from(METHODS))
def test_methods_random_point_sets(raw: list[tuple[int, int]], denominator: int,
                                   method: str) -> None:
    """Lattice points: cocircular quadruples (quasi's incircle ties, legalization)."""
    points = [point2(mpq(x, denominator), mpq(y, denominator)) for x, y in raw]
    try:
        start = triangulate(points).mesh
    except Exception:  # collinear input: nothing to refine
        return
    if start.triangle_count == 0:
        return
    same(start, MaxArea(total_area(start) / 40), method=method)


# --- the subset ---------------------------------------------------------------------------
def test_outside_the_subset_returns_none() -> None:
    start = square()
    for method in ("centroid", "quasi"):
        assert run_compiled(start, None, **options(MaxArea("0.1"), method=method)) is not None
        for centroid in ("area-exact", "vertices"):
            assert run_compiled(start, None, **options(
                MaxArea("0.1"), method=method, centroid=centroid)) is None
        assert run_compiled(start, 5, **options(MinAngle(30), method=method)) is None
    assert run_compiled(start, 5, **options(MinAngle(30))) is None
    assert run_compiled(start, None, **options(Wide("0.5"))) is None
    assert run_compiled(start, None, **options(AverageAreaFactor("0.5"))) is not None
    attributed = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                                     triangle_attributes=[(1,), (2,)])
    assert run_compiled(attributed, None, **options(MaxArea("0.1"))) is None


def test_engines_route_through_the_kernel_only_when_fast(monkeypatch: pytest.MonkeyPatch) -> None:
    """``engine="fast"`` runs the kernel, ``"python"`` and ``"transient"`` never do; all
    three record the same trace."""
    start, criterion = square(), MaxArea("1/64")
    runs = {engine: refine(start, criterion, engine=engine)
            for engine in ("fast", "python", "transient")}
    assert runs["fast"].trace == runs["python"].trace == runs["transient"].trace
    assert runs["fast"].mesh == runs["python"].mesh == runs["transient"].mesh

    def refuse(*_: Any, **__: Any) -> None:
        raise AssertionError("the kernel ran")

    # the module (geomexact.mesh2d.refinement.api, the attribute, is the function)
    monkeypatch.setattr(refinement_api, "run_compiled", refuse)
    refine(start, criterion, engine="python")
    refine(start, criterion, engine="transient")
    with pytest.raises(AssertionError, match="the kernel ran"):
        refine(start, criterion, engine="fast")


def test_hashes_match_digest() -> None:
    from geomexact.kernel import digest
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    for cell in [(0, 1, 2), (5, 3, 9), (70000, 2, 123456)]:
        assert lepp_kernel.cell_hash(*cell) == digest.cell_hash(cell)
    for vertex, x, y in [(0, mpq(0), mpq(1, 3)), (2**32 - 1, mpq(-7, 2**70), mpq(10**30))]:
        assert lepp_kernel.vertex_hash(vertex, x, y) == digest.vertex_hash(vertex, (x, y))


def test_exceptions_propagate() -> None:
    """An exception in a criterion or in on_step leaves the run (as in the Python engine)."""
    def boom(a: Point2, b: Point2, c: Point2) -> bool:
        raise RuntimeError("criterion")

    with pytest.raises(RuntimeError, match="criterion"):
        run_compiled(square(), None, **options(CallableCriterion(boom)))

    def stop(progress: Progress) -> None:
        if progress.steps == 3:
            raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        run_compiled(square(), None, **options(MaxArea("0.01"), on_step=stop))
