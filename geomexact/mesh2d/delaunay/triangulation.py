"""Delaunay property of 2D meshes (exact).

An interior edge {u, v} with triangles (u, v, w) and (v, u, x) is *locally Delaunay* when x
is not strictly inside the circle through u, v, w.  A mesh is (constrained) Delaunay when
every unconstrained interior edge is locally Delaunay; constrained segments are exempt.
Cocircular quadrilaterals count as Delaunay.  See ``specs/delaunay.md``.
"""

from __future__ import annotations

import collections
import itertools
import math
import operator
import random
from collections.abc import Sequence
from typing import Any, Literal, TypeAlias

import attrs
import immutables

from geomexact.errors import PreconditionError, SegmentError
from geomexact.kernel import digest as _digest
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import CircleLocation, Orientation
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.kernel.vectorising import worth_vectorising
from geomexact.mesh2d.engine_names import engine_named
from geomexact.mesh2d.ops import (
    attach_in_edge_in,
    attach_in_triangle_in,
    attach_outside_in,
    carve_exterior_in,
    carve_in,
    constrain_in,
    containing_triangle,
    exterior_triangles,
    flip_in,
    insert_in_edge_in,
    lawson_flip_wanted,
    legalize_stack_in,
    make_triangle_in,
    set_region_in,
)
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.segments import crossing_point, meeting_pairs, within_box
from geomexact.mesh2d.snapshot import (
    MAX_VERTICES,
    Edge,
    Mesh2,
    canonical_triangle,
    empty_mesh,
    walk_star,
)
from geomexact.mesh2d.transient import Transient2
from geomexact.trace.record import Trace, trace_of

CCW = Orientation.COUNTERCLOCKWISE
CW = Orientation.CLOCKWISE
COLLINEAR = Orientation.COLLINEAR

DelaunayEngine: TypeAlias = Literal["auto", "compiled", "python", "reference", "fast"]
ENGINES: tuple[str, ...] = ("auto", "compiled", "python", "reference")
"""The engines of :func:`triangulate_points` (:mod:`geomexact.mesh2d.engine_names`;
``"python"`` names the reference engine)."""


def non_delaunay_edges(mesh: Mesh2) -> list[Edge]:
    """Sorted (u, v), u < v, of the unconstrained interior edges that are not locally
    Delaunay.  Edges between triangles with different attributes are exempt like
    constrained ones (they bound regions; no flip may cross them).  O(n) exact incircle
    tests."""
    halfedges, vertices, segments = mesh.halfedges, mesh.vertices, mesh.segments
    attributes = mesh.triangle_attributes
    found = []
    for key, w in halfedges.items():
        u, v = key
        if u > v or key in segments:
            continue
        x = halfedges.get((v, u))
        if x is None:
            continue
        if len(attributes) and attributes.get(canonical_triangle(u, v, w)) != attributes.get(
            canonical_triangle(v, u, x)
        ):
            continue
        location = incircle(vertices[u], vertices[v], vertices[w], vertices[x])
        if location == CircleLocation.INSIDE:
            found.append((u, v))
    return sorted(found)


_VECTORISED_FROM = 256
"""Meshes of this many triangles or more are checked in one vectorised pass."""


def is_delaunay(mesh: Mesh2) -> bool:
    """True when every unconstrained interior edge is locally Delaunay (exact).  A large
    mesh is checked in one vectorised pass (:mod:`geomexact.mesh2d.mesh_arrays`: the numpy
    filters, exact arithmetic where they do not decide), with the same answer."""
    if worth_vectorising(mesh.triangle_count, _VECTORISED_FROM):
        from geomexact.mesh2d.mesh_arrays import mesh_arrays

        arrays = mesh_arrays(mesh)
        if arrays is not None:
            return not arrays.non_delaunay_edges()
    return not non_delaunay_edges(mesh)


