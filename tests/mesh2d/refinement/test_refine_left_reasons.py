"""Why each triangle is left (``RefineStats.left_reasons``): the run's own rule, one reason
per left triangle; a sharp-corner triangle has its small angle at a sharp input corner;
after a step limit the bad triangles not refined yet are ``waiting``."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import mpq, point2, triangulate
from geomexact.kernel.angles import compare_angle
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea, MinAngle


def wedge(height: int) -> PSLG:
    """A quadrilateral with sharp corners at vertices 0 and 2 (thinner for a smaller
    ``height``)."""
    points = [point2(0, 0), point2(10, 0), point2(12, 1), point2(10, mpq(height, 100))]
    return PSLG(vertices=points, segments=[(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)])


@given(st.integers(20, 300), st.sampled_from([20, 25, 30]))
@settings(max_examples=15, deadline=None)
def test_each_left_triangle_has_its_reason(height: int, degrees: int) -> None:
    mesh = triangulate(wedge(height)).mesh
    threshold = MinAngle(degrees)
    stats = refine(mesh, threshold, method="centroid").stats
    assert len(stats.left_reasons) == len(stats.left)
    assert set(stats.left_reasons) <= {"sharp-corner", "protected-tip"}
    assert stats.waiting == ()  # complete: nothing waits
    result = refine(mesh, threshold, method="centroid").mesh
    for triangle, reason in zip(stats.left, stats.left_reasons, strict=True):
        if reason == "sharp-corner":  # a small angle at an input corner (ids 0..3)
            a, b, c = triangle
            point = result.point
            assert any(
                p < 4 and compare_angle(point(q), point(p), point(r),
                                        threshold.angle_threshold) == Comparison.LESS
                for p, q, r in ((a, b, c), (b, c, a), (c, a, b))
            )
    summary = stats.left_summary()
    assert (summary is None) == (not stats.left)


def test_a_step_limit_lists_the_triangles_waiting() -> None:
    mesh = triangulate(wedge(300)).mesh
    stats = refine(mesh, MaxArea(mpq(1, 10)), max_steps=3).stats
    assert stats.status == "step-limit" and stats.waiting and not stats.left
    summary = stats.left_summary()
    assert summary is not None and f"{len(stats.waiting)} not refined yet" in summary
    done = refine(mesh, MaxArea(mpq(1, 10))).stats
    assert done.status == "complete" and done.waiting == ()
