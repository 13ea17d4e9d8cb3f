"""The certified float filters on numpy arrays: many predicates at once.

Each function takes the points' doubles as two float64 arrays ``fx``, ``fy`` (three with
``fz`` in space; indexed by point id, see :func:`point_doubles`) and index arrays naming
the points of each query, and returns an int8 array of signs: the exact sign where the
float filter certifies it, **0 where it does not** (an exact zero is never certified
either): the caller decides those entries exactly, with the scalar predicate.  The filters
repeat the scalar ones of :mod:`~geomexact.kernel.predicates2d`,
:mod:`~geomexact.kernel.predicates3d` and :mod:`~geomexact.kernel.comparisons` operation
for operation, in the same order and with the same constants
(:mod:`~geomexact.kernel.filter_bounds`), and evaluate the incircle and orient3d
determinants with the very functions the exact predicates use, so they certify exactly
the queries the scalar filter certifies, with the same sign; NaN (a coordinate beyond the
double range) and overflow are never certified.  They do not touch the filter counters.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from geomexact.kernel.filter_bounds import (
    INCIRCLE_C,
    INCIRCLE_K,
    LENGTHS_C,
    LENGTHS_K,
    ORIENT2D_C,
    ORIENT2D_K,
    ORIENT3D_C,
    ORIENT3D_K,
)
from geomexact.kernel.points import Point2, Point3
from geomexact.kernel.predicates2d import _incircle_determinant
from geomexact.kernel.predicates3d import _orient3d_determinant

__all__ = ["incircle_signs", "orient2d_signs", "orient3d_signs", "point_doubles",
           "point_doubles3", "squared_length_signs"]

FloatArray = npt.NDArray[np.float64]
SignArray = npt.NDArray[np.int8]
BoolArray = npt.NDArray[np.bool_]


def point_doubles(points: Sequence[Point2]) -> tuple[FloatArray, FloatArray]:
    """The doubles ``fx`` and ``fy`` of ``points`` (``nan`` beyond the double range), as
    two arrays indexed like ``points``."""
    count = len(points)
    fx = np.fromiter((p.fx for p in points), dtype=np.float64, count=count)
    fy = np.fromiter((p.fy for p in points), dtype=np.float64, count=count)
    return fx, fy


def point_doubles3(points: Sequence[Point3]) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The doubles ``fx``, ``fy`` and ``fz`` of ``points`` (``nan`` beyond the double
    range), as three arrays indexed like ``points``."""
    count = len(points)
    return tuple(  # type: ignore[return-value]
        np.fromiter((p[k] for p in points), dtype=np.float64, count=count) for k in (3, 4, 5))