# ---------------------------------------------------------------------------------------
# Delaunay triangulation of a point set (incremental, BRIO + snake order, walk)
# ---------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class Construction:
    """A triangulation run: the mesh of isolated input vertices it started from
    (``start``), the result (``mesh``), the trace replaying ``start`` to ``mesh``, the
    duplicate input points that were merged (pairs ``(dropped id, kept id)``; the dropped
    vertex stays isolated), and the seeds that were ignored because no triangle contains
    them when their turn comes — outside the domain, or in a hole already carved:
    ``("hole", index)`` and ``("region", index)`` into the PSLG's holes and regions."""

    start: Mesh2
    mesh: Mesh2
    trace: Trace
    duplicates: tuple[tuple[int, int], ...] = ()
    ignored_seeds: tuple[tuple[str, int], ...] = ()


_COORDINATES = operator.itemgetter(0, 1)


def vertices_mesh(pslg: PSLG, *, vertex_hashes: int | None = None) -> Mesh2:
    """The mesh of the PSLG's vertices (ids = PSLG ids, markers and attributes kept), with
    no triangles and no segments: the start of every triangulation trace.
    ``vertex_hashes``: the sum of their ``digest.vertex_hash`` when known already (the
    compiled builder makes it in C)."""
    # Transient2.add_vertex for each vertex, in bulk: the same tables and digest
    if len(pslg.vertices) > MAX_VERTICES:
        raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
    empty = empty_mesh()
    attribute_hash = _digest.attribute_hash
    if vertex_hashes is None:
        vertex_hashes = sum(map(_digest.vertex_hash, itertools.count(),
                                map(_COORDINATES, pslg.vertices)))
    total = empty.digest + vertex_hashes
    markers: dict[int, int] = {}
    attributes: dict[int, tuple[Rational, ...]] = {}
    for index, marker in enumerate(pslg.vertex_markers):
        if marker:
            markers[index] = marker
            total += attribute_hash("vm", (index,), (marker,))
    for index, values in enumerate(pslg.vertex_attributes):
        if values:
            attributes[index] = tuple(values)
            total += attribute_hash("va", (index,), values)
    return attrs.evolve(
        empty,
        vertices=immutables.Map(enumerate(pslg.vertices)),
        vertex_markers=immutables.Map(markers),
        vertex_attributes=immutables.Map(attributes),
        digest=total & (_digest.MODULUS - 1),
    )


def point_doubles(points: Sequence[Point2]) -> Any:
    """The doubles of the points (fields 2 and 3 of each ``Point2``) as an (n x 2) array,
    read in C."""
    import numpy as np

    return np.fromiter(itertools.chain.from_iterable(map(_DOUBLES, points)),
                       dtype=np.float64, count=2 * len(points)).reshape(-1, 2)


def duplicate_points(points: Sequence[Point2], doubles: Any = None) -> list[tuple[int, int]]:
    """Pairs (later id, first id) of points with equal exact coordinates, in id order.
    Points are bucketed by their doubles (exact coordinates when a double is not finite)
    and compared exactly within a bucket.  Expected O(n).  ``doubles``:
    :func:`point_doubles` of the points, when made already."""
    import numpy as np

    if doubles is None:
        doubles = point_doubles(points)
    if not len(doubles):
        return []
    if np.isfinite(doubles).all():
        ordered = doubles[np.lexsort((doubles[:, 1], doubles[:, 0]))]
        if not (ordered[1:] == ordered[:-1]).all(axis=1).any():
            return []  # distinct finite doubles (== as floats): distinct exact points
    buckets: dict[tuple[object, object], list[int]] = {}
    duplicates: list[tuple[int, int]] = []
    for index, point in enumerate(points):
        key: tuple[object, object] = (point.fx, point.fy)
        if not (math.isfinite(point.fx) and math.isfinite(point.fy)):
            key = (point.x, point.y)
        bucket = buckets.get(key)
        if bucket is None:
            buckets[key] = [index]
            continue
        for kept in bucket:
            if points[kept] == point:
                duplicates.append((index, kept))
                break
        else:
            bucket.append(index)
    return duplicates


_DOUBLES = operator.itemgetter(2, 3)


