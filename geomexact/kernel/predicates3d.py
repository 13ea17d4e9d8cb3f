"""The space predicates orient3d and insphere: a certified float filter, else exact.

The same scheme as :mod:`~geomexact.kernel.predicates2d` on the floats ``fx, fy, fz`` of
the points (constants in :mod:`~geomexact.kernel.filter_bounds`, derivation in
``specs/predicates.md``); the answer is always the exact one.

Sign conventions (see ``specs/predicates.md``):

* ``orient3d(a, b, c, d)`` is the sign of ``det[b - a, c - a, d - a]``: positive when ``d``
  is on the side of plane abc from which a, b, c appear counterclockwise.  This is the
  *opposite* of Shewchuk's ``orient3d``.
* ``insphere(a, b, c, d, e)`` is positive (INSIDE) when ``e`` is strictly inside the sphere
  through ``a, b, c, d`` *and* ``orient3d(a, b, c, d)`` is positive; the sign flips
  otherwise.  This is the opposite of Shewchuk's ``insphere`` (whose orientation
  convention is the opposite one).
"""

from __future__ import annotations

from typing import Any, Final

from geomexact.kernel.filter_bounds import INSPHERE_C, INSPHERE_K, ORIENT3D_C, ORIENT3D_K
from geomexact.kernel.filter_bounds import INSPHERE_COUNTS as _ISP
from geomexact.kernel.filter_bounds import ORIENT3D_COUNTS as _O3D
from geomexact.kernel.numbers import scaled_to_integers, sign
from geomexact.kernel.points import Point3
from geomexact.kernel.predicate_results import (
    ORIENTATIONS,
    SPHERE_LOCATIONS,
    Orientation,
    SphereLocation,
)

__all__ = ["insphere", "insphere_exact", "orient3d", "orient3d_exact"]

_CCW: Final = Orientation.COUNTERCLOCKWISE
_CW: Final = Orientation.CLOCKWISE
_INSIDE: Final = SphereLocation.INSIDE
_OUTSIDE: Final = SphereLocation.OUTSIDE


def _orient3d_determinant(
    adx: Any, ady: Any, adz: Any, bdx: Any, bdy: Any, bdz: Any, cdx: Any, cdy: Any, cdz: Any
) -> Any:
    """The orient3d determinant of the differences ``a - d``, ``b - d``, ``c - d`` in their
    own arithmetic: exact on rationals, and on floats or numpy arrays (``array_filters``)
    the same operations in the same order as the fast path of :func:`orient3d`."""
    return (
        adz * (cdx * bdy - bdx * cdy)
        + bdz * (adx * cdy - cdx * ady)
        + cdz * (bdx * ady - adx * bdy)
    )


def orient3d_exact(a: Point3, b: Point3, c: Point3, d: Point3) -> Orientation:
    """:func:`orient3d` computed with exact rational arithmetic only."""
    dx = d[0]
    dy = d[1]
    dz = d[2]
    det = _orient3d_determinant(a[0] - dx, a[1] - dy, a[2] - dz, b[0] - dx, b[1] - dy,
                                b[2] - dz, c[0] - dx, c[1] - dy, c[2] - dz)
    return ORIENTATIONS[sign(det)]


def insphere_exact(a: Point3, b: Point3, c: Point3, d: Point3, e: Point3) -> SphereLocation:
    """:func:`insphere` computed with exact rational arithmetic only."""
    ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz, ex, ey, ez = scaled_to_integers(
        (a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2],
         e[0], e[1], e[2])
    )
    aex = ax - ex
    aey = ay - ey
    aez = az - ez
    bex = bx - ex
    bey = by - ey
    bez = bz - ez
    cex = cx - ex
    cey = cy - ey
    cez = cz - ez
    dex = dx - ex
    dey = dy - ey
    dez = dz - ez
    ab = aex * bey - bex * aey
    bc = bex * cey - cex * bey
    cd = cex * dey - dex * cey
    da = dex * aey - aex * dey
    ac = aex * cey - cex * aey
    bd = bex * dey - dex * bey
    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da
    alift = aex * aex + aey * aey + aez * aez
    blift = bex * bex + bey * bey + bez * bez
    clift = cex * cex + cey * cey + cez * cez
    dlift = dex * dex + dey * dey + dez * dez
    det = (clift * dab - dlift * abc) + (alift * bcd - blift * cda)
    return SPHERE_LOCATIONS[sign(det)]