def _doubles(fx: FloatArray, fy: FloatArray, index: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The doubles of the points ``index`` names (an array of point ids)."""
    ids = np.asarray(index, dtype=np.intp)
    return fx[ids], fy[ids]


def _signs(positive: BoolArray, negative: BoolArray) -> SignArray:
    return positive.astype(np.int8) - negative.astype(np.int8)


@np.errstate(over="ignore", invalid="ignore")  # inf and NaN are never certified
def orient3d_signs(
    fx: FloatArray, fy: FloatArray, fz: FloatArray, a: npt.ArrayLike, b: npt.ArrayLike,
    c: npt.ArrayLike, d: npt.ArrayLike,
) -> SignArray:
    """``orient3d(p[a[i]], p[b[i]], p[c[i]], p[d[i]])`` of
    :mod:`~geomexact.kernel.predicates3d` for every i as 1 (positive) or -1 where its float
    filter certifies it, else 0 (undecided).  ``fx``, ``fy``, ``fz``: the points' doubles
    (:func:`point_doubles3`).  O(n)."""
    ids = [np.asarray(index, dtype=np.intp) for index in (a, b, c, d)]
    dx, dy, dz = fx[ids[3]], fy[ids[3]], fz[ids[3]]
    adx, ady, adz = fx[ids[0]] - dx, fy[ids[0]] - dy, fz[ids[0]] - dz
    bdx, bdy, bdz = fx[ids[1]] - dx, fy[ids[1]] - dy, fz[ids[1]] - dz
    cdx, cdy, cdz = fx[ids[2]] - dx, fy[ids[2]] - dy, fz[ids[2]] - dz
    det = _orient3d_determinant(adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz)
    t = (
        np.abs(adx) + np.abs(ady) + np.abs(adz) + np.abs(bdx) + np.abs(bdy) + np.abs(bdz)
        + np.abs(cdx) + np.abs(cdy) + np.abs(cdz) + ORIENT3D_K
    )  # fmt: skip
    bound = t * t * (np.abs(dx) + np.abs(dy) + np.abs(dz) + t) * ORIENT3D_C
    return _signs(det > bound, -det > bound)


@np.errstate(over="ignore", invalid="ignore")  # inf and NaN are never certified
def orient2d_signs(
    fx: FloatArray, fy: FloatArray, a: npt.ArrayLike, b: npt.ArrayLike, c: npt.ArrayLike
) -> SignArray:
    """``orient2d(p[a[i]], p[b[i]], p[c[i]])`` for every i as 1 (counterclockwise) or -1
    (clockwise) where its float filter certifies it, else 0 (undecided).  O(n)."""
    (ax, ay), (bx, by), (cx, cy) = (_doubles(fx, fy, i) for i in (a, b, c))
    acx = ax - cx
    acy = ay - cy
    bcx = bx - cx
    bcy = by - cy
    left = acx * bcy
    right = acy * bcx
    det = left - right
    t = np.abs(acx) + np.abs(acy) + np.abs(bcx) + np.abs(bcy) + ORIENT2D_K
    bound = t * (np.abs(cx) + np.abs(cy) + t) * ORIENT2D_C
    # the sign shortcut of orient2d first (products of opposite strict signs), then the bound
    positive = ((left > 0.0) & (right < 0.0)) | (det > bound)
    negative = ((left < 0.0) & (right > 0.0)) | (-det > bound)
    return _signs(positive, negative)


@np.errstate(over="ignore", invalid="ignore")  # inf and NaN are never certified
def squared_length_signs(
    fx: FloatArray,
    fy: FloatArray,
    a: npt.ArrayLike,
    b: npt.ArrayLike,
    c: npt.ArrayLike,
    d: npt.ArrayLike,
) -> SignArray:
    """``compare_squared_lengths(p[a[i]], p[b[i]], p[c[i]], p[d[i]])`` (the sign of
    ``|ab|^2 - |cd|^2``) for every i where its float filter certifies it, else 0
    (undecided).  O(n)."""
    (ax, ay), (bx, by), (cx, cy), (dx, dy) = (_doubles(fx, fy, i) for i in (a, b, c, d))
    ux = bx - ax
    uy = by - ay
    vx = dx - cx
    vy = dy - cy
    diff = (ux * ux + uy * uy) - (vx * vx + vy * vy)
    t = np.abs(ux) + np.abs(uy) + np.abs(vx) + np.abs(vy) + LENGTHS_K
    m = np.abs(ax) + np.abs(ay) + np.abs(cx) + np.abs(cy)
    bound = t * (m + (t + t)) * LENGTHS_C
    return _signs(diff > bound, -diff > bound)


@np.errstate(over="ignore", invalid="ignore")  # inf and NaN are never certified
def incircle_signs(
    fx: FloatArray,
    fy: FloatArray,
    a: npt.ArrayLike,
    b: npt.ArrayLike,
    c: npt.ArrayLike,
    d: npt.ArrayLike,
) -> SignArray:
    """``incircle(p[a[i]], p[b[i]], p[c[i]], p[d[i]])`` for every i as 1 (inside) or -1
    (outside) where its float filter certifies it, else 0 (undecided).  O(n)."""
    (ax, ay), (bx, by), (cx, cy), (dx, dy) = (_doubles(fx, fy, i) for i in (a, b, c, d))
    adx = ax - dx
    ady = ay - dy
    bdx = bx - dx
    bdy = by - dy
    cdx = cx - dx
    cdy = cy - dy
    det = _incircle_determinant(adx, ady, bdx, bdy, cdx, cdy)
    t = (np.abs(adx) + np.abs(ady) + np.abs(bdx) + np.abs(bdy) + np.abs(cdx) + np.abs(cdy)
         + INCIRCLE_K)
    bound = t * t * t * (np.abs(dx) + np.abs(dy) + t) * INCIRCLE_C
    return _signs(det > bound, -det > bound)