def insertion_order(points: Sequence[Point2], *, seed: int = 0,
                    doubles: Any = None) -> list[int]:
    """A biased randomized insertion order (Amenta–Choi–Rote): a seeded shuffle cut into
    rounds of doubling size, each round sorted along a snake (boustrophedon) curve over a
    grid of about 2 points per cell.  Deterministic for given points and seed; O(n log n).

    Each round is sorted by (column, y along the column's direction, vertex id), computed
    from the halved doubles (differences of halves never overflow near the double limit;
    a non-finite double counts as the lowest finite one): column = min(cells - 1,
    int((x - low_x) / span * cells)), with ``cells = max(1, int(sqrt(len(round) / 2)))``
    and ``span`` the larger side of the finite bounding box (1.0 when it is a point).
    The arithmetic is vectorised (numpy, IEEE doubles, the same operations in the same
    order), so the order is the one this definition gives, bit for bit.  ``doubles``:
    :func:`point_doubles` of the points, when made already.
    """
    import numpy as np

    from geomexact.mesh2d.delaunay import compiled as compiled_delaunay

    shuffled = compiled_delaunay.shuffled_ids(len(points), seed)  # the shuffle below, in C
    if shuffled is None:
        order = list(range(len(points)))
        random.Random(seed).shuffle(order)
        shuffled = np.array(order, dtype=np.int64)
    if not points:
        return []
    if doubles is None:
        doubles = point_doubles(points)
    halves = doubles[shuffled] * 0.5
    finite = np.isfinite(halves)
    lows, highs = [], []
    for axis in (0, 1):
        values = halves[finite[:, axis], axis]
        lows.append(float(values.min()) if values.size else 0.0)
        highs.append(float(values.max()) if values.size else 0.0)
    low_x, low_y = lows
    span = max(highs[0] - low_x, highs[1] - low_y) or 1.0
    xs = np.where(finite[:, 0], halves[:, 0], low_x)
    ys = np.where(finite[:, 1], halves[:, 1], low_y)
    bounds = []
    end = len(shuffled)
    while end > 0:
        begin = end // 2 if end > 64 else 0
        bounds.append((begin, end))
        end = begin
    rounds = []
    for begin, end in reversed(bounds):
        cells = max(1, int(math.sqrt((end - begin) / 2)))
        # (x - low_x) / span * cells is in [0, cells]: truncation is int()
        columns = np.minimum(
            cells - 1, ((xs[begin:end] - low_x) / span * cells).astype(np.int64)
        )
        along = np.where(columns % 2 == 0, ys[begin:end] - low_y, low_y - ys[begin:end])
        vertices = shuffled[begin:end]
        rounds.append(vertices[np.lexsort((vertices, along, columns))])
    result: list[int] = np.concatenate(rounds).tolist()
    return result


