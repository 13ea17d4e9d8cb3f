"""Lepp refinement of 2D meshes: Lepp-bisection, Lepp-centroid Delaunay, Lepp quasi-Delaunay.

``refine(mesh, criterion, ...)`` refines the triangles of ``region`` that ``criterion``
rates bad, worst first, each by repeating Lepp steps (``geomexact.lepp``) until it is
destroyed.  Every change is a step of :mod:`geomexact.ops` (``bisect``, ``flip``,
``insert_centroid``, ``insert_vertex_centroid``) or of :mod:`geomexact.centroids`
(``insert_in_quadrilateral``) recorded in the returned trace, which replays the input to
the result digest by digest; the input snapshot never changes.

Methods (``specs/refine.md``), for the terminal edge e = {u, v} of the triangles t1 (the
last of the path) and t2 (across e):

* ``"bisection"`` (Rivara): bisect e (one triangle when e is a boundary edge); with
  ``delaunay=True`` followed by Lawson legalization around the midpoint.
* ``"centroid"`` (Rivara & Rodríguez, terminal-triangles centroid): e a constraint edge ->
  bisect e; else when the second-longest edge of t1 (then t2) is a constraint edge ->
  bisect that edge; else insert the centroid of the quadrilateral t1 ∪ t2.  Each insertion
  is followed by legalization when ``delaunay=True``.
* ``"quasi"`` (Mellado, quasi-Delaunay): no legalization; at an unconstrained terminal
  pair that is not locally Delaunay, flip e (when ``delaunay=True``) and search again;
  otherwise insert as the centroid method does.

Two engines run the same algorithm: ``"fast"`` (a batch kernel on plain dicts with the
digest kept incrementally) and ``"transient"`` (the ops on a
:class:`~geomexact.transient.Transient2`, the readable reference); they record identical
traces (``tests/test_refine_engines.py``).

>>> from geomexact.criteria import MaxArea
>>> from geomexact.transient import mesh_from_triangles
>>> square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> result = refine(square, MaxArea("1/8"))
>>> result.status, result.mesh.triangle_count, len(result.trace)
('complete', 8, 5)
"""

from __future__ import annotations

import gc
import heapq
import time
from collections import Counter
from collections.abc import Callable, Hashable
from typing import Any, Literal, TypeAlias

import attrs
import immutables

from geomexact import digest as _digest
from geomexact.centroids import insert_in_quadrilateral_in, rounded_area_centroid
from geomexact.criteria import Criterion, MaxArea, as_criterion
from geomexact.dyadic_grid import grid_flags, midpoint_on_grid
from geomexact.errors import PreconditionError
from geomexact.lepp import _before, is_constraint_edge
from geomexact.mesh2d import MAX_VERTICES, Attributes, Edge, Mesh2, Triangle, canonical_triangle
from geomexact.numbers import Rational, mpq
from geomexact.ops import (
    bisect_in,
    flip_in,
    insert_centroid_in,
    legalize_in,
    quadrilateral_area_centroid,
    quadrilateral_vertex_centroid,
)
from geomexact.points import Point2, point2
from geomexact.predicates import (
    CircleLocation,
    Comparison,
    Orientation,
    compare_angle,
    compare_squared_lengths,
    incircle,
    orient2d,
)
from geomexact.regions import Region, Whole, as_region
from geomexact.step import Step
from geomexact.trace import Trace
from geomexact.transient import Transient2

__all__ = [
    "CENTROIDS",
    "ENGINES",
    "METHODS",
    "Progress",
    "RefineStats",
    "Result",
    "refine",
]

Method: TypeAlias = Literal["bisection", "centroid", "quasi"]
Status: TypeAlias = Literal["complete", "step-limit"]
METHODS: tuple[str, ...] = ("bisection", "centroid", "quasi")
CENTROIDS: tuple[str, ...] = ("area", "area-exact", "vertices")
ENGINES: tuple[str, ...] = ("fast", "transient")

_CCW = Orientation.COUNTERCLOCKWISE
_LESS = Comparison.LESS
_INSIDE = CircleLocation.INSIDE
_MASK = _digest.MODULUS - 1

TIP_DEPTH = 10
"""Minimum-angle refinement never splits a constraint edge that bounds an input angle below
the threshold once the edge is shorter than 2^-TIP_DEPTH of the shortest input constraint
edge at that corner (``specs/refine.md``, small input angles)."""


