"""The display measures of tetrahedra at any scale: :func:`lattice_quality` on the doubles
and exactly, the exact measures of one shape against the doubles' ones, and the extremes
(a cube of side 1e300 or 1e-300, a box far thinner along one axis): never NaN."""

from __future__ import annotations

import math

import numpy as np
import pytest
from gmpy2 import mpq
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.mesh3d import quality
from geomexact.mesh3d.quality import (
    dihedral_angles,
    exact_shape_quality,
    lattice_quality,
    quality_summary,
    radius_edge_ratios,
)

# a cube of side 2 cut into five tetrahedra: four corners and the regular middle one
CUBE = [(x, y, z) for x in (0, 2) for y in (0, 2) for z in (0, 2)]
FIVE = [[0, 1, 2, 4], [1, 3, 2, 7], [1, 4, 5, 7], [2, 7, 6, 4], [1, 2, 4, 7]]
FIVE = [t if np.linalg.det(np.subtract([CUBE[v] for v in t[1:]], CUBE[t[0]])) > 0
        else [t[1], t[0], *t[2:]] for t in FIVE]


def test_exact_measures_of_the_regular_tetrahedron() -> None:
    angles, ratio = exact_shape_quality((0, -2, -2), (-2, 0, -2), (-2, -2, 0))
    assert angles == pytest.approx([math.degrees(math.acos(1 / 3))] * 6, rel=1e-15)
    assert ratio == pytest.approx(math.sqrt(6) / 4, rel=1e-15)


@pytest.mark.parametrize("side", ["1", "1e300", "1e-300", "3/7", "1e400", "1e-400"])
def test_a_cube_of_any_side_has_the_unit_cubes_figures(side: str) -> None:
    unit = lattice_quality(CUBE, [mpq(1)] * 3, FIVE)
    assert unit.min_dihedral == pytest.approx(math.degrees(math.acos(1 / math.sqrt(3))))
    assert unit.max_dihedral == pytest.approx(90.0)
    assert unit.max_radius_edge == pytest.approx(math.sqrt(3) / 2)
    assert lattice_quality(CUBE, [mpq(side)] * 3, FIVE) == unit  # bit for bit


@pytest.mark.parametrize("scale", [1e300, 1e-300, 2.0**1000, 3.0])
def test_the_doubles_are_scaled_per_shape(scale: float) -> None:
    """Each shape is measured at a power-of-two scale near 1: a cube of 1e300 or 1e-300
    has the unit cube's figures (its doubles would overflow or underflow to NaN), exactly
    so for a power-of-two scale, within rounding of the scaled corners otherwise."""
    unit = quality_summary(np.array(CUBE, dtype=float), FIVE)
    with np.errstate(all="raise"):
        scaled = quality_summary(np.array(CUBE, dtype=float) * scale, FIVE)
    for ours, theirs in ((scaled.min_dihedral, unit.min_dihedral),
                         (scaled.max_dihedral, unit.max_dihedral),
                         (scaled.max_radius_edge, unit.max_radius_edge)):
        assert ours is not None and theirs is not None
        assert ours == (theirs if scale == 2.0**1000 else pytest.approx(theirs, rel=1e-12))


@pytest.mark.parametrize("thin", ["1e-40", "1e-200", "1e-400"])
def test_a_thin_box_is_measured_exactly_and_never_nan(thin: str) -> None:
    summary = lattice_quality(CUBE, [mpq(1), mpq(thin), mpq(1)], FIVE)
    values = (summary.min_dihedral, summary.max_dihedral, summary.max_radius_edge)
    assert all(value is not None and not math.isnan(value) for value in values)
    assert summary.min_dihedral == 0.0 and summary.max_dihedral == 180.0  # rounded
    ratio = summary.max_radius_edge
    assert ratio is not None
    if thin == "1e-400":
        assert ratio == math.inf  # beyond the doubles
    else:
        # the longest of the five, over the thin edge: half the cube's diagonal
        assert ratio == pytest.approx(math.sqrt(2) / 2 / float(mpq(thin)), rel=1e-12)


def test_empty() -> None:
    assert lattice_quality(CUBE, [mpq(1)] * 3, []).min_dihedral is None