class ReferenceDelaunay:
    """The reference engine of :func:`triangulate_points`: the incremental insertion made
    of the ops of :mod:`geomexact.mesh2d.ops` on a
    :class:`~geomexact.mesh2d.transient.Transient2` (each precondition checked, each step
    recorded with its digest): ``make_triangle``, then for each vertex the visibility walk
    to it, ``attach_in_triangle``, ``attach_in_edge`` or ``attach_outside``, and Lawson
    flips from the edges the attachment made.  The compiled kernel
    (:mod:`geomexact.mesh2d.delaunay.compiled`) runs the same steps on its store; the tests
    compare them step by step."""

    __slots__ = ("last", "t")

    def __init__(self, start: Mesh2) -> None:
        self.t = start.transient(batch=True)
        self.last: tuple[int, int] = (0, 0)  # a half-edge of the last triangle made

    def make_triangle(self, a: int, b: int, c: int) -> None:
        made = make_triangle_in(self.t, a, b, c)
        self.last = (made[0], made[1])

    def locate(self, p: Point2) -> tuple[str, tuple[int, int, int]]:
        """Walk from the last triangle to ``p``: ("inside", (a, b, c)), ("edge", (u, v, _))
        or ("outside", (u, v, _)) for a boundary half-edge (u, v) with p strictly right."""
        apex, point = self.t.apex, self.t.point
        a, b = self.last
        c = apex(a, b)
        assert c is not None
        if orient2d(point(a), point(b), p) == CW:
            if apex(b, a) is None:
                return "outside", (a, b, -1)
            a, b, c = self._across(a, b)
        while True:
            pa, pb, pc = point(a), point(b), point(c)
            # the first edge with p strictly beyond it, (b, c), (c, a), then (a, b) (only
            # possible in the first triangle), each tested only when needed
            crossing: tuple[int, int] | None = None
            o1 = orient2d(pb, pc, p)
            if o1 == CW:
                crossing = (b, c)
            else:
                o2 = orient2d(pc, pa, p)
                if o2 == CW:
                    crossing = (c, a)
                else:
                    o0 = orient2d(pa, pb, p)
                    if o0 == CW:
                        crossing = (a, b)
            if crossing is not None:  # cross it, or p is outside the hull there
                u, v = crossing
                if apex(v, u) is None:
                    return "outside", (u, v, -1)
                a, b, c = self._across(u, v)
                continue
            if o1 == COLLINEAR:
                return "edge", (b, c, a)
            if o2 == COLLINEAR:
                return "edge", (c, a, b)
            if o0 == COLLINEAR:
                return "edge", (a, b, c)
            return "inside", (a, b, c)

    def _across(self, u: int, v: int) -> tuple[int, int, int]:
        """The triangle (v, u, apex) beyond the edge (u, v) of the current one."""
        w = self.t.apex(v, u)
        assert w is not None
        return v, u, w

    def insert(self, vertex: int) -> None:
        """Attach the isolated ``vertex`` where it lies, then legalize the edges the
        attachment made opposite it."""
        t = self.t
        where, (a, b, c) = self.locate(t.point(vertex))
        pending: list[tuple[int, int]]
        if where == "inside":
            attach_in_triangle_in(t, vertex, (a, b, c))
            pending = [(c, a), (b, c), (a, b)]
        elif where == "edge":
            u, v = a, b
            w, x = t.apex(u, v), t.apex(v, u)
            attach_in_edge_in(t, vertex, u, v)
            pending = []
            if w is not None:
                pending += [(v, w), (w, u)]
            if x is not None:
                pending += [(u, x), (x, v)]
        else:
            pending = [(q, p) for p, q in attach_outside_in(t, vertex, a, b)]
        self.last = (vertex, pending[0][0])
        legalize_stack_in(t, vertex, pending)


def _delaunay_engine(engine: str) -> str:
    """The Delaunay engine ``engine`` names (:mod:`geomexact.mesh2d.engine_names`):
    ``"python"`` and ``"reference"`` both name :class:`ReferenceDelaunay`."""
    name = engine_named("triangulate", engine, ENGINES, stacklevel=4)
    return "reference" if name == "python" else name


@attrs.frozen(slots=True)
class _PointsPlan:
    """What a point triangulation runs: the start mesh, the first triangle's vertices, the
    vertices inserted after it in order, and the merged duplicates."""

    start: Mesh2
    first: tuple[int, int, int]
    rest: list[int]
    duplicates: tuple[tuple[int, int], ...]


def _plan_points(pslg: PSLG, merge_duplicates: bool, seed: int,
                 vertex_hashes: int | None = None) -> _PointsPlan:
    """Steps 1-3 of ``specs/delaunay.md``: duplicates, the insertion order, the first
    triangle (raises :class:`PreconditionError` as :func:`triangulate_points` does);
    ``vertex_hashes`` as :func:`vertices_mesh`."""
    vertices = pslg.vertices
    doubles = point_doubles(vertices)  # read once, for both
    duplicates = duplicate_points(vertices, doubles)
    if duplicates and not merge_duplicates:
        shown = ", ".join(f"{d} = {k}" for d, k in duplicates[:10])
        more = f" and {len(duplicates) - 10} more" if len(duplicates) > 10 else ""
        raise PreconditionError(
            "triangulate",
            f"{len(duplicates)} duplicate points (vertex = earlier vertex): {shown}{more}; "
            "pass merge_duplicates=True to keep only the first copy",
            duplicates=tuple(duplicates),
        )
    dropped = {d for d, _ in duplicates}
    order = insertion_order(vertices, seed=seed, doubles=doubles)
    if dropped:
        order = [v for v in order if v not in dropped]
    if len(order) < 3:
        raise PreconditionError("triangulate", f"{len(order)} distinct points: need at least 3",
                                distinct=tuple(sorted(order)))
    a, b = order[0], order[1]
    third = next(
        (k for k in range(2, len(order))
         if orient2d(vertices[a], vertices[b], vertices[order[k]]) != COLLINEAR),
        None,
    )
    if third is None:
        raise PreconditionError("triangulate", "all points are collinear: no triangle exists",
                                collinear=tuple(sorted(order)))
    start = vertices_mesh(pslg, vertex_hashes=vertex_hashes)
    c = order.pop(third)
    return _PointsPlan(start, (a, b, c), order[2:], tuple(duplicates))


