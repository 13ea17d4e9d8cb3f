"""The default engine: the steps of the ops on plain tables, the digest kept incrementally,
the Lepp search and the queueing inlined; exact float paths on the dyadic grid."""

from __future__ import annotations

from typing import Any

import immutables

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.dyadic_grid import grid_flags, midpoint_on_grid
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import CircleLocation, Comparison, Orientation
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.mesh2d.ops import (
    quadrilateral_area_centroid,
    quadrilateral_vertex_centroid,
)
from geomexact.mesh2d.refinement.centroids import rounded_area_centroid
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.refinement.driver import (
    CriterionMet,
    Progress,
    Refinement,
    Status,
    StepLimit,
)
from geomexact.mesh2d.snapshot import (
    MAX_VERTICES,
    Attributes,
    Edge,
    Mesh2,
    Triangle,
    canonical_triangle,
)
from geomexact.trace.step import Step

_CCW = Orientation.COUNTERCLOCKWISE
_LESS = Comparison.LESS
_INSIDE = CircleLocation.INSIDE
_MASK = _digest.MODULUS - 1


def compare_squared_lengths_on_grid(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
    """:func:`~geomexact.kernel.predicates.compare_squared_lengths` (as -1, 0, 1) for points on
    the dyadic grid (:mod:`geomexact.kernel.dyadic_grid`), where it is exact in floats."""
    ux, uy, vx, vy = b[2] - a[2], b[3] - a[3], d[2] - c[2], d[3] - c[3]
    first, second = ux * ux + uy * uy, vx * vx + vy * vy
    return (first > second) - (first < second)


def _exact_point(x: Rational, y: Rational) -> Point2:
    """:func:`point2` for rationals, without its conversions."""
    try:
        return Point2(x, y, float(x), float(y))
    except OverflowError:
        return point2(x, y)


class FastRefinement(Refinement):
    """The same steps as the ops on a plain half-edge dict; the digest is kept
    incrementally (with a cache of the hashes of the triangles made in the run) and every
    step is recorded with the digest after it.  Its trace is checked against the transient
    engine's, and by replay, in the tests."""

    def __init__(self, mesh: Mesh2, max_steps: int | None, **options: Any) -> None:
        super().__init__(mesh, **options)
        count = mesh.vertex_count
        self.points = points = [mesh.vertices[i] for i in range(count)]
        # vertices: the snapshot's own map, opened for edits (sealing is O(1)); half-edges:
        # a dict, copied into a map once at the end (a dict update costs a tenth of a map
        # mutation, and there are about seven per half-edge made)
        self.vertex_table = mesh.vertices.mutate()
        self.apex = apex = dict(mesh.halfedges.items())
        self.scale, self.grid = grid_flags(points)
        self.hints: list[int | None] = [mesh.outgoing.get(i) for i in range(count)]
        self.segments = dict(mesh.segments.items())
        self.triangle_attrs: dict[Triangle, Attributes] = dict(
            mesh.triangle_attributes.items()
        )
        self.attributed = bool(self.triangle_attrs)
        self.new_markers: dict[int, int] = {}
        self.hashes: dict[Triangle, int] = {}
        self.digest = mesh.digest
        self.steps: list[Step] = []
        self.digests: list[int] = []
        self.limit = max_steps
        self.get = apex.get
        self.point = points.__getitem__

    # -- store --------------------------------------------------------------------------
    def is_segment(self, u: int, v: int) -> bool:
        return ((u, v) if u < v else (v, u)) in self.segments

    def attributes(self, triangle: Triangle) -> Attributes | None:
        return self.triangle_attrs.get(canonical_triangle(*triangle))

    def _begin(self) -> None:
        if self.limit is not None and len(self.steps) >= self.limit:
            raise StepLimit

    def _record(self, op: str, args: tuple[int | Rational, ...]) -> None:
        step = Step(op, args)
        self.steps.append(step)
        self.digests.append(self.digest)
        if self.on_step is not None:
            self.on_step(
                Progress(
                    len(self.steps), step, len(self.apex) // 3, len(self.points),
                    self.queue.size,
                )
            )

    def _add(self, a: int, b: int, c: int, attributes: Attributes | None) -> None:
        apex = self.apex
        apex[(a, b)] = c
        apex[(b, c)] = a
        apex[(c, a)] = b
        hints = self.hints
        hints[a] = b
        hints[b] = c
        hints[c] = a
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        value = self.hashes[key] = _digest.cell_hash(key)
        total = self.digest + value
        if attributes:
            self.triangle_attrs[key] = attributes
            total += _digest.attribute_hash("ta", key, attributes)
        self.digest = total & _MASK
        self.created.append(key)

    def _remove(self, a: int, b: int, c: int) -> Attributes | None:
        apex = self.apex
        del apex[(a, b)]
        del apex[(b, c)]
        del apex[(c, a)]
        key = (a, b, c) if a < b and a < c else (b, c, a) if b < c else (c, a, b)
        value = self.hashes.pop(key, None)
        if value is None:
            value = _digest.cell_hash(key)
        total = self.digest - value
        attributes = None
        if self.attributed:
            attributes = self.triangle_attrs.pop(key, None)
            if attributes is not None:
                total -= _digest.attribute_hash("ta", key, attributes)
        self.digest = total & _MASK
        self.removed.append(key)
        return attributes

    def _add_vertex(self, point: Point2, marker: int) -> int:
        vertex = len(self.points)
        if vertex >= MAX_VERTICES:
            raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
        self.points.append(point)
        self.vertex_table[vertex] = point
        self.hints.append(None)
        self.grid.append(False)
        total = self.digest + _digest.vertex_hash(vertex, (point[0], point[1]))
        if marker:
            self.new_markers[vertex] = marker
            total += _digest.attribute_hash("vm", (vertex,), (marker,))
        self.digest = total & _MASK
        return vertex

    # -- steps --------------------------------------------------------------------------
    def bisect(self, u: int, v: int) -> int:
        """:func:`geomexact.mesh2d.ops.bisect_in`; the common case (no attributes) inlined."""
        steps = self.steps
        if self.limit is not None and len(steps) >= self.limit:
            raise StepLimit
        apex, points = self.apex, self.points
        w, x = apex.get((u, v)), apex.get((v, u))
        pu, pv = points[u], points[v]
        key = (u, v) if u < v else (v, u)
        marker = self.segments.get(key)
        # the new vertex (as _add_vertex, inlined)
        n = len(points)
        keys = _digest.VERTEX_KEYS
        if n >= MAX_VERTICES:
            raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
        mx, my = (pu[0] + pv[0]) / 2, (pu[1] + pv[1]) / 2
        point = _exact_point(mx, my)
        points.append(point)
        self.vertex_table[n] = point
        self.hints.append(None)
        grid, scale = self.grid, self.scale
        grid.append(
            scale is not None and grid[u] and grid[v] and midpoint_on_grid(pu, pv, scale)
        )
        if n >= len(keys):
            _digest.vertex_key(n + 1023)  # extend the cached vertex keys a block at a time
        total = self.digest + _digest.vertex_hash(n, (mx, my))
        if marker:
            self.new_markers[n] = marker
            total += _digest.attribute_hash("vm", (n,), (marker,))
        self.digest = total & _MASK
        if self.attributed:
            if w is not None:
                attributes = self._remove(u, v, w)
                self._add(u, n, w, attributes)
                self._add(n, v, w, attributes)
            if x is not None:
                attributes = self._remove(v, u, x)
                self._add(v, n, x, attributes)
                self._add(n, u, x, attributes)
        else:
            hashes, hints, created, removed = self.hashes, self.hints, self.created, self.removed
            cell_hash = _digest.cell_hash
            # digest.cell_hash, inlined for the two new triangles
            m0, m1, m2 = _digest.TRIANGLE_MULTIPLIERS
            final = _digest.FINAL_MULTIPLIER
            kn = keys[n]
            for p, q, r in ((u, v, w), (v, u, x)):
                if r is None:
                    continue
                # (p, q, r) -> (p, n, r), (n, q, r); n is the largest id.  The half-edges
                # (q, r) and (r, p) stay, with new apexes.
                del apex[(p, q)]
                old = (p, q, r) if p < q and p < r else (q, r, p) if q < r else (r, p, q)
                value = hashes.pop(old, None)
                total -= cell_hash(old) if value is None else value
                apex[(p, n)] = r
                apex[(n, r)] = p
                apex[(r, p)] = n
                apex[(n, q)] = r
                apex[(q, r)] = n
                apex[(r, n)] = q
                hints[p] = n
                hints[n] = q
                hints[q] = r
                hints[r] = n
                kp, kq, kr = keys[p], keys[q], keys[r]
                if p < r:
                    first = (p, n, r)
                    h = (kp * m0 + kn * m1 + kr * m2) & _MASK
                else:
                    first = (r, p, n)
                    h = (kr * m0 + kp * m1 + kn * m2) & _MASK
                h ^= h >> 61
                value = hashes[first] = (h * final) & _MASK
                total += value
                if q < r:
                    second = (q, r, n)
                    h = (kq * m0 + kr * m1 + kn * m2) & _MASK
                else:
                    second = (r, n, q)
                    h = (kr * m0 + kn * m1 + kq * m2) & _MASK
                h ^= h >> 61
                value = hashes[second] = (h * final) & _MASK
                total += value
                removed.append(old)
                created.append(first)
                created.append(second)
            self.digest = total & _MASK
        if marker is not None:
            segments = self.segments
            del segments[key]
            segments[(u, n) if u < n else (n, u)] = marker
            segments[(n, v) if n < v else (v, n)] = marker
            self.digest = (
                self.digest
                - _digest.segment_hash(key[0], key[1], marker)
                + _digest.segment_hash(min(u, n), max(u, n), marker)
                + _digest.segment_hash(min(n, v), max(n, v), marker)
            ) & _MASK
        step = Step("bisect", (u, v))
        steps.append(step)
        self.digests.append(self.digest)
        if self.on_step is not None:
            self.on_step(Progress(len(steps), step, len(apex) // 3, n + 1, self.queue.size))
        return n

    def flip(self, u: int, v: int) -> None:
        """:func:`geomexact.mesh2d.ops.flip_in`."""
        if self.limit is not None and len(self.steps) >= self.limit:
            raise StepLimit
        apex = self.apex
        w, x = apex[(u, v)], apex[(v, u)]
        attributes = self._remove(u, v, w)
        self._remove(v, u, x)
        self._add(x, w, u, attributes)
        self._add(w, x, v, attributes)
        self._record("flip", (u, v))

    def centroid(self, u: int, v: int) -> int:
        """:func:`geomexact.mesh2d.ops.insert_centroid_in` or
        :func:`geomexact.mesh2d.refinement.centroids.insert_in_quadrilateral_in`."""
        self._begin()
        apex, points = self.apex, self.points
        w, x = apex[(u, v)], apex[(v, u)]
        pu, pv, pw, px = points[u], points[v], points[w], points[x]
        args: tuple[int | Rational, ...] = (u, v)
        if self.centroid_kind == "area":
            point = rounded_area_centroid(pu, pv, pw, px)
            op, args = "insert_in_quadrilateral", (u, v, point.x, point.y)
        elif self.centroid_kind == "area-exact":
            point, op = quadrilateral_area_centroid(pu, pv, pw, px), "insert_centroid"
        else:
            point, op = quadrilateral_vertex_centroid(pu, pv, pw, px), "insert_vertex_centroid"
        for p, q in ((pu, px), (px, pv), (pv, pw), (pw, pu)):
            if orient2d(p, q, point) != _CCW:  # pragma: no cover - terminal pairs are convex
                raise PreconditionError(op, f"centroid of ({u}, {v}) outside its quadrilateral")
        n = self._add_vertex(point, 0)
        attributes = self._remove(u, v, w)
        self._remove(v, u, x)
        self._add(u, x, n, attributes)
        self._add(x, v, n, attributes)
        self._add(v, w, n, attributes)
        self._add(w, u, n, attributes)
        self._record(op, args)
        return n

    def legalize(self, vertex: int, star: list[Edge] | None = None) -> None:
        """:func:`geomexact.mesh2d.ops.legalize_in`, flip for flip; ``star`` is the star of
        ``vertex`` as :meth:`_star` gives it, when the caller knows it."""
        apex, points = self.apex, self.points
        get = apex.get
        if star is None:
            star = self._star(vertex)
        start = 0
        smallest = star[0][0]
        for index in range(1, len(star)):
            if star[index][0] < smallest:
                start, smallest = index, star[index][0]
        pending = star[start:] + star[:start]
        pending.reverse()
        p = points[vertex]
        px, py = p[0], p[1]
        segments = self.segments
        attributed = self.attributed
        grid = self.grid
        on_grid = grid[vertex]
        while pending:
            a, b = pending.pop()
            if get((vertex, a)) != b:
                continue
            q = get((b, a))
            if q is None or ((a, b) if a < b else (b, a)) in segments:
                continue
            pa, pb, pq = points[a], points[b], points[q]
            # q is strictly inside the circle through p, a, b exactly when the angles at p
            # and q facing {a, b} sum to more than 180°.  Two right or acute angles (exact
            # dot products >= 0) settle it without incircle, whose filter cannot decide the
            # cocircular case (common: squares) and falls back to slower exact arithmetic.
            # On the dyadic grid the dot products are exact in floats.
            if on_grid and grid[a] and grid[b] and grid[q]:
                ax, ay, bx, by, qx, qy = pa[2], pa[3], pb[2], pb[3], pq[2], pq[3]
                fx, fy = p[2], p[3]
                if (ax - fx) * (bx - fx) + (ay - fy) * (by - fy) >= 0 and (
                    (ax - qx) * (bx - qx) + (ay - qy) * (by - qy) >= 0
                ):
                    continue
            else:
                ax, ay, bx, by, qx, qy = pa[0], pa[1], pb[0], pb[1], pq[0], pq[1]
                if (ax - px) * (bx - px) + (ay - py) * (by - py) >= 0 and (
                    (ax - qx) * (bx - qx) + (ay - qy) * (by - qy) >= 0
                ):
                    continue
            if incircle(p, pa, pb, pq) != _INSIDE:
                continue
            if orient2d(pq, p, pa) != _CCW or orient2d(p, pq, pb) != _CCW:
                continue
            if attributed and self.different_attributes(a, b, vertex, q):
                continue
            self.flip(a, b)
            pending.append((q, b))
            pending.append((a, q))

    def _star(self, vertex: int) -> list[Edge]:
        """The edges (w, x) of the triangles (vertex, w, x) around ``vertex``, counter-
        clockwise, starting after the boundary gap for a boundary vertex (as
        :func:`geomexact.mesh2d.snapshot.walk_star`)."""
        get = self.apex.get
        start = self.hints[vertex]
        assert start is not None
        first = start
        while True:
            previous = get((first, vertex))
            if previous is None:
                break
            if previous == start:
                first = start
                break
            first = previous
        result: list[Edge] = []
        w = first
        while True:
            x = get((vertex, w))
            if x is None:
                break
            result.append((w, x))
            w = x
            if w == first:
                break
        return result

    # -- the loop, inlined --------------------------------------------------------------
    def run(self) -> Status:
        """:meth:`Refinement.run` with the Lepp search and the queueing inlined."""
        get = self.get
        points = self.points
        segments = self.segments
        queue = self.queue
        pop, push = queue.pop, queue.push
        created, removed = self.created, self.removed
        rate = self.criterion.rate
        max_area = (
            2 * self.criterion.area
            if type(self.criterion) is MaxArea and self.scale is not None
            else None
        )
        whole = self.whole
        threshold = self.threshold
        tracking = self.target_area2 is not None
        attributed = self.attributed
        bisection = self.method == "bisection"
        quasi_flips = self.method == "quasi" and self.delaunay
        legalize_insertions = self.legalize_insertions
        exact, on_grid = compare_squared_lengths, compare_squared_lengths_on_grid
        grid = self.grid
        less = _LESS
        try:
            if tracking and self.mean_reached():
                return "complete"
            while True:
                target = pop()
                if target is None:
                    break
                a, b, c = target
                if get((a, b)) != c:
                    continue
                self.targets += 1
                while True:
                    # -- Lepp: the longest edge (u, v) of (a, b, c), apex w ------------
                    pa, pb, pc = points[a], points[b], points[c]
                    compare = on_grid if grid[a] and grid[b] and grid[c] else exact
                    order = compare(pa, pb, pb, pc)
                    if order > 0 or (
                        order == 0 and (min(a, b), max(a, b)) < (min(b, c), max(b, c))
                    ):
                        order = compare(pa, pb, pc, pa)
                        if order > 0 or (
                            order == 0 and (min(a, b), max(a, b)) < (min(c, a), max(c, a))
                        ):
                            u, v, w, pu, pv = a, b, c, pa, pb
                        else:
                            u, v, w, pu, pv = c, a, b, pc, pa
                    else:
                        order = compare(pb, pc, pc, pa)
                        if order > 0 or (
                            order == 0 and (min(b, c), max(b, c)) < (min(c, a), max(c, a))
                        ):
                            u, v, w, pu, pv = b, c, a, pb, pc
                        else:
                            u, v, w, pu, pv = c, a, b, pc, pa
                    self.searches += 1
                    hops = 1
                    while True:
                        x = get((v, u))
                        if x is None or ((u, v) if u < v else (v, u)) in segments or (
                            attributed and self.different_attributes(u, v, w, x)
                        ):
                            constrained = True
                            break
                        px = points[x]
                        compare = on_grid if grid[u] and grid[v] and grid[x] else exact
                        if compare(pu, pv, pv, px) != less and compare(pu, pv, px, pu) != less:
                            constrained = False
                            break
                        hops += 1
                        order = compare(pu, px, px, pv)
                        if order > 0 or (
                            order == 0 and (min(u, x), max(u, x)) < (min(x, v), max(x, v))
                        ):
                            w, v, pv = v, x, px
                        else:
                            w, u, pu = u, x, px
                    self.hops += hops
                    # -- act -----------------------------------------------------------
                    if constrained and threshold is not None and self.protected(u, v):
                        self.left[target] = None  # its step would split a protected edge
                        created.clear()
                        removed.clear()
                        break
                    if bisection or constrained or x is None:
                        vertex = self.bisect(u, v)
                        if legalize_insertions:
                            # the star of the midpoint, counter-clockwise, starting after
                            # the boundary gap (as _star would find it)
                            if x is None:
                                self.legalize(vertex, [(v, w), (w, u)])
                            else:
                                self.legalize(vertex, [(u, x), (x, v), (v, w), (w, u)])
                    elif quasi_flips and incircle(pu, pv, points[w], points[x]) == _INSIDE:
                        self.flip(u, v)
                    elif not self.split_pair(u, v, w, x):
                        self.left[target] = None
                        break
                    # -- queue the new bad triangles -----------------------------------
                    if tracking:
                        self.account()
                    for key in created:
                        ka, kb, kc = key
                        if get((ka, kb)) != kc:
                            continue
                        if not whole and not self.in_region(ka, kb, kc):
                            continue
                        pa, pb, pc = points[ka], points[kb], points[kc]
                        if max_area is not None and grid[ka] and grid[kb] and grid[kc]:
                            # MaxArea.rate, exact in floats on the dyadic grid (a float key
                            # orders, hashes and compares like the equal rational)
                            ax, ay = pa[2], pa[3]
                            twice = (pb[2] - ax) * (pc[3] - ay) - (pb[3] - ay) * (pc[2] - ax)
                            rating = -twice if twice > max_area else None
                        else:
                            rating = rate(pa, pb, pc)
                        if rating is None:
                            continue
                        if threshold is not None and self.unimprovable(ka, kb, kc):
                            self.left[key] = None
                            continue
                        push(rating, key)
                    created.clear()
                    removed.clear()
                    if tracking and self.mean_reached():
                        raise CriterionMet
                    if get((a, b)) != c:
                        break
        except StepLimit:
            return "step-limit"
        except CriterionMet:
            pass
        return "complete"

    def finish(self, start: Mesh2) -> tuple[Mesh2, list[Step], list[int]]:
        triangle_count = len(self.apex) // 3
        markers = start.vertex_markers.mutate()
        for vertex, marker in self.new_markers.items():
            markers[vertex] = marker
        outgoing = immutables.Map(
            (vertex, hint) for vertex, hint in enumerate(self.hints) if hint is not None
        )
        mesh = Mesh2(
            vertices=self.vertex_table.finish(),
            halfedges=immutables.Map(self.apex),
            outgoing=outgoing,
            segments=immutables.Map(self.segments),
            vertex_markers=markers.finish(),
            vertex_attributes=start.vertex_attributes,
            triangle_attributes=immutables.Map(self.triangle_attrs)
            if self.attributed
            else start.triangle_attributes,
            triangle_count=triangle_count,
            digest=self.digest,
        )
        return mesh, self.steps, self.digests

