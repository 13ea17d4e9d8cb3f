"""Exact geometric queries of a :class:`~geomexact.mesh3d.surface.value.TriangleSurface`
for the octree's domain fit: which triangles a box may meet (a bucket grid of their
bounding boxes, rounded outward so no candidate is missed), where a segment meets the
surface, and on which side of a closed surface a point lies.

Everything decided is exact: candidates are filtered by the exact bounding boxes, every
orientation is :func:`~geomexact.kernel.predicates3d.orient3d` (float filter, exact
fallback), every intersection point is a rational point exactly on a triangle.  A point's
side is the parity of the proper crossings of a segment from it to beyond the surface;
a segment that touches a triangle's edge or vertex, or runs in its plane, is not used:
the next of a fixed list of directions is (no epsilon, no perturbation)."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any, Final

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.kernel.points import Point3, nearest_double, point3
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.snapshot import signed_volume6
from geomexact.mesh3d.surface.value import TriangleSurface

__all__ = ["INSIDE", "ON", "OUTSIDE", "SegmentHit", "SurfaceIndex", "surface_index"]

INSIDE: Final = 1
ON: Final = 0
OUTSIDE: Final = -1

_DIRECTIONS: Final = ((1, mpq(1, 997), mpq(1, 1009)), (mpq(1, 983), 1, mpq(1, 991)),
                      (mpq(1, 977), mpq(1, 971), 1), (1, mpq(3, 967), mpq(-5, 953)),
                      (mpq(-7, 947), 1, mpq(11, 941)), (mpq(13, 937), mpq(-17, 929), 1))
"""Ray directions tried in turn: far from any axis or diagonal, so a ray through a
lattice point rarely meets a triangle's edge."""


@attrs.frozen(slots=True)
class SegmentHit:
    """Where a segment ``p + t (q - p)`` meets triangle ``triangle``: at ``t`` (exact, 0 ≤
    t ≤ 1; the first point of the triangle along the segment), ``proper`` when it crosses
    the triangle's interior transversally."""

    t: Rational
    triangle: int
    proper: bool


def _outward_down(values: Any) -> Any:
    return np.nextafter(values, -np.inf)


def _outward_up(values: Any) -> Any:
    return np.nextafter(values, np.inf)