def triangulate_points(
    points: PSLG | Sequence[Point2],
    *,
    merge_duplicates: bool = False,
    seed: int = 0,
    engine: DelaunayEngine = "auto",
) -> Construction:
    """The Delaunay triangulation of a point set (a PSLG's segments, holes and regions are
    ignored here; see :func:`triangulate`).

    Incremental insertion in a biased randomized order with a visibility walk: expected
    O(n log n).  Vertex ids are the input positions.  Points outside the current hull are
    joined to every hull edge they see strictly, so the result covers the convex hull;
    cocircular points are resolved by the tie rule of :func:`geomexact.mesh2d.ops.legalize_in`
    (no flip on a tie), which makes the result depend on the insertion order only there.
    Raises :class:`PreconditionError` for fewer than 3 distinct points, all points
    collinear, or duplicate points unless ``merge_duplicates`` (then every copy after the
    first stays isolated and is listed in ``Construction.duplicates``).

    ``engine``: ``"auto"`` runs the compiled kernel (:mod:`geomexact.mesh2d.delaunay.compiled`)
    when it is built, else the reference engine :class:`ReferenceDelaunay` (the ops on a
    transient); ``"compiled"`` runs the kernel or raises :class:`PreconditionError` (not
    built); ``"reference"`` (or ``"python"``) runs
    :class:`ReferenceDelaunay`.  Both record the same trace and build the same mesh.
    ``"fast"`` is the old name of ``"auto"``.
    """
    # imported here: loading the kernel loads NumPy, which reading a mesh does not need
    from geomexact.mesh2d.delaunay import compiled as compiled_delaunay

    name = _delaunay_engine(engine)
    pslg = points if isinstance(points, PSLG) else PSLG(vertices=tuple(points))
    vertices = pslg.vertices
    from geomexact._version import __version__

    with collector_paused():  # the plan too: its maps are tens of thousands of objects
        kernel = (compiled_delaunay.open_builder(vertices) if name in ("auto", "compiled")
                  else None)
        plan = _plan_points(pslg, merge_duplicates, seed,
                            None if kernel is None else kernel.vertex_hashes)
        start, (a, b, c) = plan.start, plan.first
        compiled = (None if kernel is None else
                    compiled_delaunay.run_compiled(kernel, start, (a, b, c), plan.rest))
        if compiled is None and name == "compiled":
            raise PreconditionError(
                "triangulate", "engine 'compiled' cannot run this triangulation: the "
                "compiled Delaunay kernel is not built (no C compiler at install; engine "
                "'auto' runs the reference engine then)"
            )
        if compiled is not None:
            mesh, steps, digests = compiled.mesh, compiled.steps, compiled.digests
        else:
            builder = ReferenceDelaunay(start)
            builder.make_triangle(a, b, c)
            for vertex in plan.rest:
                builder.insert(vertex)
            mesh, steps, digests = builder.t.seal(), builder.t.steps, builder.t.step_digests
        # the engine is not a parameter of the construction: both record this trace
        trace = Trace(start.digest, steps, digests,
                      {"algorithm": "delaunay", "seed": seed,
                       "merge_duplicates": merge_duplicates}, __version__)
    return Construction(start, mesh, trace, plan.duplicates)


