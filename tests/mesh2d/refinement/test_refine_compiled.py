"""The compiled Lepp kernel (``geomexact.mesh2d.refinement.engines.lepp_kernel`` through
``geomexact.mesh2d.refinement.engines.compiled``): what only the kernel has — its subset,
its hashes, its region-wide state, its integer centroids, runs with and without progress
reports, exceptions from Python callbacks.  Its equality with the reference engine on
every workload is in ``tests/engines/test_engine_equivalence.py``.  Skipped when the
extension is not built."""

from __future__ import annotations

from typing import Any

import attrs
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import Mesh2, mesh_from_triangles, mpq
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.refinement.api import Progress, refine
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    CallableCriterion,
    Criterion,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
)
from geomexact.mesh2d.refinement.driver import RunOptions
from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
from geomexact.mesh2d.refinement.engines.compiled import KernelRun, run_compiled, unsupported
from geomexact.mesh2d.refinement.engines.reference import ReferenceRefinement
from geomexact.mesh2d.refinement.presets import rules
from geomexact.mesh2d.refinement.regions import Circle, Rectangle, Region, as_region

pytestmark = pytest.mark.skipif(
    not compiled_engine.AVAILABLE, reason="the compiled kernel is not built")


def square() -> Mesh2:
    return mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                               [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)])


def options(criterion: Criterion, region: Region | None = None, delaunay: bool = True,
            method: str = "bisection", on_step: Any = None, centroid: str = "area",
            constraint_midpoints: bool = True) -> RunOptions:
    """The run ``refine()`` gives the engines."""
    return RunOptions(criterion, as_region(region), method,  # type: ignore[arg-type]
                      delaunay, rules(None, centroid=centroid, second_longest_rule=(
                          "bisect-second" if constraint_midpoints else "centroid")), on_step)


@pytest.mark.parametrize("method", ["bisection", "centroid", "quasi"])
@pytest.mark.parametrize("criterion", [MaxArea("1e-3"), AverageAreaFactor("1/300"),
                                       MaxEdgeLength("0.05")])
@pytest.mark.parametrize("limit", [None, 0, 7])
def test_runs_without_progress_reports_are_the_same(
    method: str, criterion: Criterion, limit: int | None
) -> None:
    """Without ``on_step`` the kernel builds the steps at the end: the same run as with
    progress reports (one per step)."""
    reports: list[Progress] = []
    loud = run_compiled(square(), limit, options(criterion, method=method,
                                                   on_step=reports.append))
    quiet = run_compiled(square(), limit, options(criterion, method=method))
    assert loud is not None and quiet is not None
    assert quiet.steps == loud.steps and quiet.digests == loud.digests
    assert quiet.mesh == loud.mesh and quiet.status == loud.status
    assert [report.step for report in reports] == loud.steps


# --- AverageAreaFactor (region-wide: the mean area of the region's triangles) ----------------
@attrs.frozen(slots=True)
class Wide(AverageAreaFactor):
    """A region-wide criterion that is not exactly ``AverageAreaFactor`` (Python only)."""


def mean_state(start: Mesh2, criterion: Criterion, **kw: Any) -> tuple[Any, ...]:
    """The reference engine's (area2, count, target_area2) after ``start_queue``."""
    run = ReferenceRefinement(start, None, options(criterion, **kw))
    run.start_queue(sorted(start.iter_triangles()))
    return run.area2, run.count, run.target_area2


def test_factor_kernel_state() -> None:
    """The kernel's region area, count and target equal the Python engine's."""
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    start = square()
    for region in (None, Rectangle(0, 0, mpq(1, 2), mpq(1, 5)), Circle(5, 5, 1)):
        criterion = AverageAreaFactor("1/7")
        reg = as_region(region)
        kernel = lepp_kernel.Kernel(start, KernelRun(criterion, reg, average=True))
        assert kernel.mean_state() == mean_state(start, criterion, region=region)
        kernel.run()
    assert lepp_kernel.Kernel(start, KernelRun(MaxArea("0.1"), as_region(None))
                              ).mean_state() is None