@attrs.frozen(slots=True, eq=False)
class SurfaceIndex:
    """A surface with a bucket grid of its triangles' bounding boxes (doubles rounded
    outward, so a box query never misses a triangle; the exact boxes then decide)."""

    surface: TriangleSurface
    low: Any  # (n, 3) doubles, at most the exact lows
    high: Any  # (n, 3) doubles, at least the exact highs
    origin: Any  # (3,)
    step: Any  # (3,)
    shape: tuple[int, int, int]
    buckets: dict[tuple[int, int, int], list[int]]
    exact_low: tuple[tuple[Rational, Rational, Rational], ...]
    exact_high: tuple[tuple[Rational, Rational, Rational], ...]

    def _cells(self, low: Sequence[float], high: Sequence[float]) -> Iterable[tuple[int, ...]]:
        first = [max(0, min(self.shape[a] - 1, math.floor((low[a] - self.origin[a])
                                                           / self.step[a])))
                 for a in range(3)]
        last = [max(0, min(self.shape[a] - 1, math.floor((high[a] - self.origin[a])
                                                          / self.step[a])))
                for a in range(3)]
        for i in range(first[0], last[0] + 1):
            for j in range(first[1], last[1] + 1):
                for k in range(first[2], last[2] + 1):
                    yield (i, j, k)

    def near(self, low: Sequence[Rational], high: Sequence[Rational]) -> list[int]:
        """The triangles whose exact bounding box meets the closed box [low, high], sorted."""
        flow = [float(_outward_down(nearest_double(v))) for v in low]
        fhigh = [float(_outward_up(nearest_double(v))) for v in high]
        found: set[int] = set()
        for cell in self._cells(flow, fhigh):
            found.update(self.buckets.get(cell, ()))  # type: ignore[arg-type]
        return [t for t in sorted(found)
                if all(self.exact_low[t][a] <= high[a] and low[a] <= self.exact_high[t][a]
                       for a in range(3))]

    def meets_box(self, low: Sequence[Rational], high: Sequence[Rational]) -> bool:
        """True when some triangle's bounding box meets the closed box [low, high]."""
        return bool(self.near(low, high))

    def segment_hits(self, p: Point3, q: Point3) -> list[SegmentHit]:
        """Every triangle the closed segment pq meets, with the first parameter along it
        (sorted by t, then triangle)."""
        low = [min(p[a], q[a]) for a in range(3)]
        high = [max(p[a], q[a]) for a in range(3)]
        hits = []
        for index in self.near(low, high):
            hit = _segment_triangle(p, q, self.surface.triangle(index), index)
            if hit is not None:
                hits.append(hit)
        return sorted(hits, key=lambda hit: (hit.t, hit.triangle))

    def on_surface(self, p: Point3) -> bool:
        """True when ``p`` lies exactly on a triangle."""
        for index in self.near(p[:3], p[:3]):
            a, b, c = self.surface.triangle(index)
            if orient3d(a, b, c, p) == 0 and _in_triangle(p, a, b, c):
                return True
        return False

    def side(self, p: Point3) -> int:
        """:data:`INSIDE`, :data:`ON` or :data:`OUTSIDE` of the closed surface, exactly:
        the parity of proper crossings of a segment from ``p`` to beyond the surface."""
        if self.on_surface(p):
            return ON
        low, high = self.surface.bounds()
        for direction in _DIRECTIONS:
            # the far end: beyond the bounding box along the direction's main axis
            axis = max(range(3), key=lambda a: abs(direction[a]))
            beyond = (high[axis] + 1 - p[axis] if direction[axis] > 0
                      else p[axis] - low[axis] + 1)
            scale = beyond / abs(direction[axis])
            far = point3(*(p[a] + direction[a] * scale for a in range(3)))
            hits = self.segment_hits(p, far)
            if all(hit.proper for hit in hits):
                return INSIDE if len(hits) % 2 else OUTSIDE
        raise PreconditionError("side", f"every ray from {p} touches an edge of the surface "
                                f"{self.surface.name!r}")


def _in_triangle(p: Point3, a: Point3, b: Point3, c: Point3) -> bool:
    """For ``p`` in the plane of triangle abc: whether it is in the closed triangle."""
    axis = _drop_axis(a, b, c)
    keep = [i for i in range(3) if i != axis]

    def cross(u: Point3, v: Point3) -> int:
        value = ((v[keep[0]] - u[keep[0]]) * (p[keep[1]] - u[keep[1]])
                 - (v[keep[1]] - u[keep[1]]) * (p[keep[0]] - u[keep[0]]))
        return (value > 0) - (value < 0)

    signs = {cross(a, b), cross(b, c), cross(c, a)} - {0}
    return len(signs) <= 1


def _drop_axis(a: Point3, b: Point3, c: Point3) -> int:
    """The axis along which triangle abc's normal is largest (projecting along it keeps
    the triangle non-degenerate)."""
    u = [b[i] - a[i] for i in range(3)]
    v = [c[i] - a[i] for i in range(3)]
    normal = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    return max(range(3), key=lambda i: abs(normal[i]))


