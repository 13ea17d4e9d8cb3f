"""A 2D mesh as numpy arrays, and the whole-mesh measures computed on them at once: the
boundary, the exact total, smallest and largest area, the smallest and largest angle, and
the (constrained) Delaunay check.

Every answer equals the one of the scalar definitions (:mod:`~geomexact.mesh2d.measures`,
:func:`~geomexact.mesh2d.delaunay.triangulation.non_delaunay_edges`): the floats only
*select*.  Predicates go through the certified numpy filters of
:mod:`~geomexact.kernel.array_filters` and only the queries they leave undecided are
computed exactly; exact areas are computed only for the triangles that can be the smallest
or the largest (a float area with a rigorous error bound); angles (floats, for reports) are
recomputed with :mod:`math` for the few corners that can hold the extreme, so they are the
same doubles as :func:`~geomexact.mesh2d.measures.triangle_angles_degrees`.  Exact work on
many equal shapes (a uniform refinement: every triangle one of a few shapes) is done once
per shape: for vertices whose doubles are their exact coordinates, the differences of
doubles split exactly into two doubles each (Knuth's TwoSum), a key that names the exact
difference.

:func:`mesh_arrays` returns None for a mesh whose tables are inconsistent (vertex ids not
``0..n-1``, a half-edge whose triangle is incomplete, ids too large to pack two in an
int64); the callers then use the scalar definitions.
"""

from __future__ import annotations

import itertools
import math
import operator
from typing import Any

import attrs
import numpy as np
import numpy.typing as npt

from geomexact.kernel.array_filters import incircle_signs
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import CircleLocation
from geomexact.kernel.predicates2d import incircle_exact
from geomexact.mesh2d.measures import signed_area, triangle_angles_degrees
from geomexact.mesh2d.snapshot import Edge, Mesh2, canonical_triangle

__all__ = ["MeshArrays", "mesh_arrays"]

IntArray = npt.NDArray[np.signedinteger[Any]]
FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

_U = 2.0**-53
_TINY = 2.0**-960
"""Absolute slack of the area bounds: covers underflow in the float products."""
_BAND = (2.0**-500, 2.0**500)
"""Arms whose largest component lies here are used as doubles by
:func:`~geomexact.mesh2d.measures.triangle_angles_degrees` (else it scales them)."""
_ANGLE_SLACK = 1e-9
"""Relative distance from the extreme float angle within which a corner is recomputed with
:mod:`math` (numpy's ``arctan2`` may differ from the C library's by a few units in the
last place)."""
_BLOCK = 1 << 16
"""Triangles per block in the area and angle passes (bounded temporaries)."""
_MAX_PACKED = 1 << 31
"""Vertex ids below this pack two to an int64 key."""