# The fast path is written out in full in each function (no helper calls, tuple indexing,
# locals) because these run millions of times (calling _orient3d_determinant from orient3d
# costs about 6%, an insphere determinant shared with insphere_exact 5-9%, measured);
# each ends as those of predicates2d.


def orient3d(a: Point3, b: Point3, c: Point3, d: Point3) -> Orientation:
    """Orientation of the tetrahedron abcd: the sign of ``det[b - a, c - a, d - a]``.

    COUNTERCLOCKWISE (positive) when d lies on the side of plane abc from which a, b, c
    are seen counterclockwise (the right-hand rule: (b - a) x (c - a) points towards d);
    COLLINEAR when the four points are coplanar.  Opposite sign to Shewchuk's orient3d.
    Exact; float filter first.
    """
    dx = d[3]
    dy = d[4]
    dz = d[5]
    adx = a[3] - dx
    ady = a[4] - dy
    adz = a[5] - dz
    bdx = b[3] - dx
    bdy = b[4] - dy
    bdz = b[5] - dz
    cdx = c[3] - dx
    cdy = c[4] - dy
    cdz = c[5] - dz
    det = (
        adz * (cdx * bdy - bdx * cdy)
        + bdz * (adx * cdy - cdx * ady)
        + cdz * (bdx * ady - adx * bdy)
    )
    t = (
        abs(adx) + abs(ady) + abs(adz) + abs(bdx) + abs(bdy) + abs(bdz)
        + abs(cdx) + abs(cdy) + abs(cdz) + ORIENT3D_K
    )  # fmt: skip
    bound = t * t * (abs(dx) + abs(dy) + abs(dz) + t) * ORIENT3D_C
    if det > bound or -det > bound:
        _O3D[0] += 1
        return _CCW if det > 0.0 else _CW
    _O3D[1] += 1
    return orient3d_exact(a, b, c, d)


def insphere(a: Point3, b: Point3, c: Point3, d: Point3, e: Point3) -> SphereLocation:
    """Where ``e`` lies with respect to the sphere through a, b, c, d.

    INSIDE (positive) when e is strictly inside and ``orient3d(a, b, c, d)`` is
    COUNTERCLOCKWISE; COSPHERICAL when the five points are on one sphere (or plane); the
    answer flips when the tetrahedron abcd is negatively oriented.  Opposite sign to
    Shewchuk's insphere.  Exact; float filter first.
    """
    ex = e[3]
    ey = e[4]
    ez = e[5]
    aex = a[3] - ex
    aey = a[4] - ey
    aez = a[5] - ez
    bex = b[3] - ex
    bey = b[4] - ey
    bez = b[5] - ez
    cex = c[3] - ex
    cey = c[4] - ey
    cez = c[5] - ez
    dex = d[3] - ex
    dey = d[4] - ey
    dez = d[5] - ez
    ab = aex * bey - bex * aey
    bc = bex * cey - cex * bey
    cd = cex * dey - dex * cey
    da = dex * aey - aex * dey
    ac = aex * cey - cex * aey
    bd = bex * dey - dex * bey
    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da
    det = (
        (cex * cex + cey * cey + cez * cez) * dab - (dex * dex + dey * dey + dez * dez) * abc
    ) + ((aex * aex + aey * aey + aez * aez) * bcd - (bex * bex + bey * bey + bez * bez) * cda)
    t = (
        abs(aex) + abs(aey) + abs(aez) + abs(bex) + abs(bey) + abs(bez)
        + abs(cex) + abs(cey) + abs(cez) + abs(dex) + abs(dey) + abs(dez) + INSPHERE_K
    )  # fmt: skip
    t2 = t * t
    bound = t2 * t2 * (abs(ex) + abs(ey) + abs(ez) + t) * INSPHERE_C
    if det > bound or -det > bound:
        _ISP[0] += 1
        return _INSIDE if det > 0.0 else _OUTSIDE
    _ISP[1] += 1
    return insphere_exact(a, b, c, d, e)
