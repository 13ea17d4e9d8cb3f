"""The fast refinement engines (compiled and Python) against the reference engine (the ops
on a transient): the same steps, the same digest after every step, the same result, for
every method, criterion, region, centroid kind, rule and step limit."""

from __future__ import annotations

from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from geomexact import Mesh2, mpq, replay, total_area
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import Result, refine
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    Criterion,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
)
from geomexact.mesh2d.refinement.regions import Circle, Polygon, Rectangle, Region, Whole
from geomexact.strategies import meshes_with_traces, pslgs

REGIONS = st.sampled_from([
    Whole(), Circle(0, 0, 3), Circle(100, 100, 90), Rectangle(-2, -2, 6, 3),
    Polygon([(0, 0), (300, 0), (0, 300)]),
])


def both(start: Mesh2, criterion: Criterion, **options: Any) -> Result:
    """The default engine (compiled where it applies) and the Python engine against the
    reference: the same run in every respect."""
    fast = refine(start, criterion, engine="fast", **options)
    if options.get("method", "bisection") == "bisection":
        python = refine(start, criterion, engine="python", **options)
        assert python.trace == fast.trace
        assert python.mesh == fast.mesh
    reference = refine(start, criterion, engine="transient", **options)
    assert fast.trace.steps == reference.trace.steps
    assert fast.trace.digests == reference.trace.digests
    assert fast.trace == reference.trace
    assert fast.mesh == reference.mesh
    assert fast.stats.left == reference.stats.left
    assert fast.status == reference.status
    for name in ("bisections", "centroids", "flips", "targets", "lepp_searches",
                 "lepp_triangles"):
        assert getattr(fast.stats, name) == getattr(reference.stats, name), name
    return fast


@given(
    meshes_with_traces(max_steps=10),
    st.sampled_from(["bisection", "centroid", "quasi"]),
    st.booleans(),
    st.sampled_from(["area", "area-exact", "vertices"]),
    st.booleans(),
    st.sampled_from(["max_area", "edge", "factor", "angle"]),
    REGIONS,
    st.sampled_from([None, 0, 3, 25]),
)
def test_engines_record_the_same_trace(
    case: tuple[Mesh2, Mesh2, Any], method: Any, delaunay: bool, centroid: Any,
    midpoints: bool, kind: str, region: Region, limit: int | None,
) -> None:
    """Random meshes (convex polygons after random steps): identical runs."""
    _, start, _ = case
    area = total_area(start)
    criterion: Criterion = {
        "max_area": MaxArea(area / 30),
        "edge": MaxEdgeLength(mpq(1, 4) * 256),
        "factor": AverageAreaFactor(mpq(1, 3)),
        "angle": MinAngle(27),
    }[kind]
    if kind == "angle" or centroid == "area-exact":
        # exact area centroids grow coordinates geometrically: keep those runs short; and
        # minimum-angle runs on random meshes need not terminate (random convex polygons
        # can have input angles below 27° that the small-angle rules do not bound — a
        # known limit, specs/refine.md), while this test is about engine equality
        limit = 40 if limit is None else limit
    result = both(start, criterion, method=method, delaunay=delaunay, centroid=centroid,
                  constraint_midpoints=midpoints, region=region, max_steps=limit)
    assert replay(start, result.trace) == result.mesh


@given(pslgs(max_boundary=9, max_points=8), st.sampled_from(["centroid", "quasi"]),
       st.integers(20, 34), st.booleans())
def test_engines_agree_on_min_angle_refinement_of_pslgs(
    pslg: PSLG, method: Any, degrees: int, delaunay: bool
) -> None:
    """Constrained Delaunay triangulations of PSLGs (holes, small input angles); without
    flips the run cannot finish, so it is cut at 150 steps."""
    start = triangulate(pslg).mesh
    both(start, MinAngle(degrees), method=method, delaunay=delaunay,
         max_steps=None if delaunay else 150)


@given(st.sampled_from(["bisection", "centroid", "quasi"]), st.integers(3, 60))
def test_engines_agree_with_triangle_attributes(method: Any, pieces: int) -> None:
    """Regional attributes (two regions): the kernel's attribute path."""
    from geomexact import mesh_from_triangles

    start = mesh_from_triangles(
        [(0, 0), (4, 0), (4, 3), (0, 3), (2, 1)],
        [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
        [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)],
        triangle_attributes=[(mpq(1),), (mpq(1),), (mpq(2),), (mpq(3),)],
    )
    both(start, MaxArea(mpq(12, pieces)), method=method)
    both(start, MinAngle(28), method=method, max_steps=500)