# ---------------------------------------------------------------------------------------
# Lawson flips, segment recovery, constrained Delaunay triangulation of a PSLG
# ---------------------------------------------------------------------------------------
def make_delaunay_in(t: Transient2) -> int:
    """Lawson's flip algorithm on a transient: flip every unconstrained interior edge that
    is not locally Delaunay (a strict incircle test: cocircular quadrilaterals are left
    alone) until none is left; edges are examined from a stack seeded with all edges in
    sorted order, and the four outer edges of each flipped quadrilateral are pushed back.
    Terminates (each flip lifts the triangulation strictly, Lawson 1977).  Returns the
    number of flips."""
    pending = sorted(t.iter_edges(), reverse=True)
    flips = 0
    while pending:
        u, v = pending.pop()
        w, x = t.apex(u, v), t.apex(v, u)
        if w is None or x is None or t.segment_marker(u, v) is not None:
            continue
        if not lawson_flip_wanted(t, w, u, v, x):
            continue
        flip_in(t, u, v)
        flips += 1
        pending.extend(sorted([(min(a, b), max(a, b)) for a, b in
                               ((u, x), (x, v), (v, w), (w, u))], reverse=True))
    return flips


def make_delaunay(mesh: Mesh2) -> tuple[Mesh2, Trace]:
    """The (constrained) Delaunay triangulation of the same vertices, segments and
    domain as ``mesh``, by Lawson flips; the trace records the flips."""
    transient = Transient2(mesh)
    make_delaunay_in(transient)
    result = transient.seal()
    return result, trace_of(mesh, transient, {"algorithm": "lawson"})


def _offending_pairs(pslg: PSLG) -> list[tuple[tuple[int, int], object]]:
    """Pairs of input segments that meet improperly, then segments through vertices."""
    points = pslg.vertices
    segments = [(u, v) for u, v, _ in pslg.segments]
    found: list[tuple[tuple[int, int], object]] = list(meeting_pairs(points, segments))
    for u, v in segments:
        for w in range(len(points)):
            if w not in (u, v) and orient2d(points[u], points[v], points[w]) == COLLINEAR \
                    and within_box(points[w], points[u], points[v]):
                found.append(((u, v), w))
    return found


def _insert_segment(t: Transient2, u: int, v: int, marker: int, split: bool,
                    pslg: PSLG) -> None:
    """Make {u, v} (a union of) constrained edges: split at vertices on it and (when
    ``split``) at crossings with constrained edges, then flip away the edges it crosses
    (Sloan 1993)."""
    work = [(u, v)]
    while work:
        a, b = work.pop()
        if a == b:
            continue
        if t.apex(a, b) is not None or t.apex(b, a) is not None:
            if t.segment_marker(a, b) is None:
                constrain_in(t, a, b, marker)
            continue
        crossed, stop = _crossed_edges(t, a, b)
        if stop is not None:
            kind, data = stop
            if not split:
                raise SegmentError(_offending_pairs(pslg))
            if kind == "vertex":
                w = data[0]
            else:  # a constrained edge (p, q) crosses ab: split both at the crossing
                p, q = data
                point = crossing_point(t.point(a), t.point(b), t.point(p), t.point(q))
                w = insert_in_edge_in(t, p, q, point)
            work.append((w, b))
            work.append((a, w))
            continue
        _flip_out(t, a, b, crossed)
        constrain_in(t, a, b, marker)