# --- methods centroid and quasi (centroid="area": insert_in_quadrilateral) ------------------
@settings(max_examples=300)
@given(st.lists(st.tuples(st.integers(-10**6, 10**6), st.integers(-10**6, 10**6)),
                min_size=4, max_size=4, unique=True),
       st.sampled_from([3, 10**4, 7 * 2**20, 10**16, 3**40]),
       st.sampled_from([0, mpq(1, 3), mpq(-8858, 100), mpq(10**12, 7)]))
def test_float_centroid_is_rounded_area_centroid(raw: list[tuple[int, int]],
                                                denominator: int, shift: Any) -> None:
    """The kernel's certified float path of ``rounded_area_centroid`` (corners off the
    grid: thirds, decimals) gives exactly the Python function's point, or defers to it."""
    from geomexact.kernel.predicate_results import Orientation
    from geomexact.kernel.predicates2d import orient2d
    from geomexact.mesh2d.refinement.centroids import rounded_area_centroid
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    pu, pv, pw, px = (point2(mpq(x, denominator) + shift, mpq(y, denominator) - shift)
                      for x, y in raw)
    ccw = Orientation.COUNTERCLOCKWISE
    if not all(orient2d(p, q, r) == ccw for p, q, r in (
            (pu, px, pv), (px, pv, pw), (pv, pw, pu), (pw, pu, px))):
        return  # not a strictly convex quadrilateral u, x, v, w
    start = mesh_from_triangles([pu, pv, pw, px], [(0, 1, 2), (1, 0, 3)])
    kernel = lepp_kernel.Kernel(start, KernelRun(MaxArea(1), as_region(None)))
    point = kernel.float_centroid(0, 1, 2, 3)
    if point is not None:
        assert point == rounded_area_centroid(pu, pv, pw, px)


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
    kernel = lepp_kernel.Kernel(start, KernelRun(MaxArea(1), as_region(None)))
    point = kernel.grid_centroid(0, 1, 2, 3)
    if denominator != 3:
        assert point is not None or denominator == 1 << 40
    if point is not None:
        assert point == rounded_area_centroid(pu, pv, pw, px)


# --- the subset ---------------------------------------------------------------------------
class OtherAngle(MinAngle):
    """A minimum-angle criterion that is not exactly ``MinAngle`` (no kernel)."""


def test_outside_the_subset_returns_none() -> None:
    start = square()
    for method in ("centroid", "quasi"):
        assert run_compiled(start, None, options(MaxArea("0.1"), method=method)) is not None
        for centroid in ("area-exact", "vertices", "midpoint"):  # every kind (issue 25)
            assert run_compiled(start, None, options(
                MaxArea("0.1"), method=method, centroid=centroid)) is not None
        assert run_compiled(start, 5, options(MinAngle(30), method=method)) is not None
        # a minimum-angle criterion of another type (its rate may differ): declined
        assert run_compiled(start, 5, options(OtherAngle(30), method=method)) is None
    assert run_compiled(start, 5, options(MinAngle(30))) is not None
    # a run is a typed record (issue 25, item 4): there is no unknown option to decline
    assert unsupported(start, options(MaxArea("0.1"))) is None
    assert run_compiled(start, None, options(Wide("0.5"))) is None
    assert run_compiled(start, None, options(AverageAreaFactor("0.5"))) is not None
    attributed = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                                     triangle_attributes=[(1,), (2,)])
    assert run_compiled(attributed, None, options(MaxArea("0.1"))) is not None


def test_hashes_match_digest() -> None:
    from geomexact.kernel import digest
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    for cell in [(0, 1, 2), (5, 3, 9), (70000, 2, 123456)]:
        assert lepp_kernel.cell_hash(*cell) == digest.cell_hash(cell)
    for vertex, x, y in [(0, mpq(0), mpq(1, 3)), (2**32 - 1, mpq(-7, 2**70), mpq(10**30))]:
        assert lepp_kernel.vertex_hash(vertex, x, y) == digest.vertex_hash(vertex, (x, y))


@settings(max_examples=300, deadline=None)
@given(vertex=st.integers(0, 2**63 - 1), gx=st.integers(-2**63, 2**63 - 1),
       gy=st.one_of(st.integers(-2**63, 2**63 - 1), st.sampled_from([0, 1, -1, 2**62])),
       bits=st.integers(0, 62))
