"""The refinement loop over a mesh store (:class:`Refinement`), with the progress record and
the exceptions that end a run.  The engines subclass :class:`Refinement` with a store."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal, TypeAlias

import attrs

from geomexact.kernel.angles import compare_angle
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import CircleLocation, Comparison, Orientation
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.mesh2d.longest_edge import _before, is_constraint_edge
from geomexact.mesh2d.refinement.criteria import AnyOf, Criterion, rate_with_attributes
from geomexact.mesh2d.refinement.presets import Rules
from geomexact.mesh2d.refinement.queue import WorkQueue
from geomexact.mesh2d.refinement.regions import Region, Whole
from geomexact.mesh2d.snapshot import Attributes, Edge, Mesh2, Triangle
from geomexact.trace.step import Step

Method: TypeAlias = Literal["bisection", "centroid", "quasi"]
Status: TypeAlias = Literal["complete", "step-limit", "budget"]
LeftReason: TypeAlias = Literal["sharp-corner", "protected-tip"]
"""Why a bad triangle was left (``specs/refine.md``, small input angles): ``"sharp-corner"``
— its angle below the threshold lies in an input angle below it, which no triangulation
can improve; ``"protected-tip"`` — its Lepp step would split a constraint edge of such a
corner that is already shorter than 2^-TIP_DEPTH of its input length."""

_CCW = Orientation.COUNTERCLOCKWISE
_LESS = Comparison.LESS
_INSIDE = CircleLocation.INSIDE

TIP_DEPTH = 10
"""Minimum-angle refinement never splits a constraint edge that bounds an input angle below
the threshold once the edge is shorter than 2^-TIP_DEPTH of the shortest input constraint
edge at that corner (``specs/refine.md``, small input angles)."""


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
class RunOptions:
    """What one Lepp refinement run does, typed, from ``refine()`` to every engine (the
    reference engine and the compiled kernel): the criterion, the region,
    the method, whether Delaunay flips are made, the rules (:class:`~geomexact.mesh2d.
    refinement.presets.Rules`: centroid kind, order, second-longest rule, factor stop)
    and what receives each step's :class:`Progress`."""

    criterion: Criterion
    region: Region
    method: Method = "bisection"
    delaunay: bool = True
    rules: Rules = attrs.field(factory=Rules)
    on_step: Callable[[Progress], None] | None = None

    @property
    def constraint_midpoints(self) -> bool:
        """The older name of the second-longest rule ``"bisect-second"``."""
        return self.rules.second_longest_rule == "bisect-second"


class StepLimit(Exception):
    """Raised before a step when ``max_steps`` steps are recorded."""


class CriterionMet(Exception):
    """Raised when a region-wide criterion is met."""