def _segment_triangle(p: Point3, q: Point3, triangle: tuple[Point3, Point3, Point3],
                      index: int) -> SegmentHit | None:
    a, b, c = triangle
    op, oq = orient3d(a, b, c, p), orient3d(a, b, c, q)
    if op != 0 and op == oq:
        return None
    if op == 0 and oq == 0:
        return _coplanar_hit(p, q, a, b, c, index)
    s1, s2, s3 = orient3d(p, q, a, b), orient3d(p, q, b, c), orient3d(p, q, c, a)
    signs = {s1, s2, s3}
    nonzero = signs - {0}
    if len(nonzero) > 1:
        return None  # the line passes beside the triangle
    if not nonzero:  # pragma: no cover - p, q and the triangle coplanar was handled
        return None
    vp, vq = signed_volume6(a, b, c, p), signed_volume6(a, b, c, q)
    t = vp / (vp - vq)
    proper = op != 0 and oq != 0 and 0 not in signs
    return SegmentHit(t, index, proper)


def _coplanar_hit(p: Point3, q: Point3, a: Point3, b: Point3, c: Point3,
                  index: int) -> SegmentHit | None:
    """The first point of the closed triangle abc on segment pq, both in one plane (exact
    clipping of the segment by the triangle's three sides in a projection)."""
    axis = _drop_axis(a, b, c)
    keep = [i for i in range(3) if i != axis]
    corners = [(x[keep[0]], x[keep[1]]) for x in (a, b, c)]
    start = (p[keep[0]], p[keep[1]])
    direction = (q[keep[0]] - start[0], q[keep[1]] - start[1])
    area = ((corners[1][0] - corners[0][0]) * (corners[2][1] - corners[0][1])
            - (corners[1][1] - corners[0][1]) * (corners[2][0] - corners[0][0]))
    orientation = 1 if area > 0 else -1
    lo, hi = ZERO, mpq(1)
    for i in range(3):
        u, v = corners[i], corners[(i + 1) % 3]
        # inside: orientation * cross(v - u, x - u) >= 0, linear in t
        edge = (v[0] - u[0], v[1] - u[1])
        at0 = orientation * (edge[0] * (start[1] - u[1]) - edge[1] * (start[0] - u[0]))
        slope = orientation * (edge[0] * direction[1] - edge[1] * direction[0])
        if slope == 0:
            if at0 < 0:
                return None
            continue
        bound = -at0 / slope
        if slope > 0:
            lo = max(lo, bound)
        else:
            hi = min(hi, bound)
        if lo > hi:
            return None
    return SegmentHit(lo, index, False)


def surface_index(surface: TriangleSurface) -> SurfaceIndex:
    """The bucket grid of ``surface`` (about four triangles a bucket)."""
    count = surface.triangle_count
    if count == 0:
        raise PreconditionError("surface_index", f"the surface {surface.name!r} has no "
                                "triangle")
    exact_low = []
    exact_high = []
    for t in range(count):
        a, b, c = surface.triangle(t)
        exact_low.append(tuple(min(a[i], b[i], c[i]) for i in range(3)))
        exact_high.append(tuple(max(a[i], b[i], c[i]) for i in range(3)))
    low = _outward_down(np.array([[nearest_double(v) for v in row] for row in exact_low]))
    high = _outward_up(np.array([[nearest_double(v) for v in row] for row in exact_high]))
    origin = low.min(axis=0)
    extent = np.maximum(high.max(axis=0) - origin, 1e-300)
    per_axis = max(1, round((count / 4) ** (1 / 3)))
    shape = (per_axis, per_axis, per_axis)
    step = extent / per_axis
    buckets: dict[tuple[int, int, int], list[int]] = {}
    first = np.clip(np.floor((low - origin) / step).astype(np.int64), 0, per_axis - 1)
    last = np.clip(np.floor((high - origin) / step).astype(np.int64), 0, per_axis - 1)
    for t, (f, g) in enumerate(zip(first.tolist(), last.tolist(), strict=True)):
        for i in range(f[0], g[0] + 1):
            for j in range(f[1], g[1] + 1):
                for k in range(f[2], g[2] + 1):
                    buckets.setdefault((i, j, k), []).append(t)
    return SurfaceIndex(surface, low, high, origin, step, shape, buckets,
                        tuple(exact_low), tuple(exact_high))  # type: ignore[arg-type]