# ---------------------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class Progress:
    """What ``on_step`` receives after each step: the number of steps so far, the step,
    the mesh's triangle and vertex counts, and the number of entries in the work queue
    (an upper bound on the bad triangles still waiting)."""

    steps: int
    step: Step
    triangles: int
    vertices: int
    pending: int


@attrs.frozen(slots=True)
class RefineStats:
    """Counts of a run.

    ``status``: ``"complete"`` (every triangle of the region meets the criterion or is
    listed in ``left``; for an average-area criterion, the mean is reached) or
    ``"step-limit"`` (stopped by ``max_steps``); ``steps``: trace length; ``bisections``:
    edge midpoints inserted; ``centroids``: quadrilateral centroids inserted; ``flips``:
    legalization and quasi-Delaunay flips; ``targets``: bad triangles taken from the
    queue; ``lepp_searches`` / ``lepp_triangles``: Lepp paths computed and their total
    length in triangles; ``left``: bad triangles of the final mesh left alone at input
    angles below the minimum angle — those with an angle below it inside such an input
    angle, and those whose Lepp step would split a constraint edge of such an input angle
    shorter than 2^-TIP_DEPTH of its input length (sorted, canonical); ``seconds``: wall
    time."""

    status: Status
    steps: int
    bisections: int
    centroids: int
    flips: int
    targets: int
    lepp_searches: int
    lepp_triangles: int
    left: tuple[Triangle, ...]
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready counts (``left`` as a count)."""
        return {
            "status": self.status,
            "steps": self.steps,
            "bisections": self.bisections,
            "centroids": self.centroids,
            "flips": self.flips,
            "targets": self.targets,
            "lepp_searches": self.lepp_searches,
            "lepp_triangles": self.lepp_triangles,
            "left": len(self.left),
            "seconds": self.seconds,
        }


@attrs.frozen(slots=True)
class Result:
    """A refinement run: the input (``start``), the result (``mesh``), the trace replaying
    ``start`` to ``mesh``, and the run's :class:`RefineStats`."""

    start: Mesh2
    mesh: Mesh2
    trace: Trace
    stats: RefineStats

    @property
    def status(self) -> Status:
        """``"complete"`` or ``"step-limit"``."""
        return self.stats.status


class _StepLimit(Exception):
    """Raised before a step when ``max_steps`` steps are recorded."""


class _Stop(Exception):
    """Raised when a region-wide criterion is met."""


# ---------------------------------------------------------------------------------------
# the work queue
# ---------------------------------------------------------------------------------------
def _rank(key: Any) -> float:
    """A float that orders like ``key`` where it can (monotone: never inverts two keys),
    so most comparisons in the queue are float comparisons."""
    try:
        return float(key)
    except OverflowError:
        return float("inf") if key > 0 else float("-inf")
    except (TypeError, ValueError):
        return 0.0


class _Queue:
    """Triangles by priority: ``pop`` returns the triangle with the smallest (key,
    triangle), as one heap of such pairs would, but stores each distinct key once (a heap
    of (rank, key)) with a heap of its triangles, so that equal keys — common, e.g. equal
    areas — cost integer comparisons only.  Keys must be hashable and totally ordered."""

    __slots__ = ("buckets", "keys", "size")

    def __init__(self) -> None:
        self.buckets: dict[Hashable, list[Triangle]] = {}
        self.keys: list[tuple[float, Any]] = []
        self.size = 0

    def push(self, key: Any, triangle: Triangle) -> None:
        bucket = self.buckets.get(key)
        if bucket is None:
            self.buckets[key] = [triangle]
            heapq.heappush(self.keys, (_rank(key), key))
        else:
            heapq.heappush(bucket, triangle)
        self.size += 1

    def pop(self) -> Triangle | None:
        keys = self.keys
        if not keys:
            return None
        key = keys[0][1]
        bucket = self.buckets[key]
        triangle = heapq.heappop(bucket)
        if not bucket:
            heapq.heappop(keys)
            del self.buckets[key]
        self.size -= 1
        return triangle