class Refinement:
    """The refinement loop over a mesh store, written once for every engine.  Subclasses
    provide the store: ``get`` (directed edge -> apex or None), ``point``, ``is_segment``,
    ``attributed`` and ``attributes``; the steps ``bisect``, ``flip``, ``centroid`` and
    ``legalize``, each appending the canonical triangles it adds and removes to
    ``created`` and ``removed``; and the Lepp search ``terminal``.  They may replace
    ``rating`` and ``insert_midpoint`` by faster equal ones."""

    get: Callable[[Edge], int | None]
    point: Callable[[int], Point2]
    attributed: bool

    def __init__(self, start: Mesh2, run: RunOptions) -> None:
        self.start = start
        self.tip_limits: dict[int, Rational | None] = {}
        criterion = self.criterion = run.criterion
        self.region = run.region
        self.whole = isinstance(run.region, Whole)
        self.inside: dict[int, bool] = {}
        self.method = run.method
        self.delaunay = run.delaunay
        self.centroid_kind = run.rules.centroid
        self.constraint_midpoints = run.constraint_midpoints
        self.second_longest_rule = run.rules.second_longest_rule
        self.passes = run.rules.order == "passes"
        self.pass_number = -1  # the pass of the current target ("passes" order)
        self.stop_per_action = run.rules.factor_stop == "action"
        self.legalize_insertions = run.delaunay and run.method != "quasi"
        self.on_step = run.on_step
        self.threshold = criterion.angle_threshold
        self.criterion_attributes = bool(getattr(criterion, "needs_attributes", False))
        self.created: list[Triangle] = []
        self.removed: list[Triangle] = []
        self.queue = WorkQueue()
        self.left: dict[Triangle, LeftReason] = {}
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
        if not self.whole and not self.in_region(a, b, c):
            return
        key = self.rating(a, b, c)
        if key is None:
            return
        if self.threshold is not None and self.unimprovable(a, b, c):
            # a combined criterion may still ask for it (too large): refine it for that
            beyond = (self.criterion.rate_beyond_angle(self.point(a), self.point(b),
                                                       self.point(c),
                                                       self.attributes((a, b, c)))
                      if isinstance(self.criterion, AnyOf) else None)
            if beyond is None:
                self.left[(a, b, c)] = "sharp-corner"
                return
            key = beyond
        if self.passes:
            key = self.pass_number + 1
        self.queue.push(key, (a, b, c))

    def rating(self, a: int, b: int, c: int) -> Any | None:
        """The criterion's key of the triangle (a, b, c), or None when it is good (read
        with its attributes when the criterion needs them: a region's maximum area)."""
        point = self.point
        if self.criterion_attributes:
            return rate_with_attributes(self.criterion, point(a), point(b), point(c),
                                        self.attributes((a, b, c)))
        return self.criterion.rate(point(a), point(b), point(c))

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
                self.area2 -= doubled_area(point(a), point(b), point(c))
                self.count -= 1
        for a, b, c in self.created:
            if self.in_region(a, b, c):
                self.area2 += doubled_area(point(a), point(b), point(c))
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
        if self.stop_per_action and self.target_area2 is not None and self.mean_reached():
            raise CriterionMet

    # -- Lepp ---------------------------------------------------------------------------
    def terminal(self, a: int, b: int, c: int) -> tuple[int, int, int, int | None, bool]:
        """The terminal edge (u, v) of Lepp((a, b, c)) (:func:`geomexact.mesh2d.longest_edge.
        lepp`), its apexes w (left, in the last triangle of the path) and x (right; None on
        the boundary), and whether it is a constraint edge; adds 1 to ``searches`` and the
        path's length in triangles to ``hops``."""
        raise NotImplementedError

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
                squared_length(start.point(vertex), start.point(w)) for w in ends
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
                length = squared_length(self.point(u), self.point(v))
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
        rule = self.second_longest_rule
        if rule != "centroid":
            for p, q in (self.second_edge(u, v, w), self.second_edge(v, u, x)):
                if self.constraint(p, q):
                    if rule == "bisect-longest":
                        p, q = u, v  # Mellado: the midpoint of the longest edge instead
                    elif self.protected(p, q):
                        return False
                    self.insert_midpoint(p, q)
                    return True
        if self.centroid_kind == "midpoint":  # Mellado's centroid=false: bisect e
            self.insert_midpoint(u, v)
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
                    total += doubled_area(point(a), point(b), point(c))
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
            queue = self.queue
            while True:
                if self.passes and queue.keys:
                    self.pass_number = queue.keys[0][1]
                target = queue.pop()
                if target is None:
                    break
                a, b, c = target
                if get((a, b)) != c:
                    continue
                self.targets += 1
                while True:
                    if not self.act(*self.terminal(a, b, c)):
                        self.left[(a, b, c)] = "protected-tip"  # its step would split one
                        break
                    self.drain()
                    if get((a, b)) != c:
                        break
                if not self.stop_per_action and self.target_area2 is not None and (
                    self.mean_reached()
                ):
                    raise CriterionMet
        except StepLimit:
            return "step-limit"
        except CriterionMet:
            pass
        return "complete"

    def left_triangles(self) -> tuple[Triangle, ...]:
        """The left triangles still in the mesh, sorted."""
        get = self.get
        return tuple(sorted(t for t in self.left if get((t[0], t[1])) == t[2]))

    def left_reasons(self) -> tuple[LeftReason, ...]:
        """Why each of :meth:`left_triangles` was left, in the same order."""
        return tuple(self.left[triangle] for triangle in self.left_triangles())


def squared_length(p: Point2, q: Point2) -> Rational:
    dx, dy = q[0] - p[0], q[1] - p[1]
    result: Rational = dx * dx + dy * dy
    return result


def doubled_area(a: Point2, b: Point2, c: Point2) -> Rational:
    ax, ay = a[0], a[1]
    result: Rational = (b[0] - ax) * (c[1] - ay) - (b[1] - ay) * (c[0] - ax)
    return result