corner = st.tuples(*[st.integers(-6, 6)] * 3)


@settings(max_examples=200, deadline=None)
@given(st.lists(corner, min_size=4, max_size=4, unique=True),
       st.tuples(*[st.integers(1, 10**6)] * 3))
def test_exact_measures_agree_with_the_doubles(corners: list[tuple[int, int, int]],
                                               steps: tuple[int, int, int]) -> None:
    """Both ways of measuring give the same figures (to the doubles' rounding), on any
    non-flat tetrahedron with any steps."""
    points = [tuple(c * s for c, s in zip(p, steps, strict=True)) for p in corners]
    (bx, by, bz), (cx, cy, cz), (dx, dy, dz) = (
        tuple(q - p for q, p in zip(x, points[0], strict=True)) for x in points[1:])
    volume = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx)
    if volume == 0:
        return
    order = [0, 1, 2, 3] if volume > 0 else [1, 0, 2, 3]
    tetrahedron = [order]
    a, b, c, d = (points[v] for v in order)
    shape = [(x[0] - a[0], x[1] - a[1], x[2] - a[2]) for x in (b, c, d)]
    angles, ratio = exact_shape_quality(shape[0], shape[1], shape[2])
    assert np.allclose(dihedral_angles(points, tetrahedron)[0], angles, rtol=0, atol=1e-6)
    assert radius_edge_ratios(points, tetrahedron)[0] == pytest.approx(ratio, rel=1e-9)
    # lattice_quality on either path: the doubles, and exactly (every ratio of steps
    # below a threshold above 1)
    units = [mpq(s) for s in steps]
    for threshold in (quality.DOUBLES_FROM, mpq(2)):
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(quality, "DOUBLES_FROM", threshold)
            summary = lattice_quality(corners, units, tetrahedron)
        assert summary.min_dihedral == pytest.approx(min(angles), abs=1e-6)
        assert summary.max_dihedral == pytest.approx(max(angles), abs=1e-6)
        assert summary.max_radius_edge == pytest.approx(ratio, rel=1e-9)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(FIVE), st.tuples(*[st.integers(-3, 3)] * 3),
                          st.sampled_from([1.0, 0.5, 4.0])), min_size=1, max_size=30))
def test_each_tetrahedron_gets_its_own_shapes_measures(
        pieces: list[tuple[list[int], tuple[int, int, int], float]]) -> None:
    """Measured once a shape, then handed to every tetrahedron of that shape: the same
    doubles as measuring each tetrahedron alone (translated and scaled copies of the
    cube's five tetrahedra, repeated and in any order)."""
    points, tetrahedra = [], []
    for tetrahedron, shift, scale in pieces:
        tetrahedra.append([len(points) + k for k in range(4)])
        points += [tuple(scale * (c + s) for c, s in zip(CUBE[v], shift, strict=True))
                   for v in tetrahedron]
    angles = dihedral_angles(points, tetrahedra)
    ratios = radius_edge_ratios(points, tetrahedra)
    for row, tetrahedron in enumerate(tetrahedra):
        alone = np.array([points[v] for v in tetrahedron])
        assert (angles[row] == dihedral_angles(alone, [[0, 1, 2, 3]])[0]).all()
        assert ratios[row] == radius_edge_ratios(alone, [[0, 1, 2, 3]])[0]


def test_shapes_that_share_a_hash_are_still_told_apart(monkeypatch: pytest.MonkeyPatch
                                                        ) -> None:
    """Every shape hashed alike (a collision everywhere): the rows themselves decide."""
    points = [tuple(2 * c + s for c in corner) for s in (0, 1) for corner in CUBE]
    tetrahedra = [*FIVE, *([v + 8 for v in t] for t in FIVE)]
    expected = dihedral_angles(points, tetrahedra), radius_edge_ratios(points, tetrahedra)
    monkeypatch.setattr(quality, "_row_hashes",
                        lambda columns: np.zeros(columns.shape[1], dtype=np.uint64))
    assert (dihedral_angles(points, tetrahedra) == expected[0]).all()
    assert (radius_edge_ratios(points, tetrahedra) == expected[1]).all()