def _crossed_edges(
    t: Transient2, a: int, b: int
) -> tuple[list[tuple[int, int]], tuple[str, tuple[int, ...]] | None]:
    """Edges crossed by segment ab, walking from a; or a stop: ("vertex", (w,)) for the
    first vertex w strictly inside ab, ("constrained", (p, q)) for the first constrained
    edge crossed."""
    pa, pb = t.point(a), t.point(b)
    current: tuple[int, int] | None = None  # (vertex left of ab, vertex right of ab)
    for _, first, second in walk_star(t.apex, a, t.outgoing(a)):
        side = orient2d(pa, pb, t.point(first))
        other = orient2d(pa, pb, t.point(second))
        for vertex, orientation in ((first, side), (second, other)):
            if orientation == COLLINEAR and within_box(t.point(vertex), pa, pb):
                return [], ("vertex", (vertex,))
        if side == CW and other == CCW:
            current = (second, first)
            break
    if current is None:
        raise PreconditionError("triangulate", f"segment ({a}, {b}) leaves the mesh at {a}")
    crossed: list[tuple[int, int]] = []
    while True:
        left, right = current
        if t.segment_marker(left, right) is not None:
            return crossed, ("constrained", (left, right))
        crossed.append(current)
        c = t.apex(left, right)
        if c is None:
            raise PreconditionError("triangulate", f"segment ({a}, {b}) leaves the mesh")
        if c == b:
            return crossed, None
        side = orient2d(pa, pb, t.point(c))
        if side == COLLINEAR:
            return crossed, ("vertex", (c,))
        current = (c, right) if side == CCW else (left, c)


def _flip_out(t: Transient2, a: int, b: int, crossed: list[tuple[int, int]]) -> None:
    """Flip the edges crossing ab until ab is an edge (Sloan's queue: an edge whose
    quadrilateral is not strictly convex waits at the back)."""
    pa, pb = t.point(a), t.point(b)
    queue = collections.deque(crossed)
    stalled = 0
    while queue:
        u, v = queue.popleft()
        w, x = t.apex(u, v), t.apex(v, u)
        assert w is not None and x is not None  # crossing edges are interior
        pu, pv, pw, px = t.point(u), t.point(v), t.point(w), t.point(x)
        if orient2d(px, pw, pu) != CCW or orient2d(pw, px, pv) != CCW:
            queue.append((u, v))
            stalled += 1
            if stalled > len(queue) + 1:
                raise PreconditionError("triangulate", f"cannot recover segment ({a}, {b})")
            continue
        stalled = 0
        flip_in(t, u, v)
        if {w, x} == {a, b}:
            continue
        sw, sx = orient2d(pa, pb, pw), orient2d(pa, pb, px)
        if sw * sx < 0:
            queue.append((w, x) if sw == CCW else (x, w))


def triangulate(
    pslg: PSLG | Sequence[Point2],
    *,
    keep_convex_hull: bool = False,
    split_segments: bool = False,
    merge_duplicates: bool = False,
    seed: int = 0,
    engine: DelaunayEngine = "auto",
) -> Construction:
    """The constrained Delaunay triangulation of a PSLG (a point set gives its Delaunay
    triangulation).

    1. :func:`triangulate_points` on all vertices;
    2. each segment, in input order, is recovered by flips (Sloan) and constrained; a
       vertex lying on a segment or two crossing segments raise :class:`SegmentError`
       listing them, unless ``split_segments`` (then the segment is split at the vertex, and
       crossing segments at their exact crossing point, a new vertex);
    3. Lawson flips make it constrained Delaunay;
    4. unless ``keep_convex_hull``, triangles outside the segments are removed (when the
       PSLG has segments), then each hole seed's region, then regional attributes are set;
       a seed in no triangle (outside the domain, or in a hole carved already) is ignored
       and listed in ``Construction.ignored_seeds``.

    Every change is a recorded step: ``trace`` replays ``start`` (the isolated input
    vertices) to ``mesh``.  ``engine`` is that of :func:`triangulate_points`: with
    ``"auto"`` or ``"compiled"`` and the kernel built, steps 1-4 run in the compiled
    kernel (``compiled.run_compiled_constrained``: segment recovery, the Lawson pass and
    carving recorded step for step as the ops below record them; region seeds then run
    the ops on a transient); where the kernel declines (a crossing point to insert, a
    :class:`SegmentError` to raise, a marker beyond int64) or with ``"python"``, step 1
    runs in that engine and the rest runs the reference ops on a transient.  Both paths
    record the same trace and build the same mesh (``tests/engines``).
    """
    pslg = pslg if isinstance(pslg, PSLG) else PSLG(vertices=tuple(pslg))
    if (pslg.segments or pslg.holes) and _delaunay_engine(engine) in ("auto", "compiled"):
        constrained = _constrained_in_kernel(pslg, keep_convex_hull, split_segments,
                                             merge_duplicates, seed)
        if constrained is not None:
            return constrained
    points_run = triangulate_points(pslg, merge_duplicates=merge_duplicates, seed=seed,
                                    engine=engine)
    if not (pslg.segments or pslg.holes or pslg.regions):
        return points_run
    remap = dict(points_run.duplicates)
    transient = Transient2(points_run.mesh)
    with collector_paused():
        for u, v, marker in pslg.segments:
            _insert_segment(transient, remap.get(u, u), remap.get(v, v), marker,
                            split_segments, pslg)
        make_delaunay_in(transient)
        if pslg.segments and not keep_convex_hull and exterior_triangles(transient):
            carve_exterior_in(transient)
        ignored: list[tuple[str, int]] = []
        for index, hole in enumerate(pslg.holes):
            if containing_triangle(transient, hole) is not None:
                carve_in(transient, hole.x, hole.y)
            else:
                ignored.append(("hole", index))
        for index, region in enumerate(pslg.regions):
            if containing_triangle(transient, region.point) is not None:
                set_region_in(transient, region.point.x, region.point.y, (region.attribute,))
            else:
                ignored.append(("region", index))
        mesh = transient.seal()
    first = points_run.trace
    trace = Trace(
        first.input_digest,
        (*first.steps, *transient.steps),
        (*first.digests, *transient.step_digests),
        {**dict(first.parameters), "keep_convex_hull": keep_convex_hull,
         "split_segments": split_segments},
        first.version,
    )
    return Construction(points_run.start, mesh, trace, points_run.duplicates, tuple(ignored))