@attrs.frozen(slots=True, eq=False)
class MeshArrays:
    """A consistent mesh as arrays.  ``points[i]`` is vertex i; ``fx``, ``fy`` its doubles;
    ``exact[i]`` when they are its exact coordinates.  Half-edge j is ``(hu[j], hv[j])``
    with apex ``hw[j]``, reverse half-edge ``twin[j]`` (-1 on the boundary) and next
    half-edge ``following[j]`` = (hv[j], hw[j]) of the same triangle.
    ``triangles`` are the canonical triangles (rows a < b, a < c) in table order."""

    mesh: Mesh2
    points: list[Point2]
    fx: FloatArray
    fy: FloatArray
    exact: BoolArray
    hu: IntArray
    hv: IntArray
    hw: IntArray
    twin: IntArray
    following: IntArray
    triangles: IntArray

    # -- counts -------------------------------------------------------------------------
    @property
    def boundary_count(self) -> int:
        """Number of boundary half-edges (no triangle on their right)."""
        return int(np.count_nonzero(self.twin < 0))

    def boundary_keys(self) -> IntArray:
        """Indices of the boundary half-edges."""
        return np.flatnonzero(self.twin < 0)

    # -- areas --------------------------------------------------------------------------
    def total_area(self) -> Rational:
        """The exact sum of the signed triangle areas: half the sum of ``p_u x p_v`` over
        every half-edge (u, v), where the two half-edges of an interior edge cancel, so over
        the boundary half-edges only (exactly; the tables are consistent)."""
        points = self.points
        twice = ZERO
        for j in self.boundary_keys().tolist():
            p, q = points[self.hu[j]], points[self.hv[j]]
            twice += p.x * q.y - q.x * p.y
        return twice / 2

    def _blocks(self) -> list[slice]:
        """The triangles in blocks of :data:`_BLOCK` (bounded temporaries)."""
        count = len(self.triangles)
        return [slice(at, min(at + _BLOCK, count)) for at in range(0, count, _BLOCK)]

    def _area_intervals(self, block: slice) -> tuple[FloatArray, FloatArray, BoolArray]:
        """For the triangles of ``block``: intervals [low, high] (floats, possibly
        infinite or NaN: then unsure) holding twice their exact signed areas, and whether
        their vertices are exact doubles."""
        rows = self.triangles[block]
        a, b, c = rows[:, 0], rows[:, 1], rows[:, 2]
        fx, fy = self.fx, self.fy
        with np.errstate(over="ignore", invalid="ignore"):
            ux = fx[b] - fx[a]
            uy = fy[b] - fy[a]
            vx = fx[c] - fx[a]
            vy = fy[c] - fy[a]
            left = ux * vy
            right = uy * vx
            twice = left - right
            exact = self.exact[a] & self.exact[b] & self.exact[c]
            # exact doubles: each difference within 1 rounding, each product 1, the
            # difference 1 (relative), so 4u of |left| + |right| covers them
            bound = (np.abs(left) + np.abs(right)) * (8 * _U) + _TINY
            # inexact doubles: each coordinate within u|x| too; with m the largest
            # |coordinate|, each arm is within 4um of its exact value and at most 2m long
            size = np.maximum.reduce([np.abs(fx[a]), np.abs(fy[a]), np.abs(fx[b]),
                                      np.abs(fy[b]), np.abs(fx[c]), np.abs(fy[c])])
            loose = size * size * (128 * _U) + size * 2.0**-1000 + _TINY
            bound = np.where(exact, bound, loose)
            return twice - bound, twice + bound, exact

    def area_extremes(self) -> tuple[Rational, Rational] | None:
        """The exact smallest and largest signed triangle area (None without triangles):
        float intervals first (block by block), then exact areas for the triangles whose
        interval reaches the smallest upper or the largest lower end."""
        if not len(self.triangles):
            return None
        least_high, most_low = math.inf, -math.inf
        for block in self._blocks():
            low, high, _ = self._area_intervals(block)
            sure = np.isfinite(low) & np.isfinite(high)
            if sure.any():
                least_high = min(least_high, float(high[sure].min()))
                most_low = max(most_low, float(low[sure].max()))
        smallest: Rational | None = None
        largest: Rational | None = None
        for block in self._blocks():
            low, high, exact = self._area_intervals(block)
            with np.errstate(invalid="ignore"):
                unsure = ~(np.isfinite(low) & np.isfinite(high))
                small = unsure | (low <= least_high)
                large = unsure | (high >= most_low)
            chosen = np.flatnonzero(small | large)
            if not len(chosen):
                continue
            values, which = self._exact_twice_areas(chosen + block.start, exact[chosen])
            for i in np.unique(which[small[chosen]]).tolist():
                if smallest is None or values[i] < smallest:
                    smallest = values[i]
            for i in np.unique(which[large[chosen]]).tolist():
                if largest is None or values[i] > largest:
                    largest = values[i]
        assert smallest is not None and largest is not None
        return smallest / 2, largest / 2

    def _exact_twice_areas(self, chosen: IntArray, exact: BoolArray
                           ) -> tuple[list[Rational], IntArray]:
        """Twice the exact signed areas of the triangles ``chosen``: distinct values and,
        for each triangle, the index of its value (all-exact-double triangles computed once
        per distinct shape)."""
        which = np.zeros(len(chosen), dtype=np.int64)
        rows = self.triangles[chosen]
        points = self.points
        values: list[Rational] = []
        picked = np.flatnonzero(exact)
        if len(picked):
            a, b, c = rows[picked, 0], rows[picked, 1], rows[picked, 2]
            arms = _split_differences(self.fx, self.fy, [(b, a), (c, a)])
            shapes, inverse = _distinct_rows(arms)
            values = [_twice_area_of_arms(row) for row in shapes.tolist()]
            which[picked] = inverse
        for i in np.flatnonzero(~exact).tolist():
            a, b, c = rows[i].tolist()
            which[i] = len(values)
            values.append(2 * signed_area(points[a], points[b], points[c]))
        return values, which

    # -- angles -------------------------------------------------------------------------
    def _corner_intervals(self, block: slice) -> tuple[FloatArray, FloatArray, FloatArray,
                                                        FloatArray, BoolArray]:
        """For the corners of the triangles of ``block`` (at the first, second, third
        vertex, concatenated): |cross| and dot of the arms in doubles, and an interval
        [low, high] holding the angle :func:`~geomexact.mesh2d.measures.
        triangle_angles_degrees` gives (infinite or NaN: unsure); ``usable`` where that
        function's arms are these doubles (exact-double vertices, arms of ordinary size),
        so that ``degrees(atan2(cross, dot))`` with :mod:`math` is its value.

        Elsewhere each arm is within ``4u(m + |arm|)`` of its exact value (m: the largest
        coordinate), and so is the arm that function rounds, which bounds the angle's
        error (generously)."""
        tri = self.triangles[block]
        fx, fy = self.fx, self.fy
        exact = self.exact[tri[:, 0]] & self.exact[tri[:, 1]] & self.exact[tri[:, 2]]
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            size = np.maximum.reduce([np.abs(fx[tri[:, k]]) for k in range(3)]
                                     + [np.abs(fy[tri[:, k]]) for k in range(3)])
            crosses = []
            dots = []
            errors = []
            for p, q, r in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
                ip, iq, ir = tri[:, p], tri[:, q], tri[:, r]
                ux = fx[iq] - fx[ip]
                uy = fy[iq] - fy[ip]
                vx = fx[ir] - fx[ip]
                vy = fy[ir] - fy[ip]
                shortest = np.full(len(tri), np.inf)
                for x, y in ((ux, uy), (vx, vy)):
                    length = np.maximum(np.abs(x), np.abs(y))
                    exact &= (length >= _BAND[0]) & (length <= _BAND[1])
                    shortest = np.minimum(shortest, length)
                crosses.append(np.abs(ux * vy - uy * vx))
                dots.append(ux * vx + uy * vy)
                # radians: each arm's direction moves by about its relative error at most
                # (inf-norm lengths: a factor 2), for the doubles here and for the arms
                # triangle_angles_degrees rounds; a generous factor; 0 length -> inf
                relative = 64 * _U * (size / shortest + 1)
                ordinary = (shortest >= 2.0**-450) & (size <= 2.0**450)
                errors.append(np.where(ordinary, np.degrees(relative), np.inf))
            cross = np.concatenate(crosses)
            dot = np.concatenate(dots)
            angle = np.degrees(np.arctan2(cross, dot))
            usable = np.concatenate([exact, exact, exact])
            error = np.where(usable, angle * _ANGLE_SLACK + 1e-300, np.concatenate(errors))
            return cross, dot, angle - error, angle + error, usable

    def angle_extremes(self) -> tuple[float, float] | None:
        """The smallest and largest triangle angle in degrees, the same doubles as the
        minimum and maximum of :func:`~geomexact.mesh2d.measures.triangle_angles_degrees`
        over the triangles (None without triangles): float intervals first (block by
        block, :meth:`_corner_intervals`), then the corners whose interval reaches the
        smallest upper or the largest lower end computed as that function does."""
        if not len(self.triangles):
            return None
        least_high, most_low = math.inf, -math.inf
        for block in self._blocks():
            _, _, low, high, _ = self._corner_intervals(block)
            sure = np.isfinite(low) & np.isfinite(high)
            if sure.any():
                least_high = min(least_high, float(high[sure].min()))
                most_low = max(most_low, float(low[sure].max()))
        values: list[float] = []
        points = self.points
        for block in self._blocks():
            cross, dot, low, high, usable = self._corner_intervals(block)
            with np.errstate(invalid="ignore"):
                near = (~(np.isfinite(low) & np.isfinite(high)) | (low <= least_high)
                        | (high >= most_low))
            chosen = near & usable
            if chosen.any():
                pairs, _ = _distinct_rows(np.stack([cross[chosen], dot[chosen]], axis=1)
                                          + 0.0)
                values += [math.degrees(math.atan2(y, x)) for y, x in pairs.tolist()]
            others = np.flatnonzero((near & ~usable).reshape(3, -1).any(axis=0))
            for a, b, c in self.triangles[block][others].tolist():
                values.extend(triangle_angles_degrees(points[a], points[b], points[c]))
            if len(values) > 2:
                values = [min(values), max(values)]
        return min(values), max(values)

    # -- Delaunay -----------------------------------------------------------------------
    def non_delaunay_edges(self) -> list[Edge]:
        """Sorted (u, v), u < v, of the unconstrained interior edges that are not locally
        Delaunay, edges between triangles of different attributes exempt: the same list as
        :func:`~geomexact.mesh2d.delaunay.triangulation.non_delaunay_edges`."""
        mesh = self.mesh
        interior = (self.twin >= 0) & (self.hu < self.hv)
        if len(mesh.segments):
            size = len(self.points)
            keys = self.hu.astype(np.int64) * size + self.hv
            constrained = np.fromiter(  # a segment of missing vertices is no edge
                (u * size + v for u, v in mesh.segments if 0 <= u < size and 0 <= v < size),
                dtype=np.int64)
            interior &= ~np.isin(keys, constrained)
        edges = np.flatnonzero(interior)
        u, v, w = self.hu[edges], self.hv[edges], self.hw[edges]
        x = self.hw[self.twin[edges]]
        signs = incircle_signs(self.fx, self.fy, u, v, w, x)
        inside = signs > 0
        undecided = np.flatnonzero(signs == 0)
        if len(undecided):
            inside[undecided] = self._exact_incircles(
                u[undecided], v[undecided], w[undecided], x[undecided])
        found = np.flatnonzero(inside)
        pairs = list(zip(u[found].tolist(), v[found].tolist(), w[found].tolist(),
                         x[found].tolist(), strict=True))
        attributes = mesh.triangle_attributes
        if len(attributes):
            pairs = [(a, b, c, d) for a, b, c, d in pairs
                     if attributes.get(canonical_triangle(a, b, c))
                     == attributes.get(canonical_triangle(b, a, d))]
        return sorted((a, b) for a, b, _, _ in pairs)

    def _exact_incircles(self, a: IntArray, b: IntArray, c: IntArray, d: IntArray
                         ) -> BoolArray:
        """Whether d is strictly inside the circle through a, b, c, exactly, for each row
        (each distinct configuration of exact-double points once: incircle depends only on
        the differences to d)."""
        inside = np.zeros(len(a), dtype=np.bool_)
        exact = self.exact[a] & self.exact[b] & self.exact[c] & self.exact[d]
        points = self.points
        for i in np.flatnonzero(~exact).tolist():
            location = incircle_exact(points[a[i]], points[b[i]], points[c[i]],
                                      points[d[i]])
            inside[i] = location == CircleLocation.INSIDE
        picked = np.flatnonzero(exact)
        if len(picked):
            differences = _split_differences(
                self.fx, self.fy, [(a[picked], d[picked]), (b[picked], d[picked]),
                                   (c[picked], d[picked])])
            shapes, inverse = _distinct_rows(differences)
            origin = Point2(ZERO, ZERO, 0.0, 0.0)
            verdicts = []
            for row in shapes.tolist():
                ax, ay, bx, by, cx, cy = _exact_values(row)
                location = incircle_exact(_point(ax, ay), _point(bx, by), _point(cx, cy),
                                          origin)
                verdicts.append(location == CircleLocation.INSIDE)
            inside[picked] = np.asarray(verdicts, dtype=np.bool_)[inverse]
        return inside