# ---------------------------------------------------------------------------------------
# the driver (the reference; the fast engine inlines the same loop)
# ---------------------------------------------------------------------------------------
class _Refinement:
    """The refinement loop over a mesh store.  Subclasses provide the store: ``get``
    (directed edge -> apex or None), ``point``, ``is_segment``, ``attributed`` and
    ``attributes``, and the steps ``bisect``, ``flip``, ``centroid`` and ``legalize``,
    each appending the canonical triangles it adds and removes to ``created`` and
    ``removed``."""

    get: Callable[[Edge], int | None]
    point: Callable[[int], Point2]
    attributed: bool

    def __init__(
        self,
        start: Mesh2,
        criterion: Criterion,
        region: Region,
        method: Method,
        delaunay: bool,
        centroid: str,
        constraint_midpoints: bool,
        on_step: Callable[[Progress], None] | None,
    ) -> None:
        self.start = start
        self.tip_limits: dict[int, Rational | None] = {}
        self.criterion = criterion
        self.region = region
        self.whole = isinstance(region, Whole)
        self.inside: dict[int, bool] = {}
        self.method = method
        self.delaunay = delaunay
        self.centroid_kind = centroid
        self.constraint_midpoints = constraint_midpoints
        self.legalize_insertions = delaunay and method != "quasi"
        self.on_step = on_step
        self.threshold = criterion.angle_threshold
        self.created: list[Triangle] = []
        self.removed: list[Triangle] = []
        self.queue = _Queue()
        self.left: dict[Triangle, None] = {}
        self.target_area2: Rational | None = None  # twice the target mean area
        self.area2: Rational = mpq(0)
        self.count = 0
        self.targets = self.searches = self.hops = 0

    # -- the store (overridden) ---------------------------------------------------------
    def is_segment(self, u: int, v: int) -> bool:
        raise NotImplementedError

    def attributes(self, triangle: Triangle) -> Attributes | None:
        raise NotImplementedError

    def bisect(self, u: int, v: int) -> int:
        raise NotImplementedError

    def flip(self, u: int, v: int) -> None:
        raise NotImplementedError

    def centroid(self, u: int, v: int) -> int:
        raise NotImplementedError

    def legalize(self, vertex: int) -> None:
        raise NotImplementedError

    def finish(self, start: Mesh2) -> tuple[Mesh2, list[Step], list[int]]:
        raise NotImplementedError

    # -- region, rating, constraints ----------------------------------------------------
    def in_region(self, a: int, b: int, c: int) -> bool:
        """True when a vertex of the triangle is in the region (cached per vertex)."""
        if self.whole:
            return True
        inside = self.inside
        for vertex in (a, b, c):
            known = inside.get(vertex)
            if known is None:
                known = inside[vertex] = self.region.contains(self.point(vertex))
            if known:
                return True
        return False

    def consider(self, a: int, b: int, c: int) -> None:
        """Queue the canonical triangle (a, b, c) when it is in the region and bad (or
        note it as left when it is bad only at input angles)."""
        if not self.in_region(a, b, c):
            return
        point = self.point
        key = self.criterion.rate(point(a), point(b), point(c))
        if key is None:
            return
        if self.threshold is not None and self.unimprovable(a, b, c):
            self.left[(a, b, c)] = None
            return
        self.queue.push(key, (a, b, c))

    def different_attributes(self, u: int, v: int, w: int, x: int) -> bool:
        return self.attributes((u, v, w)) != self.attributes((v, u, x))

    def constraint(self, u: int, v: int) -> bool:
        """True when the edge {u, v} is a boundary, segment or attribute-border edge."""
        w, x = self.get((u, v)), self.get((v, u))
        if w is None or x is None or self.is_segment(u, v):
            return True
        return self.attributed and self.different_attributes(u, v, w, x)

    def unimprovable(self, a: int, b: int, c: int) -> bool:
        """True when an angle of (a, b, c) below the threshold lies inside an *input angle*
        below the threshold: the sector between the two consecutive constraint edges
        around its vertex that enclose the triangle (Rivara & Rodríguez's non-improvable
        triangles; no triangulation of that sector has an angle >= θ at the vertex, and
        refining there would never end)."""
        threshold = self.threshold
        assert threshold is not None
        point = self.point
        for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
            pp = point(p)
            if compare_angle(point(q), pp, point(r), threshold) != _LESS:
                continue
            sector = self.constraint_sector(p, q, r)
            if sector is None:
                continue
            first, last = point(sector[0]), point(sector[1])
            if orient2d(pp, first, last) == _CCW and (
                compare_angle(first, pp, last, threshold) == _LESS
            ):
                return True
        return False

    def constraint_sector(self, p: int, q: int, r: int) -> Edge | None:
        """For the triangle (p, q, r): the far ends (s, t) of the constraint edges p-s and
        p-t met first turning clockwise from p->q and counter-clockwise from p->r (the
        sector from p->s counter-clockwise to p->t holds the triangle), or None when p has
        fewer than two constraint edges (no sector)."""
        first = q
        while not self.constraint(p, first):
            previous = self.get((first, p))
            assert previous is not None
            first = previous
            if first == r:
                return None  # all the way round
        last = r
        while not self.constraint(p, last):
            following = self.get((p, last))
            assert following is not None
            last = following
        return first, last

    def account(self) -> None:
        """Update the region's doubled area and triangle count by the last action."""
        point = self.point
        for a, b, c in self.removed:
            if self.in_region(a, b, c):
                self.area2 -= _doubled(point(a), point(b), point(c))
                self.count -= 1
        for a, b, c in self.created:
            if self.in_region(a, b, c):
                self.area2 += _doubled(point(a), point(b), point(c))
                self.count += 1

    def mean_reached(self) -> bool:
        assert self.target_area2 is not None
        return bool(self.count == 0 or self.area2 <= self.target_area2 * self.count)

    def drain(self) -> None:
        """Account for the triangles the last action removed and added, and queue the new
        ones that are bad."""
        if self.target_area2 is not None:
            self.account()
        get = self.get
        for a, b, c in self.created:
            if get((a, b)) == c:
                self.consider(a, b, c)
        self.created.clear()
        self.removed.clear()
        if self.target_area2 is not None and self.mean_reached():
            raise _Stop

    # -- Lepp ---------------------------------------------------------------------------
    def terminal(self, a: int, b: int, c: int) -> tuple[int, int, int, int | None, bool]:
        """The terminal edge (u, v) of Lepp((a, b, c)), its apexes w (left, in the last
        triangle of the path) and x (right; None on the boundary), and whether it is a
        constraint edge.  As :func:`geomexact.lepp.lepp`."""
        get, point = self.get, self.point
        pa, pb, pc = point(a), point(b), point(c)
        if _before(pa, pb, a, b, pb, pc, b, c):
            u, v, w = (a, b, c) if _before(pa, pb, a, b, pc, pa, c, a) else (c, a, b)
        else:
            u, v, w = (b, c, a) if _before(pb, pc, b, c, pc, pa, c, a) else (c, a, b)
        self.searches += 1
        self.hops += 1
        while True:
            x = get((v, u))
            if x is None or self.is_segment(u, v) or (
                self.attributed and self.different_attributes(u, v, w, x)
            ):
                return u, v, w, x, True
            pu, pv, px = point(u), point(v), point(x)
            if (
                compare_squared_lengths(pu, pv, pv, px) != _LESS
                and compare_squared_lengths(pu, pv, px, pu) != _LESS
            ):
                return u, v, w, x, False
            self.hops += 1
            if _before(pu, px, u, x, px, pv, x, v):
                u, v, w = u, x, v
            else:
                u, v, w = x, v, u

    def second_edge(self, u: int, v: int, w: int) -> Edge:
        """The longer (edge order) of the edges (v, w), (w, u) of triangle (u, v, w)."""
        point = self.point
        pu, pv, pw = point(u), point(v), point(w)
        return (v, w) if _before(pv, pw, v, w, pw, pu, w, u) else (w, u)

    # -- actions ------------------------------------------------------------------------
    def sharp(self, p: int, q: int, r: int) -> bool:
        """True when the triangle (p, q, r) lies in a sector at p between two constraint
        edges that meet at less than the threshold (an input angle below θ)."""
        threshold = self.threshold
        assert threshold is not None
        sector = self.constraint_sector(p, q, r)
        if sector is None:
            return False
        point = self.point
        pp, first, last = point(p), point(sector[0]), point(sector[1])
        return orient2d(pp, first, last) == _CCW and (
            compare_angle(first, pp, last, threshold) == _LESS
        )

    def tip_limit(self, vertex: int) -> Rational | None:
        """(2^-TIP_DEPTH × the shortest constraint edge at ``vertex`` in the input)²,
        or None for a vertex with fewer than two constraint edges in the input."""
        if vertex in self.tip_limits:
            return self.tip_limits[vertex]
        limit = None
        start = self.start
        if vertex < start.vertex_count:
            star = start.star(vertex)
            ends = [w for _, w, _ in star]
            if star and start.apex(vertex, star[-1][2]) is None:
                ends.append(star[-1][2])  # a boundary vertex: the last edge of the fan
            lengths = [
                _squared(start.point(vertex), start.point(w)) for w in ends
                if is_constraint_edge(start, vertex, w)
            ]
            if len(lengths) >= 2:
                limit = min(lengths) / 4**TIP_DEPTH
        self.tip_limits[vertex] = limit
        return limit

    def protected(self, u: int, v: int) -> bool:
        """Minimum-angle criteria: True when the constraint edge {u, v} bounds an input
        angle below the threshold at u or v and is shorter than that corner's tip limit
        (splitting it would only push a cascade of bad triangles into the corner)."""
        if self.threshold is None:
            return False
        length = None
        for p, s in ((u, v), (v, u)):
            limit = self.tip_limit(p)
            if limit is None:
                continue
            if length is None:
                length = _squared(self.point(u), self.point(v))
            if length >= limit:
                continue
            left, right = self.get((p, s)), self.get((s, p))
            if left is not None and self.sharp(p, s, left):
                return True
            if right is not None and self.sharp(p, right, s):
                return True
        return False

    def insert_midpoint(self, u: int, v: int) -> None:
        vertex = self.bisect(u, v)
        if self.legalize_insertions:
            self.legalize(vertex)

    def act(self, u: int, v: int, w: int, x: int | None, constrained: bool) -> bool:
        """One Lepp step at the terminal edge (u, v) of triangles (u, v, w), (v, u, x);
        False (and no step) when the step would split a protected edge."""
        if constrained or x is None or self.method == "bisection":
            if constrained and self.protected(u, v):
                return False
            self.insert_midpoint(u, v)
            return True
        point = self.point
        if self.method == "quasi" and self.delaunay and (
            incircle(point(u), point(v), point(w), point(x)) == _INSIDE
        ):
            self.flip(u, v)
            return True
        return self.split_pair(u, v, w, x)

    def split_pair(self, u: int, v: int, w: int, x: int) -> bool:
        """Insert into the unconstrained terminal pair (u, v, w), (v, u, x): the midpoint
        of a constraint second-longest edge (of the first triangle, then the second), else
        the quadrilateral's centroid.  False (and no step) when that midpoint would split
        a protected edge."""
        if self.constraint_midpoints:
            for p, q in (self.second_edge(u, v, w), self.second_edge(v, u, x)):
                if self.constraint(p, q):
                    if self.protected(p, q):
                        return False
                    self.insert_midpoint(p, q)
                    return True
        vertex = self.centroid(u, v)
        if self.legalize_insertions:
            self.legalize(vertex)
        return True

    # -- the loop -----------------------------------------------------------------------
    def start_queue(self, triangles: list[Triangle]) -> None:
        """Rate every triangle of the input (and set up a region-wide criterion)."""
        if self.criterion.target_mean_area(mpq(1), 1) is not None:
            point = self.point
            total, count = mpq(0), 0
            for a, b, c in triangles:
                if self.in_region(a, b, c):
                    total += _doubled(point(a), point(b), point(c))
                    count += 1
            target = self.criterion.target_mean_area(total / 2, count)
            assert target is not None
            self.target_area2, self.area2, self.count = 2 * target, total, count
        for a, b, c in triangles:
            self.consider(a, b, c)

    def run(self) -> Status:
        """Refine until the queue is empty (or the region-wide target is met)."""
        get = self.get
        try:
            if self.target_area2 is not None and self.mean_reached():
                return "complete"
            while True:
                target = self.queue.pop()
                if target is None:
                    break
                a, b, c = target
                if get((a, b)) != c:
                    continue
                self.targets += 1
                while True:
                    if not self.act(*self.terminal(a, b, c)):
                        self.left[(a, b, c)] = None  # its step would split a protected edge
                        break
                    self.drain()
                    if get((a, b)) != c:
                        break
        except _StepLimit:
            return "step-limit"
        except _Stop:
            pass
        return "complete"

    def left_triangles(self) -> tuple[Triangle, ...]:
        get = self.get
        return tuple(sorted(t for t in self.left if get((t[0], t[1])) == t[2]))