def _constrained_in_kernel(pslg: PSLG, keep_convex_hull: bool, split_segments: bool,
                           merge_duplicates: bool, seed: int) -> Construction | None:
    """:func:`triangulate` with the point triangulation, segment recovery, the Lawson
    pass and carving in the compiled kernel, and the region seeds (few, at the end) by
    the ops on a transient: the same steps, digests and mesh as the Python path.  None
    when the kernel is not built or declines the run (then the Python path runs, and
    raises what it raises)."""
    from geomexact.mesh2d.delaunay import compiled as compiled_delaunay

    if not compiled_delaunay.AVAILABLE:
        return None
    from geomexact._version import __version__

    with collector_paused():  # the plan too: its maps are tens of thousands of objects
        kernel = compiled_delaunay.open_builder(pslg.vertices)
        plan = _plan_points(pslg, merge_duplicates, seed, kernel.vertex_hashes)
        remap = dict(plan.duplicates)
        segments = [(remap.get(u, u), remap.get(v, v), marker)
                    for u, v, marker in pslg.segments]
        run = compiled_delaunay.run_compiled_constrained(
            kernel, plan.start, plan.first, plan.rest, segments,
            split_segments=split_segments,
            carve_exterior=bool(pslg.segments) and not keep_convex_hull,
            holes=pslg.holes,
        )
        if run is None:
            return None
        mesh, steps, digests = run.mesh, run.steps, run.digests
        ignored = [("hole", index) for index in run.ignored_holes]
        if pslg.regions:
            transient = Transient2(mesh)
            for index, region in enumerate(pslg.regions):
                if containing_triangle(transient, region.point) is not None:
                    set_region_in(transient, region.point.x, region.point.y,
                                  (region.attribute,))
                else:
                    ignored.append(("region", index))
            mesh = transient.seal()
            steps = [*steps, *transient.steps]
            digests = [*digests, *transient.step_digests]
        trace = Trace(plan.start.digest, steps, digests,
                      {"algorithm": "delaunay", "seed": seed,
                       "merge_duplicates": merge_duplicates,
                       "keep_convex_hull": keep_convex_hull,
                       "split_segments": split_segments}, __version__)
    return Construction(plan.start, mesh, trace, plan.duplicates, tuple(ignored))
