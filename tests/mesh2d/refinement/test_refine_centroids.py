"""The rounded area centroid of a terminal quadrilateral and the step
``insert_in_quadrilateral`` (``geomexact.mesh2d.refinement.centroids``)."""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from geomexact import (
    PreconditionError,
    Step,
    apply,
    mesh_from_triangles,
    mpq,
    point2,
    total_area,
    validate,
)
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.ops import quadrilateral_area_centroid
from geomexact.mesh2d.refinement.centroids import CENTROID_BITS, rounded_area_centroid
from geomexact.strategies import convex_polygons


def test_module_doctest() -> None:
    """The module's docstring examples (none yet besides prose) run cleanly."""
    import doctest

    from geomexact.mesh2d.refinement import centroids
    assert doctest.testmod(centroids).failed == 0


def rhombus() -> Any:
    return mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (1, 0, 3)])


def test_the_centroid_of_a_symmetric_quadrilateral_is_exact() -> None:
    """Its centre (2, 0) lies on every grid: no rounding at all."""
    mesh = rhombus()
    p = [mesh.point(i) for i in range(4)]
    assert rounded_area_centroid(p[0], p[1], p[2], p[3]) == point2(2, 0)


@given(convex_polygons(min_size=4, max_size=4, coordinate_bits=20))
def test_rounded_centroid_is_near_the_exact_one_inside_and_small(corners: list[Any]) -> None:
    """For a strictly convex quadrilateral: strictly inside the four triangles, with
    power-of-two denominators when rounded, and within half a grid cell (2^-bits of the
    shortest side) of the exact area centroid in each coordinate."""
    if len(corners) != 4:
        return
    u, x, v, w = corners  # counter-clockwise: triangles (u, v, w) and (v, u, x)
    exact = quadrilateral_area_centroid(u, v, w, x)
    point = rounded_area_centroid(u, v, w, x)
    for p, q in ((u, x), (x, v), (v, w), (w, u)):
        assert orient2d(p, q, point) == Orientation.COUNTERCLOCKWISE
    shortest = min((q.x - p.x) ** 2 + (q.y - p.y) ** 2
                   for p, q in ((u, x), (x, v), (v, w), (w, u)))
    distance = (point.x - exact.x) ** 2 + (point.y - exact.y) ** 2
    assert distance <= shortest * mpq(1, 2 ** (2 * CENTROID_BITS + 1))
    if point != exact:
        for denominator in (int(point.x.denominator), int(point.y.denominator)):
            assert denominator & (denominator - 1) == 0


def test_insert_in_quadrilateral_splits_two_triangles_into_four() -> None:
    """The step joins the given point to the four corners; area kept; replays by apply."""
    mesh = rhombus()
    result = apply(mesh, Step("insert_in_quadrilateral", (0, 1, mpq(2), mpq(1, 4))))
    assert result.triangle_count == 4
    assert validate(result) == []
    assert total_area(result) == total_area(mesh)
    assert result.point(4) == point2(2, "0.25")


@pytest.mark.parametrize(
    ("step", "message"),
    [
        (Step("insert_in_quadrilateral", (0, 1, mpq(4), mpq(0))), "not strictly inside"),
        (Step("insert_in_quadrilateral", (0, 1, mpq(2), mpq(1))), "not strictly inside"),
        (Step("insert_in_quadrilateral", (0, 2, mpq(1), mpq(0))), "boundary"),
        (Step("insert_in_quadrilateral", (2, 3, mpq(2), mpq(0))), "not an edge"),
        (Step("insert_in_quadrilateral", (0, 1, mpq(2))), "expects"),
    ],
)
def test_insert_in_quadrilateral_checks_its_preconditions(step: Step, message: str) -> None:
    """Outside or on the quadrilateral's border, a boundary edge, a non-edge, wrong
    arguments: a precise error."""
    with pytest.raises(PreconditionError, match=message):
        apply(rhombus(), step)


def test_insert_in_quadrilateral_refuses_constrained_edges_and_mixed_attributes() -> None:
    """Like insert_centroid: never across a segment or between different attributes."""
    segment = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (1, 0, 3)],
                                  [(0, 1, 7)])
    with pytest.raises(PreconditionError, match="constrained"):
        apply(segment, Step("insert_in_quadrilateral", (0, 1, mpq(2), mpq(0))))
    mixed = mesh_from_triangles([(0, 0), (4, 0), (2, 1), (2, -1)], [(0, 1, 2), (1, 0, 3)],
                                triangle_attributes=[(mpq(1),), (mpq(2),)])
    with pytest.raises(PreconditionError, match="attributes"):
        apply(mixed, Step("insert_in_quadrilateral", (0, 1, mpq(2), mpq(0))))


@given(st.integers(1, 2**20), st.integers(1, 2**20))
def test_rounded_centroids_of_thin_quadrilaterals_are_inside(height: int, scale: int) -> None:
    """Very thin rhombi (height down to 2^-40 of the width): still strictly inside."""
    h = mpq(height, 2**40)
    width = mpq(scale)
    u, v, w, x = point2(0, 0), point2(width, 0), point2(width / 2, h), point2(width / 3, -h)
    point = rounded_area_centroid(u, v, w, x)
    for p, q in ((u, x), (x, v), (v, w), (w, u)):
        assert orient2d(p, q, point) == Orientation.COUNTERCLOCKWISE