def _point(x: Rational, y: Rational) -> Point2:
    """A point for the exact predicates (whose doubles they do not read)."""
    return Point2(x, y, math.nan, math.nan)


def _two_difference(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``a - b`` as ``hi + lo`` exactly (Knuth's TwoSum; finite doubles, no overflow):
    ``hi`` is the rounded difference, ``lo`` its error, a pair unique to the exact value."""
    hi = a - b
    virtual = hi - a
    lo = (a - (hi - virtual)) + (-b - virtual)
    return hi, lo


def _split_differences(fx: FloatArray, fy: FloatArray,
                       pairs: list[tuple[IntArray, IntArray]]) -> FloatArray:
    """Rows of (hi, lo) of x then y of each difference ``p[first] - p[second]``."""
    columns: list[FloatArray] = []
    for first, second in pairs:
        for coordinate in (fx, fy):
            columns.extend(_two_difference(coordinate[first], coordinate[second]))
    # -0.0 and 0.0 are one value: make them one key
    return np.stack(columns, axis=1) + 0.0


def _distinct_rows(rows: FloatArray) -> tuple[FloatArray, IntArray]:
    """The distinct rows and, for each row, the index of its distinct row.  Rows are
    grouped by a 64-bit hash of their bits (one sort of integers), then checked equal to
    their group's first row; on a hash collision the rows are sorted themselves."""
    bits = np.ascontiguousarray(rows).view(np.uint64)
    mixed = np.zeros(len(rows), dtype=np.uint64)
    with np.errstate(over="ignore"):
        for column in range(bits.shape[1]):
            mixed = (mixed ^ bits[:, column]) * np.uint64(0x9E3779B97F4A7C15)
            mixed ^= mixed >> np.uint64(29)
    _, first, inverse = np.unique(mixed, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    shapes = rows[first]
    if np.array_equal(bits, bits[first][inverse]):
        return shapes, inverse
    shapes, inverse = np.unique(rows, axis=0, return_inverse=True)
    return shapes, inverse.reshape(-1)


def _exact_values(row: list[float]) -> list[Rational]:
    """The exact values ``hi + lo`` of a row of (hi, lo) pairs."""
    return [mpq(hi) + mpq(lo) for hi, lo in zip(row[0::2], row[1::2], strict=True)]


def _twice_area_of_arms(row: list[float]) -> Rational:
    """``ux * vy - uy * vx`` exactly, from the (hi, lo) pairs of ux, uy, vx, vy."""
    ux, uy, vx, vy = _exact_values(row)
    return ux * vy - uy * vx


def mesh_arrays(mesh: Mesh2) -> MeshArrays | None:
    """The arrays of ``mesh``, or None when its tables are inconsistent (the scalar
    definitions then apply).  O(n log n) in numpy, O(n) in Python (reading the tables)."""
    source = mesh.source
    n = mesh.vertex_count
    if n >= _MAX_PACKED:
        return None
    try:
        points = mesh.point_list()
    except KeyError:
        return None
    fx = np.fromiter(map(operator.itemgetter(2), points), dtype=np.float64, count=n)
    fy = np.fromiter(map(operator.itemgetter(3), points), dtype=np.float64, count=n)
    exact = np.fromiter((p[0] == p[2] and p[1] == p[3] for p in points), dtype=np.bool_,
                        count=n)
    if source is not None:
        count = len(source.halfedges)
        hu, hv, hw = (column.astype(np.int32) for column in source.halfedges.T)
    else:
        halfedges = mesh.halfedges
        count = len(halfedges)
        try:  # ids are int32 (vertex ids below 2^31 here); a wrong id does not fit
            keys = np.fromiter(itertools.chain.from_iterable(halfedges.keys()),
                               dtype=np.int32, count=2 * count)
            hw = np.fromiter(halfedges.values(), dtype=np.int32, count=count)
        except (OverflowError, TypeError):
            return None
        hu, hv = keys[0::2].copy(), keys[1::2].copy()
        del keys
    if count and (min(int(hu.min()), int(hv.min()), int(hw.min())) < 0
                  or max(int(hu.max()), int(hv.max()), int(hw.max())) >= n):
        return None
    packed = hu.astype(np.int64) * n + hv
    order = np.argsort(packed)
    ordered = packed[order]
    del packed

    def find(first: IntArray, second: IntArray) -> IntArray:
        wanted = first.astype(np.int64) * n + second
        queries = np.argsort(wanted)  # sorted queries search the table in cache order
        at = np.empty_like(queries)
        at[queries] = np.searchsorted(ordered, wanted[queries])
        del queries
        np.minimum(at, max(count - 1, 0), out=at)
        found = ordered[at] == wanted if count else np.zeros(0, dtype=np.bool_)
        return np.where(found, order[at], -1).astype(np.int32)

    following = find(hv, hw)
    if np.any(following < 0) or np.any(hw[np.maximum(following, 0)] != hu):
        return None  # a half-edge whose triangle is not complete
    twin = find(hv, hu)
    first = (hu < hv) & (hu < hw)
    triangles = np.stack([hu[first], hv[first], hw[first]], axis=1)
    if len(triangles) != mesh.triangle_count:
        return None
    return MeshArrays(mesh, points, fx, fy, exact, hu, hv, hw, twin, following, triangles)