def test_grid_vertex_hash_in_c_matches_digest(vertex: int, gx: int, gy: int,
                                              bits: int) -> None:
    """The C BLAKE2b of a grid point (gx / 2**F, gy / 2**F) is ``digest.vertex_hash``:
    same encoding (reduced fraction, sign byte, byte lengths), same personalisation."""
    from geomexact.kernel import digest
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    expected = digest.vertex_hash(vertex, (mpq(gx, 2**bits), mpq(gy, 2**bits)))
    assert lepp_kernel.grid_vertex_hash(vertex, gx, gy, bits) == expected
    # a power of two in the numerator cancels against the denominator
    shifted = gx >> 1 << 1
    assert lepp_kernel.grid_vertex_hash(vertex, shifted, gy, bits) == digest.vertex_hash(
        vertex, (mpq(shifted, 2**bits), mpq(gy, 2**bits)))


def test_grid_vertex_hash_refuses_an_exponent_off_its_range() -> None:
    from geomexact.mesh2d.refinement.engines import lepp_kernel

    with pytest.raises(ValueError, match=r"outside 0\.\.62"):
        lepp_kernel.grid_vertex_hash(0, 1, 1, 63)


@settings(max_examples=300, deadline=None)
@given(g=st.one_of(st.integers(-2**63, 2**63 - 1), st.integers(-99, 99)),
       shift=st.integers(0, 56), bits=st.integers(0, 62))
def test_grid_rational_is_the_mpq(g: int, shift: int, bits: int) -> None:
    """The kernel's mpq(g, 2**F), built in place through gmpy2's C API, is gmpy2's own:
    reduced, same hash (its cache reset), same arithmetic, same pickle."""
    import pickle

    from geomexact.mesh2d.refinement.engines import lepp_kernel

    if -2**63 <= g << shift < 2**63:
        g <<= shift
    made, expected = lepp_kernel.grid_rational(g, bits), mpq(g, 2**bits)
    assert type(made) is type(expected)
    assert (made.numerator, made.denominator) == (expected.numerator, expected.denominator)
    assert made == expected and hash(made) == hash(expected)
    assert made + expected == 2 * expected and made * 3 == 3 * expected
    assert pickle.loads(pickle.dumps(made)) == expected and str(made) == str(expected)


def test_grid_rationals_are_built_in_c_when_the_headers_were_there() -> None:
    """Built against gmpy2's headers and run with that gmpy2: the C path is taken."""
    import gmpy2

    from geomexact.mesh2d.refinement.engines import lepp_kernel

    if gmpy2.version() == lepp_kernel.GMPY2_BUILT_VERSION:
        assert lepp_kernel.GRID_MPQ_IN_C
    else:
        assert not lepp_kernel.GRID_MPQ_IN_C


def test_exceptions_propagate() -> None:
    """An exception in a criterion or in on_step leaves the run (as in the Python engine)."""
    def boom(a: Point2, b: Point2, c: Point2) -> bool:
        raise RuntimeError("criterion")

    with pytest.raises(RuntimeError, match="criterion"):
        run_compiled(square(), None, options(CallableCriterion(boom)))

    def stop(progress: Progress) -> None:
        if progress.steps == 3:
            raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"):
        run_compiled(square(), None, options(MaxArea("0.01"), on_step=stop))


def test_kernel_steps_are_plain_steps_left_to_reference_counting() -> None:
    """The kernels build their steps in place (``make_step``): each is a ``Step`` equal to
    the one the attrs ``__init__`` makes, hashable, picklable, and, with its arguments,
    untracked by the cyclic collector."""
    import gc
    import pickle

    from geomexact.mesh2d.delaunay.triangulation import triangulate
    from geomexact.trace.step import Step

    result = refine(square(), MaxArea("0.01"), method="centroid")
    built = triangulate([point2(*xy) for xy in [(0, 0), (3, 0), (3, 2), (0, 2), (1, 1),
                                                (2, 1)]]).trace.steps
    for step in (*result.trace.steps, *built):
        assert type(step) is Step
        again = Step(step.op, step.args)
        assert step == again and hash(step) == hash(again) and repr(step) == repr(again)
        assert pickle.loads(pickle.dumps(step)) == again
        assert not gc.is_tracked(step) and not gc.is_tracked(step.args)
    assert {step.op for step in result.trace.steps} >= {"insert_in_quadrilateral", "flip"}