def _compare_squared_lengths_on_grid(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
    """:func:`~geomexact.predicates.compare_squared_lengths` (as -1, 0, 1) for points on
    the dyadic grid (:mod:`geomexact.dyadic_grid`), where it is exact in floats."""
    ux, uy, vx, vy = b[2] - a[2], b[3] - a[3], d[2] - c[2], d[3] - c[3]
    first, second = ux * ux + uy * uy, vx * vx + vy * vy
    return (first > second) - (first < second)


def _squared(p: Point2, q: Point2) -> Rational:
    dx, dy = q[0] - p[0], q[1] - p[1]
    result: Rational = dx * dx + dy * dy
    return result


def _doubled(a: Point2, b: Point2, c: Point2) -> Rational:
    ax, ay = a[0], a[1]
    result: Rational = (b[0] - ax) * (c[1] - ay) - (b[1] - ay) * (c[0] - ax)
    return result


# ---------------------------------------------------------------------------------------
# engine "transient": the ops on a Transient2
# ---------------------------------------------------------------------------------------
class _RecordingTransient(Transient2):
    """A transient that lists the triangles it adds and removes, refuses to start a step
    beyond the step limit, and reports each step."""

    __slots__ = ("created", "limit", "removed", "report")

    def __init__(self, mesh: Mesh2, limit: int | None) -> None:
        super().__init__(mesh)
        self.created: list[Triangle] = []
        self.removed: list[Triangle] = []
        self.limit = limit
        self.report: Callable[[Step], None] | None = None

    def _guard(self) -> None:
        # the first edit of each step used here is add_vertex or remove_triangle, and the
        # step count changes only when the step is complete
        if self.limit is not None and len(self.steps) >= self.limit:
            raise _StepLimit

    def add_vertex(
        self, point: Point2, marker: int = 0, attributes: Attributes = ()
    ) -> int:
        self._guard()
        return super().add_vertex(point, marker, attributes)

    def add_triangle(
        self, a: int, b: int, c: int, attributes: Attributes | None = None
    ) -> None:
        super().add_triangle(a, b, c, attributes)
        self.created.append(canonical_triangle(a, b, c))

    def remove_triangle(self, a: int, b: int, c: int) -> Attributes | None:
        self._guard()
        attributes = super().remove_triangle(a, b, c)
        self.removed.append(canonical_triangle(a, b, c))
        return attributes

    def record(self, step: Step) -> None:
        super().record(step)
        if self.report is not None:
            self.report(step)


class _TransientRefinement(_Refinement):
    def __init__(self, mesh: Mesh2, max_steps: int | None, **options: Any) -> None:
        super().__init__(mesh, **options)
        self.t = t = _RecordingTransient(mesh, max_steps)
        t.created = self.created
        t.removed = self.removed
        self.get = lambda edge: t.apex(edge[0], edge[1])
        self.point = t.point
        self.attributed = bool(len(mesh.triangle_attributes))
        if self.on_step is not None:
            t.report = self._report

    def _report(self, step: Step) -> None:
        assert self.on_step is not None
        t = self.t
        self.on_step(
            Progress(len(t.steps), step, t.triangle_count, t.vertex_count, self.queue.size)
        )

    def is_segment(self, u: int, v: int) -> bool:
        return self.t.segment_marker(u, v) is not None

    def attributes(self, triangle: Triangle) -> Attributes | None:
        return self.t.triangle_attributes(triangle)

    def bisect(self, u: int, v: int) -> int:
        return bisect_in(self.t, u, v)

    def flip(self, u: int, v: int) -> None:
        flip_in(self.t, u, v)

    def centroid(self, u: int, v: int) -> int:
        t = self.t
        if self.centroid_kind == "area":
            w, x = t.apex(u, v), t.apex(v, u)
            assert w is not None and x is not None
            point = rounded_area_centroid(t.point(u), t.point(v), t.point(w), t.point(x))
            return insert_in_quadrilateral_in(t, u, v, point)
        kind = "area" if self.centroid_kind == "area-exact" else "vertices"
        return insert_centroid_in(t, u, v, kind=kind)

    def legalize(self, vertex: int) -> None:
        legalize_in(self.t, vertex)

    def finish(self, start: Mesh2) -> tuple[Mesh2, list[Step], list[int]]:
        t = self.t
        return t.seal(), t.steps, t.step_digests


# ---------------------------------------------------------------------------------------
# engine "fast": the batch kernel on plain dicts
# ---------------------------------------------------------------------------------------
def _exact_point(x: Rational, y: Rational) -> Point2:
    """:func:`point2` for rationals, without its conversions."""
    try:
        return Point2(x, y, float(x), float(y))
    except OverflowError:
        return point2(x, y)


class _FastRefinement(_Refinement):
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
            raise _StepLimit

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
        """:func:`geomexact.ops.bisect_in`; the common case (no attributes) inlined."""
        steps = self.steps
        if self.limit is not None and len(steps) >= self.limit:
            raise _StepLimit
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
        """:func:`geomexact.ops.flip_in`."""
        if self.limit is not None and len(self.steps) >= self.limit:
            raise _StepLimit
        apex = self.apex
        w, x = apex[(u, v)], apex[(v, u)]
        attributes = self._remove(u, v, w)
        self._remove(v, u, x)
        self._add(x, w, u, attributes)
        self._add(w, x, v, attributes)
        self._record("flip", (u, v))

    def centroid(self, u: int, v: int) -> int:
        """:func:`geomexact.ops.insert_centroid_in` or
        :func:`geomexact.centroids.insert_in_quadrilateral_in`."""
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
        """:func:`geomexact.ops.legalize_in`, flip for flip; ``star`` is the star of
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
        :func:`geomexact.mesh2d.walk_star`)."""
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
        """:meth:`_Refinement.run` with the Lepp search and the queueing inlined."""
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
        exact, on_grid = compare_squared_lengths, _compare_squared_lengths_on_grid
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
                        raise _Stop
                    if get((a, b)) != c:
                        break
        except _StepLimit:
            return "step-limit"
        except _Stop:
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


# ---------------------------------------------------------------------------------------
# the public function
# ---------------------------------------------------------------------------------------
def refine(
    mesh: Mesh2,
    criterion: Criterion | Callable[[Point2, Point2, Point2], object],
    *,
    region: Region | Callable[[Point2], object] | None = None,
    method: Method = "bisection",
    delaunay: bool = True,
    centroid: Literal["area", "area-exact", "vertices"] = "area",
    constraint_midpoints: bool = True,
    max_steps: int | None = None,
    on_step: Callable[[Progress], None] | None = None,
    engine: Literal["fast", "transient"] = "fast",
) -> Result:
    """Refine the triangles of ``region`` that ``criterion`` rates bad, by Lepp steps.

    Parameters
    ----------
    mesh:
        The input snapshot (never changed).  For a Delaunay method it should be (constrained)
        Delaunay; then the result is too.
    criterion:
        A :class:`~geomexact.criteria.Criterion` (``MaxArea``, ``AverageAreaFactor``,
        ``MinAngle``, ``MaxEdgeLength``, ``CallableCriterion``) or a callable
        ``test(a, b, c) -> bool``.
    region:
        A :class:`~geomexact.regions.Region` or a callable ``contains(point) -> bool``
        (default: the whole mesh).  A triangle is in the region when one of its vertices is.
    method:
        ``"bisection"``, ``"centroid"`` or ``"quasi"`` (module docstring).
    delaunay:
        Legalize after each insertion (bisection, centroid) or flip non-Delaunay terminal
        pairs (quasi).  ``False`` never flips.
    centroid:
        The point inserted into a terminal quadrilateral: ``"area"`` (its area centroid
        rounded to 24 bits below its shortest side, step ``insert_in_quadrilateral``; see
        :mod:`geomexact.centroids`), ``"area-exact"`` (the exact area centroid, step
        ``insert_centroid``: coordinate sizes grow geometrically, for small runs only) or
        ``"vertices"`` (the mean of its four vertices, exact, step
        ``insert_vertex_centroid``).
    constraint_midpoints:
        Centroid and quasi methods: when a terminal triangle's second-longest edge is a
        constraint edge, insert that edge's midpoint instead of the centroid (Rivara &
        Rodríguez's rule for convergence near constraints).  ``False`` always inserts the
        centroid into an unconstrained terminal pair (as QLepp2D does).
    max_steps:
        Stop before the step that would exceed it, with status ``"step-limit"`` (a run may
        stop inside a legalization: the mesh is valid but need not be Delaunay).  Required
        with a minimum-angle criterion for Lepp-bisection and for ``delaunay=False``, which
        cannot meet it in general.
    on_step:
        Called with a :class:`Progress` after every step.
    engine:
        ``"fast"`` (batch kernel) or ``"transient"`` (the ops on a transient; slower, the
        reference).  Both record the same trace.

    Raises :class:`~geomexact.errors.PreconditionError` for an unknown method, centroid or
    engine, a negative ``max_steps``, or a minimum angle with bisection or without
    Delaunay flips and no step limit.

    Every decision is exact and every tie is broken by vertex ids (``specs/refine.md``),
    so the trace is the same on every machine.  Cost: O(steps × Lepp length) exact
    predicates.  The cyclic garbage collector is paused during the run; afterwards, when it
    was enabled, every tracked object is moved to its oldest generation (``gc.freeze()``
    then ``gc.unfreeze()``), so the new mesh is not scanned by young collections.
    """
    rule = as_criterion(criterion)
    area = as_region(region)
    if method not in METHODS:
        raise PreconditionError("refine", f"unknown method {method!r}; choose from {METHODS}")
    if centroid not in CENTROIDS:
        raise PreconditionError(
            "refine", f"unknown centroid {centroid!r}; choose from {CENTROIDS}"
        )
    if engine not in ENGINES:
        raise PreconditionError("refine", f"unknown engine {engine!r}; choose from {ENGINES}")
    if max_steps is not None and (
        isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 0
    ):
        raise PreconditionError("refine", f"max_steps must be an integer >= 0, not {max_steps!r}")
    if rule.angle_threshold is not None and max_steps is None:
        if method == "bisection":
            raise PreconditionError(
                "refine",
                "Lepp-bisection does not raise angles (each bisection keeps or halves the "
                "angles at the split), so a minimum-angle criterion may never be met; use "
                "method 'centroid' or 'quasi', or give a step limit (max_steps, --max-steps) "
                "to bisect anyway",
            )
        if not delaunay:
            raise PreconditionError(
                "refine",
                "without Delaunay flips no angle at an existing vertex ever grows (insertions "
                "only split angles), so a minimum-angle criterion may never be met; allow "
                "flips (delaunay=True, no --no-delaunay) or give a step limit (max_steps, "
                "--max-steps)",
            )
    began = time.perf_counter()
    options: dict[str, Any] = {
        "criterion": rule,
        "region": area,
        "method": method,
        "delaunay": delaunay,
        "centroid": centroid,
        "constraint_midpoints": constraint_midpoints,
        "on_step": on_step,
    }
    collecting = gc.isenabled()
    gc.disable()  # a large run makes millions of small tuples: the cyclic GC would walk them
    try:
        run: _Refinement
        if engine == "fast":
            run = _FastRefinement(mesh, max_steps, **options)
        else:
            run = _TransientRefinement(mesh, max_steps, **options)
        run.start_queue(sorted(mesh.iter_triangles()))
        status = run.run()
        result, steps, digests = run.finish(mesh)
        left = run.left_triangles()
        targets, searches, hops = run.targets, run.searches, run.hops
        del run  # its work tables go now, before the collector would scan them
    finally:
        if collecting:
            # The objects made by the run (the new mesh's tables, points and steps) are
            # long-lived: put them straight into the oldest generation (freeze, then
            # unfreeze) instead of letting the first young collections scan them all.
            gc.freeze()
            gc.unfreeze()
            gc.enable()
    from geomexact import __version__

    parameters = {
        "algorithm": "lepp",
        "method": method,
        "delaunay": delaunay,
        "centroid": centroid,
        "constraint_midpoints": constraint_midpoints,
        "criterion": rule.parameters(),
        "region": area.parameters(),
        "max_steps": max_steps,
    }
    trace = Trace(mesh.digest, steps, digests, parameters, __version__)
    ops = Counter(step.op for step in steps)
    stats = RefineStats(
        status=status,
        steps=len(steps),
        bisections=ops["bisect"],
        centroids=ops["insert_in_quadrilateral"] + ops["insert_centroid"]
        + ops["insert_vertex_centroid"],
        flips=ops["flip"],
        targets=targets,
        lepp_searches=searches,
        lepp_triangles=hops,
        left=left,
        seconds=time.perf_counter() - began,
    )
    return Result(mesh, result, trace, stats)
