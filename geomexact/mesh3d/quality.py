"""Display measures of tetrahedra, vectorised (numpy, doubles): dihedral angles and the
radius-edge ratio.  They are for reports and pictures only; exact questions (orientation,
volume, Delaunay) are answered by ``measures`` and ``validation``.  On a lattice with
exact steps (the octree's), :func:`lattice_quality` gives them at any scale."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import attrs
import gmpy2
import numpy as np

from geomexact.kernel.numbers import Rational
from geomexact.kernel.vectors import cross3, dot3, sub3

__all__ = [
    "QualitySummary",
    "dihedral_angles",
    "lattice_quality",
    "quality_summary",
    "radius_edge_ratios",
]

_EDGES = ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1))
"""Each edge (i, j) of a tetrahedron with its two other vertices (k, l)."""


def _shapes(points: Any, tetrahedra: Any) -> tuple[Any, Any]:
    """The distinct shapes of the tetrahedra, as corners (S x 4 x 3) with the first at
    the origin, and each tetrahedron's shape (T,): the measures below are taken once a
    shape.  An octree's 234,208 tetrahedra have 1,407 shapes; a mesh whose shapes are all
    different pays one sort of its T rows of nine doubles.

    Translated corners: the edges are ``(c_j - c_0) - (c_i - c_0)`` instead of ``c_j -
    c_i``, the same doubles wherever the differences are exact (lattice points, as in
    an octree's mesh), within an ulp of them elsewhere: the measures are for display.
    The nine differences are kept column by column (9 x T: each a gather and a
    subtraction, and the hash below runs on columns that stay in cache)."""
    coordinates = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    ids = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    corners = [np.ascontiguousarray(ids[:, corner]) for corner in range(4)]
    columns = np.empty((9, len(ids)))
    for axis in range(3):
        values = np.ascontiguousarray(coordinates[:, axis])
        origin = values[corners[0]]
        for corner in (1, 2, 3):
            np.subtract(values[corners[corner]], origin, out=columns[3 * (corner - 1) + axis])
    _, first, shape = np.unique(_row_hashes(columns), return_index=True, return_inverse=True)
    shape = shape.ravel()
    chosen = first[shape]
    if not all(np.array_equal(column[chosen], column) for column in columns):
        # two shapes share a hash
        rows = np.ascontiguousarray(columns.T)
        keys = rows.view(np.dtype((np.void, rows.itemsize * 9))).ravel()
        _, first, shape = np.unique(keys, return_index=True, return_inverse=True)
        shape = shape.ravel()
    distinct = columns[:, first].T
    # each shape scaled by a power of two to a largest coordinate in [1/2, 1): exact, so
    # the same measures, without the overflow or underflow of a 1e300 or 1e-300 mesh
    _, exponent = np.frexp(np.abs(distinct).max(axis=1))
    shapes = np.zeros((len(first), 4, 3))
    shapes[:, 1:] = np.ldexp(distinct, -exponent[:, None]).reshape(-1, 3, 3)
    return shapes, shape


_COLUMN_MULTIPLIERS = np.array(
    [0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0xD6E8FEB86659FD93,
     0xA0761D6478BD642F, 0xE7037ED1A0B428DB, 0x8EBC6AF09C88C6E3, 0x589965CC75374CC3,
     0x1D8E4E27C47D124F], dtype=np.uint64)


def _row_hashes(columns: Any) -> Any:
    """A 64-bit hash of each row of nine doubles, given as nine columns (9 x T), of
    their bits (a 1-D sort of these is about 3x faster than one of the rows; the caller
    checks that equal hashes are equal rows).  The bits are folded down before the
    multiply: a small integer's double has its information in its high bits, which a
    multiply alone never carries down.  Column by column, in place."""
    count = columns.shape[1]
    total = np.zeros(count, dtype=np.uint64)
    mixed, shifted = np.empty(count, dtype=np.uint64), np.empty(count, dtype=np.uint64)
    for bits, multiplier in zip(columns.view(np.uint64), _COLUMN_MULTIPLIERS, strict=True):
        np.right_shift(bits, np.uint64(32), out=mixed)
        mixed ^= bits
        np.right_shift(mixed, np.uint64(16), out=shifted)
        mixed ^= shifted
        mixed *= multiplier
        np.right_shift(mixed, np.uint64(31), out=shifted)
        mixed ^= shifted
        total += mixed
    return total


def _cross(u: Any, v: Any) -> Any:
    """The cross product of each row of u and v (n x 3): np.cross's arithmetic written out
    (the same doubles, without its reshaping and copies)."""
    return np.stack((u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],
                     u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                     u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), axis=1)


def _dihedral_angles(p: Any) -> Any:
    angles = np.empty((len(p), len(_EDGES)))
    for n, (i, j, k, m) in enumerate(_EDGES):
        edge = p[:, j] - p[:, i]
        first = _cross(edge, p[:, k] - p[:, i])  # the normals of faces (i, j, k), (i, j, m)
        second = _cross(edge, p[:, m] - p[:, i])
        cosine = np.einsum("ij,ij->i", first, second) / (
            np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1))
        angles[:, n] = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    return angles


def _radius_edge_ratios(p: Any) -> Any:
    b, c, d = (p[:, n] - p[:, 0] for n in (1, 2, 3))
    cd = _cross(c, d)
    numerator = (np.einsum("ij,ij->i", b, b)[:, None] * cd
                 + np.einsum("ij,ij->i", c, c)[:, None] * _cross(d, b)
                 + np.einsum("ij,ij->i", d, d)[:, None] * _cross(b, c))
    denominator = 2.0 * np.einsum("ij,ij->i", b, cd)
    radius = np.linalg.norm(numerator, axis=1) / np.abs(denominator)
    lengths = [np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j, _, _ in _EDGES]
    return radius / np.min(np.stack(lengths, axis=1), axis=1)


def dihedral_angles(points: Any, tetrahedra: Any) -> Any:
    """The six dihedral angles (degrees) of each tetrahedron (T x 6), from float
    coordinates ``points`` (V x 3), measured once a shape (:func:`_shapes`)."""
    if len(tetrahedra) == 0:
        return np.empty((0, len(_EDGES)))
    corners, shape = _shapes(points, tetrahedra)
    return _dihedral_angles(corners)[shape]


def radius_edge_ratios(points: Any, tetrahedra: Any) -> Any:
    """Circumradius / shortest edge of each tetrahedron (sqrt(6)/4 ~ 0.612 for the
    regular one), measured once a shape."""
    if len(tetrahedra) == 0:
        return np.empty(0)
    corners, shape = _shapes(points, tetrahedra)
    return _radius_edge_ratios(corners)[shape]


@attrs.frozen(slots=True)
class QualitySummary:
    """Extremes over a mesh (degrees; ratios): None for an empty mesh."""

    min_dihedral: float | None
    max_dihedral: float | None
    max_radius_edge: float | None


def quality_summary(points: Any, tetrahedra: Any) -> QualitySummary:
    """The smallest and largest dihedral angle and the largest radius-edge ratio."""
    if len(tetrahedra) == 0:
        return QualitySummary(None, None, None)
    corners, _ = _shapes(points, tetrahedra)
    angles = _dihedral_angles(corners)
    ratios = _radius_edge_ratios(corners)
    return QualitySummary(float(angles.min()), float(angles.max()), float(ratios.max()))


DOUBLES_FROM = gmpy2.mpq(1, 2**100)
""":func:`lattice_quality` goes through doubles when every step divided by the largest is
at least this: the norms are products of up to eight coordinates, each non-zero one then
between 2^-100 and 2^62 in magnitude, so they stay within the normal doubles."""


def lattice_quality(
    vertices: Any, units: Sequence[Rational], tetrahedra: Any
) -> QualitySummary:
    """:func:`quality_summary` of ``tetrahedra`` on the integer lattice points ``vertices``
    (V x 3) whose step along axis a is the exact ``units[a]`` (> 0): right at any scale.

    The figures depend only on the steps' ratios, so the steps are first divided exactly by
    the largest: a cube of side 1e300 or 1e-300 gives the unit cube's figures bit for bit.
    When the ratios are at least :data:`DOUBLES_FROM` the doubles measure every
    tetrahedron; beyond (a box far thinner along one axis than another) each distinct
    shape is measured in exact integers and rounded once (:func:`exact_shape_quality`).
    Never NaN; a radius-edge ratio beyond the doubles is ``inf``."""
    if len(tetrahedra) == 0:
        return QualitySummary(None, None, None)
    largest = max(gmpy2.mpq(unit) for unit in units)
    steps = [gmpy2.mpq(unit) / largest for unit in units]
    if min(steps) >= DOUBLES_FROM:
        scale = np.array([float(step) for step in steps])  # exact: 1 or within 2^-100..1
        return quality_summary(np.asarray(vertices, dtype=np.float64) * scale, tetrahedra)
    denominator = math.lcm(*(int(step.denominator) for step in steps))
    integer_steps = [int(step * denominator) for step in steps]
    lowest, highest, worst = math.inf, -math.inf, 0.0
    for shape in _lattice_shapes(vertices, tetrahedra).tolist():
        b, c, d = (tuple(shape[3 * k + a] * integer_steps[a] for a in range(3)) for k in range(3))
        angles, ratio = exact_shape_quality(b, c, d)
        lowest, highest = min(lowest, *angles), max(highest, *angles)
        worst = max(worst, ratio)
    return QualitySummary(lowest, highest, worst)


def _lattice_shapes(vertices: Any, tetrahedra: Any) -> Any:
    """The distinct shapes of the tetrahedra (rows b - a, c - a, d - a of each, divided by
    their gcd: the figures do not change under a uniform scaling), as int64 rows of 9."""
    points = np.asarray(vertices, dtype=np.int64)[np.asarray(tetrahedra, dtype=np.int64)]
    shapes = (points[:, 1:] - points[:, :1]).reshape(-1, 9)
    divisor = np.gcd.reduce(shapes, axis=1)
    return np.unique(shapes // np.maximum(divisor, 1)[:, None], axis=0)


Vector = tuple[int, int, int]





def _root_of_quotient(numerator: int, denominator: int) -> float:
    """sqrt(numerator / denominator) (positive integers) to within an ulp or two; ``inf``
    beyond the doubles."""
    try:
        return math.sqrt(numerator / denominator)  # int / int: correctly rounded
    except OverflowError:  # the square is beyond the doubles: the integer root is close
        try:
            return float(math.isqrt(numerator // denominator))
        except OverflowError:
            return math.inf


def exact_shape_quality(b: Vector, c: Vector, d: Vector) -> tuple[list[float], float]:
    """The six dihedral angles (degrees, :data:`_EDGES` order) and the radius-edge ratio of
    the non-flat tetrahedron (0, b, c, d) of integer corners: each cosine squared and the
    ratio squared are exact quotients, rounded once to a double, then rooted."""
    p = ((0, 0, 0), b, c, d)
    angles = []
    for i, j, k, m in _EDGES:
        edge = sub3(p[j], p[i])
        first = cross3(edge, sub3(p[k], p[i]))
        second = cross3(edge, sub3(p[m], p[i]))
        dot = dot3(first, second)
        root = math.sqrt(dot * dot / (dot3(first, first) * dot3(second, second)))
        angles.append(math.degrees(math.acos(-root if dot < 0 else root)))
    terms = (cross3(c, d), cross3(d, b), cross3(b, c))
    weights = (dot3(b, b), dot3(c, c), dot3(d, d))
    centre = tuple(sum(w * t[a] for w, t in zip(weights, terms, strict=True)) for a in range(3))
    volume = 2 * dot3(b, terms[0])
    shortest = min(dot3(edge, edge) for edge in (sub3(p[j], p[i]) for i, j, _, _ in _EDGES))
    ratio = _root_of_quotient(sum(x * x for x in centre), volume * volume * shortest)
    return angles, ratio
