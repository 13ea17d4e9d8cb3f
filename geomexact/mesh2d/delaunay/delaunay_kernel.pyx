# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, infer_types=False
"""Typed kernel of ``geomexact.mesh2d.delaunay.triangulation.triangulate_points``: the incremental Delaunay
construction of ``ReferenceDelaunay`` on C data structures.

Contract: :class:`Builder` runs exactly ``ReferenceDelaunay.make_triangle`` then
``insert`` for every vertex of the given order (the visibility walk ``locate``, the ops
``attach_in_triangle`` / ``attach_in_edge`` / ``attach_outside``, Lawson flips from the
edges the attachment made, with the tie rule "no flip on cocircular").  It records the
same steps, the same digest after every step, and seals the same ``Mesh2`` — including the
``outgoing`` hints, Transient2's: ``add_triangle`` writes a -> b, b -> c, c -> a,
``remove_triangle`` leaves them, and sealing repairs a broken hint to the smallest
neighbour.  ``geomexact.mesh2d.delaunay.compiled`` is the only caller.

The constrained phase (``begin_constrained``, ``recover``, ``lawson``, ``carve_exterior``,
``carve``, ``finish_constrained``) continues on the same tables what
``triangulation.triangulate`` runs on a ``Transient2`` after the point triangulation:
``_insert_segment`` (Sloan's walk from u along uv, a vertex on the segment splits it with
``split_segments``, the FIFO queue of crossed edges), ``make_delaunay_in`` (the sorted
stack, the four outer edges pushed back), ``ops.carve_exterior_in`` and ``ops.carve_in``
(``containing_triangle``: the smallest canonical triangle whose closure holds the seed).
Where the reference would insert a crossing point or raise (a ``SegmentError``, a segment
it cannot recover) ``recover`` answers ``DECLINED`` and the caller runs the reference ops
from the start.

Where the C data live: in a ``TriangleStore`` (``geomexact/kernel/ctriangulation.pxd``,
the store the Lepp kernel runs on too): the half-edges, the vertices (the doubles of the
``Point2`` for the float filters; the coordinates times ``2**F`` as int64 when the exact
rational is a double on that grid — the *grid* vertices; ``F`` makes the largest finite
coordinate below ``2**60``, so every double in [0, 1) at or above ``2**-8`` is on the
grid; the digest key; the hints), the digest and the step records.  This module keeps its
own loops: the walk, the three attachments, the legalization, segment recovery, the Lawson
pass and carving.

Every geometric decision is exact: orient2d on grid vertices by integer arithmetic in
``__int128`` (differences below 2**61, products below 2**122); incircle on grid vertices
in ``__int128`` when the differences, divided by their common power of two, are below
2**30 (lattices: the cocircular ties); otherwise by the certified float filters of
``geomexact.kernel.predicates2d`` (same formulas and constants, compiled without FMA), falling
back to the exact Python predicate on the ``Point2`` objects.  The shared C pieces are in
``geomexact/kernel/ckernel.h``.
"""

from libc.stdint cimport int64_t, uint64_t, int8_t, uint32_t
from libc.stdlib cimport malloc, free, qsort
from cpython.exc cimport PyErr_CheckSignals
from libc.string cimport memmove, memset
from libc.math cimport frexp, ldexp, fabs, floor, isfinite

import immutables
import numpy as np

from geomexact.kernel import digest as _digest
from geomexact.trace.step import Step

# the triangulation store: its types and store_* steps (names prefixed, see the .pxd)
from geomexact.kernel.ctriangulation cimport *
from geomexact.kernel.triangle_store cimport RecordedStore
# the shared C layer (ckernel.pxd: hash tables, 128-bit digests, filters, step records)
from geomexact.kernel.ckernel cimport *

_init_constants()

cdef StepLayout _STEP_LAYOUT = step_layout(Step)


cdef enum:
    OP_MAKE_TRIANGLE = 0
    OP_ATTACH_IN_TRIANGLE = 1
    OP_ATTACH_IN_EDGE = 2
    OP_ATTACH_OUTSIDE = 3
    OP_FLIP = 4
    OP_CONSTRAIN = 5
    OP_CARVE_EXTERIOR = 6
    OP_CARVE = 7

cdef enum:
    WHERE_INSIDE = 0
    WHERE_EDGE = 1
    WHERE_OUTSIDE = 2

cdef double GRID_BOUND = 1152921504606846976.0  # 2**60

_OP_NAMES = ("make_triangle", "attach_in_triangle", "attach_in_edge", "attach_outside",
             "flip", "constrain", "carve_exterior", "carve")

# what _crossed found walking from a along ab
cdef enum:
    CROSSED_REACHED = 0      # b: the crossed edges are in ``crossed``
    CROSSED_VERTEX = 1       # a vertex on the open segment ab (``stop_vertex``)
    CROSSED_CONSTRAINED = 2  # a constrained edge crosses ab
    CROSSED_LOST = 3         # the walk left the mesh (the Python engine raises)

# the answers of ``recover``
RECOVERED = 0
DECLINED = 1


cdef class Builder(RecordedStore):
    """One ``triangulate_points`` construction: ``run(a, b, c, rest)`` then
    ``finish(start)``; the store, the digests and the step count: :class:`RecordedStore`."""

    cdef Pair *visible
    cdef Py_ssize_t cap_visible
    cdef int64_t last_a, last_b
    cdef int F
    cdef readonly tuple points
    cdef public int64_t grid_vertices
    # the constrained phase (``begin_constrained``): the store's hints are then
    # Transient2's outgoing hints; the constrained edges (min, max) -> marker, the work
    # stacks, the probe (a seed point)
    cdef bint constrained
    cdef bint sealed  # finish* sealed the result and freed the half-edge table
    cdef gx_map segments
    cdef PairStack work, crossed, queue
    cdef Py_ssize_t queue_head
    cdef int64_t stop_vertex
    cdef GridPoint probe
    cdef object probe_point
    cdef list carve_args

    def __dealloc__(self):
        # (the C attributes start zeroed: pointers that __init__ did not reach are NULL;
        # RecordedStore frees the store)
        free(self.visible)
        free(self.work.items)
        free(self.crossed.items)
        free(self.queue.items)
        gx_map_free(&self.segments)

    def __init__(self, points):
        """``points``: the ``Point2`` of every vertex id.  :meth:`begin` gives the digest
        of the mesh of isolated vertices the construction starts from (its vertex hashes
        are :attr:`vertex_hashes`)."""
        cdef Py_ssize_t i, count = len(points)
        cdef TriVertex *vertex
        cdef double largest = 0.0, gx, gy
        cdef int exponent = 0
        cdef uint64_t slots = 64
        self.points = tuple(points)
        # at most 6n - 12 half-edges, at load <= 1/2: no growth on the way
        while slots < 12 * <uint64_t>count + 64:
            slots *= 2
        store_init(&self.store, count, count, slots, 5 * count)
        self.cap_visible = 64
        self.visible = <Pair *>malloc(self.cap_visible * sizeof(Pair))
        if not self.visible:
            raise MemoryError
        for i in range(count):
            point = self.points[i]
            vertex = &self.store.vs[i]
            vertex.at.fx = point[2]
            vertex.at.fy = point[3]
            vertex.key = gx_cached_vertex_key(<uint64_t>i)  # digest.vertex_key, in C
            vertex.hint = -1
            vertex.inside = -1
            vertex.at.grid = 0
            if isfinite(vertex.at.fx) and fabs(vertex.at.fx) > largest:
                largest = fabs(vertex.at.fx)
            if isfinite(vertex.at.fy) and fabs(vertex.at.fy) > largest:
                largest = fabs(vertex.at.fy)
        # the grid 2**-F: |finite coordinate| < 2**(60 - F)
        if largest > 0.0:
            frexp(largest, &exponent)
        self.F = 60 - exponent
        self.grid_vertices = 0
        for i in range(count):
            vertex = &self.store.vs[i]
            if not self._grid_value(vertex.at.fx, &gx) or not self._grid_value(
                    vertex.at.fy, &gy):
                continue
            point = self.points[i]
            # the double is the exact coordinate (mpq == float compares exactly)
            if not (point[0] == vertex.at.fx and point[1] == vertex.at.fy):
                continue
            vertex.at.gx = <int64_t>gx
            vertex.at.gy = <int64_t>gy
            vertex.at.grid = 1
            self.grid_vertices += 1
        self.last_a = self.last_b = -1

    @property
    def vertex_hashes(self):
        """The sum mod 2**128 of ``digest.vertex_hash`` over the vertices: made in C for
        the grid vertices (with 0 <= F <= 62), by the Python function for the others."""
        cdef Py_ssize_t i
        cdef gx_u128 total = 0
        cdef TriVertex *vertex
        vertex_hash = _digest.vertex_hash
        for i in range(self.store.nv):
            vertex = &self.store.vs[i]
            if vertex.at.grid and 0 <= self.F <= 62:
                total += gx_grid_vertex_hash(i, vertex.at.gx, vertex.at.gy, self.F)
            else:
                point = self.points[i]
                total += _to_u128(vertex_hash(i, (point[0], point[1])))
        return _from_u128(total)

    def begin(self, start_digest):
        """Start from the mesh of isolated vertices whose digest is ``start_digest``."""
        self._open()
        self.store.digest = _to_u128(start_digest)

    cdef bint _grid_value(self, double value, double *out) noexcept:
        """True (and ``out`` = value * 2**F, an integer of magnitude <= 2**60) when the
        double is a multiple of 2**-F in range."""
        cdef double scaled
        if not isfinite(value):
            return False
        scaled = ldexp(value, self.F)
        if not (fabs(scaled) <= GRID_BOUND) or floor(scaled) != scaled:
            return False
        if ldexp(scaled, -self.F) != value:  # lost bits (underflow): not exact
            return False
        out[0] = scaled
        return True

    cdef int _open(self) except -1:
        if self.sealed:
            raise RuntimeError("the builder has sealed its result: its tables are freed")
        return 0

    # -- predicates (exact): the store's, on these vertices -------------------------------
    cdef int _orient(self, int64_t a, int64_t b, int64_t c) except -2:
        return store_orient(&self.store, self.points, a, b, c)

    cdef int _incircle(self, int64_t a, int64_t b, int64_t c, int64_t d) except -2:
        return store_incircle(&self.store, self.points, a, b, c, d)

    cdef inline int64_t _get(self, int64_t u, int64_t v) noexcept nogil:
        """apex(u, v), or -1."""
        return store_apex(&self.store, u, v)

    cdef int _record(self, int8_t op, int64_t a, int64_t b, int64_t c,
                     int64_t d) except -1:
        store_record(&self.store, op, a, b, c, d)
        return 0

    # -- the construction -----------------------------------------------------------------
    cdef int _make_triangle(self, int64_t a, int64_t b, int64_t c) except -1:
        if self._orient(a, b, c) == 1:
            store_add(&self.store, a, b, c)
        else:
            store_add(&self.store, a, c, b)
        self._record(OP_MAKE_TRIANGLE, a, b, c, -1)
        self.last_a = a
        self.last_b = b if self._get(a, b) >= 0 else c
        return 0

    cdef inline bint _cross(self, int64_t x, int64_t y, int64_t *abc,
                            int64_t *out) noexcept:
        """Walk across the edge (x, y) of the current triangle: ``abc`` := (y, x, apex) of
        the triangle beyond, True; or, on the hull, ``out`` := (x, y), False."""
        cdef int64_t d = self._get(y, x)
        if d < 0:
            out[0], out[1] = x, y
            return False
        abc[0], abc[1], abc[2] = y, x, d
        return True

    cdef int _locate(self, int64_t p, int64_t *out) except -1:
        """``ReferenceDelaunay.locate`` for vertex p: WHERE_INSIDE (a, b, c), WHERE_EDGE
        (u, v, _) or WHERE_OUTSIDE (u, v, _), the triple in ``out``."""
        cdef int64_t a, b, c
        cdef int64_t abc[3]
        cdef int o0, o1, o2
        abc[0], abc[1] = self.last_a, self.last_b
        abc[2] = self._get(abc[0], abc[1])
        if self._orient(abc[0], abc[1], p) == -1 and not self._cross(abc[0], abc[1], abc, out):
            return WHERE_OUTSIDE
        while True:
            a, b, c = abc[0], abc[1], abc[2]
            o1 = self._orient(b, c, p)
            if o1 == -1:
                if not self._cross(b, c, abc, out):
                    return WHERE_OUTSIDE
                continue
            o2 = self._orient(c, a, p)
            if o2 == -1:
                if not self._cross(c, a, abc, out):
                    return WHERE_OUTSIDE
                continue
            o0 = self._orient(a, b, p)
            if o0 == -1:  # only possible in the first triangle
                if not self._cross(a, b, abc, out):
                    return WHERE_OUTSIDE
                continue
            if o1 == 0:
                out[0], out[1], out[2] = b, c, a
                return WHERE_EDGE
            if o2 == 0:
                out[0], out[1], out[2] = c, a, b
                return WHERE_EDGE
            if o0 == 0:
                out[0], out[1], out[2] = a, b, c
                return WHERE_EDGE
            out[0], out[1], out[2] = a, b, c
            return WHERE_INSIDE

    cdef int _insert(self, int64_t vertex) except -1:
        cdef int64_t found[3]
        cdef int64_t a, b, c, u, v, w, x
        cdef int where = self._locate(vertex, found)
        a, b, c = found[0], found[1], found[2]
        self.store.pending.count = 0
        if where == WHERE_INSIDE:
            store_remove(&self.store, a, b, c)
            store_add(&self.store, a, b, vertex)
            store_add(&self.store, b, c, vertex)
            store_add(&self.store, c, a, vertex)
            self._record(OP_ATTACH_IN_TRIANGLE, vertex, a, b, c)
            push_pair(&self.store.pending, c, a)
            push_pair(&self.store.pending, b, c)
            push_pair(&self.store.pending, a, b)
        elif where == WHERE_EDGE:
            u, v = a, b
            w = self._get(u, v)
            x = self._get(v, u)
            store_split_edge(&self.store, u, v, w, x, vertex)
            if w >= 0:
                push_pair(&self.store.pending, v, w)
                push_pair(&self.store.pending, w, u)
            if x >= 0:
                push_pair(&self.store.pending, u, x)
                push_pair(&self.store.pending, x, v)
            self._record(OP_ATTACH_IN_EDGE, vertex, u, v, -1)
        else:
            self._attach_outside(vertex, a, b)
        self.last_a = vertex
        self.last_b = self.store.pending.items[0].a
        return self._legalize(vertex)

    cdef int _visible(self, Py_ssize_t index, Pair edge) except -1:
        if index >= self.cap_visible:
            grow_array(<void **>&self.visible, &self.cap_visible, sizeof(Pair))
        self.visible[index] = edge
        return 0

    cdef int _attach_outside(self, int64_t vertex, int64_t u, int64_t v) except -1:
        """``ops.attach_outside_in``: the visible run is the edges before (u, v)
        (collected backwards, then reversed), (u, v), the edges after it."""
        cdef Pair edge, swap
        cdef Py_ssize_t before = 0, total, i
        # the edges before (u, v), nearest first, at the front of ``visible``
        store_boundary_step(&self.store, u, v, False, &edge)
        while self._orient(edge.a, edge.b, vertex) == -1:
            self._visible(before, edge)
            before += 1
            store_boundary_step(&self.store, edge.a, edge.b, False, &edge)
        for i in range(before // 2):
            swap = self.visible[i]
            self.visible[i] = self.visible[before - 1 - i]
            self.visible[before - 1 - i] = swap
        total = before
        edge.a, edge.b = u, v
        self._visible(total, edge)
        total += 1
        store_boundary_step(&self.store, u, v, True, &edge)
        while self._orient(edge.a, edge.b, vertex) == -1:
            self._visible(total, edge)
            total += 1
            store_boundary_step(&self.store, edge.a, edge.b, True, &edge)
        for i in range(total):
            store_add(&self.store, self.visible[i].b, self.visible[i].a, vertex)
        self._record(OP_ATTACH_OUTSIDE, vertex, u, v, -1)
        for i in range(total):
            push_pair(&self.store.pending, self.visible[i].b, self.visible[i].a)
        return 0

    cdef int _legalize(self, int64_t vertex) except -1:
        """``BatchTriangulation.legalize_edges``: pop (a, b) with apex(a, b) == vertex; flip when
        the vertex is strictly inside the circle of (a, b, q) across it."""
        cdef int64_t a, b, q
        while pop_pair(&self.store.pending, &a, &b):
            q = self._get(b, a)
            if q < 0 or self._get(a, b) != vertex:
                continue
            if self._incircle(a, b, vertex, q) != 1:
                continue
            store_flip(&self.store, a, b, vertex, q)  # -> (q, vertex, a), (vertex, q, b)
            self._record(OP_FLIP, a, b, -1, -1)
            push_pair(&self.store.pending, q, b)
            push_pair(&self.store.pending, a, q)
        return 0

    # -- the constrained phase: segment recovery, the Lawson pass, carving ------------------
    # The edits below are Transient2's: add_triangle writes the outgoing hints a -> b,
    # b -> c, c -> a; remove_triangle leaves them (a broken hint is repaired when sealing,
    # to the smallest neighbour); the steps are those of ``geomexact.mesh2d.ops``.
    def begin_constrained(self):
        """Enter the constrained phase after ``run``: the hints of the sealed point
        triangulation (broken ones repaired) are the hints that Transient2 edits."""
        self._open()
        if self.constrained:
            raise RuntimeError("the constrained phase has begun already")
        self.constrained = True
        store_repair_hints(&self.store)  # as the sealed point triangulation has them
        if gx_map_alloc(&self.segments, 64) < 0:
            raise MemoryError
        open_pair_stack(&self.work, 64)
        open_pair_stack(&self.crossed, 64)
        open_pair_stack(&self.queue, 64)
        self.carve_args = []

    cdef int _t_flip(self, int64_t u, int64_t v) except -1:
        """ops.flip_in on an edge known to be flippable (the hints as add_triangle writes
        them; the insertion numbers are unused in this phase)."""
        store_flip(&self.store, u, v, self._get(u, v), self._get(v, u))
        self._record(OP_FLIP, u, v, -1, -1)
        return 0

    cdef inline bint _constrained(self, int64_t u, int64_t v) noexcept:
        cdef uint64_t key = gx_edge(u, v) if u < v else gx_edge(v, u)
        return self.segments.keys[gx_map_slot(&self.segments, key)] == key

    cdef int _constrain(self, int64_t a, int64_t b, int64_t marker) except -1:
        """ops.constrain_in on an existing, unconstrained edge."""
        cdef int64_t low = a if a < b else b, high = b if a < b else a
        if gx_map_set(&self.segments, gx_edge(low, high), marker) < 0:
            raise MemoryError
        self.store.digest += _to_u128(_digest.segment_hash(low, high, marker))
        self._record(OP_CONSTRAIN, a, b, marker, -1)
        return 0

    cdef int _on_segment(self, int64_t w, int64_t a, int64_t b) except -1:
        """For w on line ab: 1 when w is on the closed segment ab (``within_box``)."""
        cdef int sign = filtered_dot(&self.store.vs[w].at, &self.store.vs[a].at, &self.store.vs[b].at)
        if sign != 2:
            return sign <= 0
        from geomexact.mesh2d.segments import within_box
        return 1 if within_box(self.points[w], self.points[a], self.points[b]) else 0

    cdef int _crossed(self, int64_t a, int64_t b) except -1:
        """``triangulation._crossed_edges``: the edges crossed by ab walking from a, into
        ``crossed`` as (left of ab, right of ab); or where the walk stopped."""
        cdef int64_t start = self.store.vs[a].hint, first, previous, w, x, left = -1, right = -1, c
        cdef int side, other
        self.crossed.count = 0
        if start < 0 or self._get(a, start) < 0:
            return CROSSED_LOST
        first = start
        while True:  # walk_star: clockwise to the boundary, or all the way round
            previous = self._get(first, a)
            if previous < 0:
                break
            if previous == start:
                first = start
                break
            first = previous
        w = first
        while True:
            x = self._get(a, w)
            if x < 0:
                break
            side = self._orient(a, b, w)
            other = self._orient(a, b, x)
            if side == 0 and self._on_segment(w, a, b):
                self.stop_vertex = w
                return CROSSED_VERTEX
            if other == 0 and self._on_segment(x, a, b):
                self.stop_vertex = x
                return CROSSED_VERTEX
            if side == -1 and other == 1:
                left, right = x, w
                break
            w = x
            if w == first:
                break
        if left < 0:
            return CROSSED_LOST
        while True:
            if self._constrained(left, right):
                return CROSSED_CONSTRAINED
            push_pair(&self.crossed, left, right)
            c = self._get(left, right)
            if c < 0:
                return CROSSED_LOST
            if c == b:
                return CROSSED_REACHED
            side = self._orient(a, b, c)
            if side == 0:
                self.stop_vertex = c
                return CROSSED_VERTEX
            if side == 1:
                left = c
            else:
                right = c

    cdef int _enqueue(self, int64_t u, int64_t v) except -1:
        """Append (u, v) to the FIFO ``queue`` (items ``queue_head`` .. ``count``)."""
        cdef Py_ssize_t live
        if self.queue.count == self.queue.capacity and self.queue_head:
            live = self.queue.count - self.queue_head
            memmove(self.queue.items, self.queue.items + self.queue_head, live * sizeof(Pair))
            self.queue.count = live
            self.queue_head = 0
        push_pair(&self.queue, u, v)
        return 0

    cdef int _flip_out(self, int64_t a, int64_t b) except -1:
        """``triangulation._flip_out``: 0 when ab is an edge now; 1 when the Python engine
        would raise (then the run is declined)."""
        cdef Py_ssize_t i, stalled = 0
        cdef int64_t u, v, w, x
        cdef int sw, sx
        self.queue.count = self.queue_head = 0
        for i in range(self.crossed.count):
            self._enqueue(self.crossed.items[i].a, self.crossed.items[i].b)
        while self.queue_head < self.queue.count:
            u = self.queue.items[self.queue_head].a
            v = self.queue.items[self.queue_head].b
            self.queue_head += 1
            w = self._get(u, v)
            x = self._get(v, u)
            if w < 0 or x < 0:
                return 1
            if self._orient(x, w, u) != 1 or self._orient(w, x, v) != 1:
                self._enqueue(u, v)
                stalled += 1
                if stalled > self.queue.count - self.queue_head + 1:
                    return 1
                continue
            stalled = 0
            self._t_flip(u, v)
            if (w == a and x == b) or (w == b and x == a):
                continue
            sw = self._orient(a, b, w)
            sx = self._orient(a, b, x)
            if sw * sx < 0:
                if sw == 1:
                    self._enqueue(w, x)
                else:
                    self._enqueue(x, w)
        return 0

    cdef int _recover(self, int64_t u, int64_t v, int64_t marker, bint split) except -1:
        """``triangulation._insert_segment`` for one segment: RECOVERED, or DECLINED where
        the Python engine inserts a crossing point or raises."""
        cdef int64_t a, b
        cdef int found
        self.work.count = 0
        push_pair(&self.work, u, v)
        while pop_pair(&self.work, &a, &b):
            if a == b:
                continue
            if self._get(a, b) >= 0 or self._get(b, a) >= 0:
                if not self._constrained(a, b):
                    self._constrain(a, b, marker)
                continue
            found = self._crossed(a, b)
            if found == CROSSED_VERTEX:
                if not split:
                    return DECLINED
                push_pair(&self.work, self.stop_vertex, b)
                push_pair(&self.work, a, self.stop_vertex)
                continue
            if found != CROSSED_REACHED:
                return DECLINED
            if self._flip_out(a, b):
                return DECLINED
            self._constrain(a, b, marker)
        return RECOVERED

    def recover(self, segments, bint split):
        """Recover each ``(u, v, marker)`` of ``segments`` in order (ids in range, markers
        int64): RECOVERED, or DECLINED at the first segment the Python engine must do (a
        crossing point to insert, a SegmentError to raise); the builder is then spent."""
        self._open()
        cdef int64_t u, v, marker
        cdef Py_ssize_t count = 0
        if not self.constrained:
            raise RuntimeError("call begin_constrained first")
        for u, v, marker in segments:
            if not (0 <= u < self.store.nv and 0 <= v < self.store.nv):
                raise IndexError((u, v))
            if self._recover(u, v, marker, split) != RECOVERED:
                return DECLINED
            count += 1
            if not count & 1023:
                PyErr_CheckSignals()
        return RECOVERED

    def lawson(self):
        """``triangulation.make_delaunay_in`` (no triangle attributes yet): returns the
        number of flips."""
        self._open()
        cdef Py_ssize_t i, n = 0, flips = 0
        cdef uint64_t slot = 0, swap
        cdef uint64_t four[4]
        cdef int64_t u, v, w, x
        cdef uint64_t *edges = <uint64_t *>malloc(
            (<Py_ssize_t>self.store.apex.count + 1) * sizeof(uint64_t))
        cdef int j, k
        if edges == NULL:
            raise MemoryError
        try:
            while store_next_halfedge(&self.store, &slot, &u, &v, &w):
                if u < v:
                    edges[n] = gx_edge(u, v)
                    n += 1
                elif self._get(v, u) < 0:
                    edges[n] = gx_edge(v, u)
                    n += 1
            qsort(edges, n, sizeof(uint64_t), store_compare_keys)
            self.store.pending.count = 0
            for i in range(n - 1, -1, -1):
                push_pair(&self.store.pending, <int64_t>(edges[i] >> 32),
                          <int64_t><uint32_t>edges[i])
        finally:
            free(edges)
        while pop_pair(&self.store.pending, &u, &v):
            w = self._get(u, v)
            x = self._get(v, u)
            if w < 0 or x < 0 or self._constrained(u, v):
                continue
            if self._incircle(u, v, w, x) != 1:
                continue
            if self._orient(x, w, u) != 1 or self._orient(w, x, v) != 1:
                continue
            self._t_flip(u, v)
            flips += 1
            four[0] = gx_edge(u, x) if u < x else gx_edge(x, u)
            four[1] = gx_edge(x, v) if x < v else gx_edge(v, x)
            four[2] = gx_edge(v, w) if v < w else gx_edge(w, v)
            four[3] = gx_edge(w, u) if w < u else gx_edge(u, w)
            for j in range(1, 4):  # insertion sort, ascending
                k = j
                while k > 0 and four[k - 1] > four[k]:
                    swap = four[k - 1]
                    four[k - 1] = four[k]
                    four[k] = swap
                    k -= 1
            for j in range(3, -1, -1):  # the smallest on top
                push_pair(&self.store.pending, <int64_t>(four[j] >> 32),
                          <int64_t><uint32_t>four[j])
            if not flips & 4095:
                PyErr_CheckSignals()
        return flips

    cdef Py_ssize_t _flood_remove(self, PairStack *region) except -1:
        """ops._flood from the canonical triangles in ``region`` (distinct), then remove
        them all; returns the number removed."""
        cdef gx_map seen
        cdef Py_ssize_t i = 0, slots = 64
        cdef int64_t a, b, c, e0, e1, w
        cdef int64_t ring[4]
        cdef int k
        cdef Pair canonical
        cdef uint64_t key
        while slots < 4 * region.count + 64:
            slots *= 2
        if gx_map_alloc(&seen, <uint64_t>slots) < 0:
            raise MemoryError
        try:
            for i in range(region.count):
                if gx_map_set(&seen, gx_edge(region.items[i].a, region.items[i].b), 1) < 0:
                    raise MemoryError
            i = 0
            while i < region.count:
                a = region.items[i].a
                b = region.items[i].b
                c = self._get(a, b)
                i += 1
                ring[0], ring[1], ring[2], ring[3] = a, b, c, a
                for k in range(3):
                    e0, e1 = ring[k], ring[k + 1]
                    if self._constrained(e0, e1):
                        continue
                    w = self._get(e1, e0)
                    if w < 0:
                        continue
                    store_canonical(e1, e0, w, &canonical)
                    key = gx_edge(canonical.a, canonical.b)
                    if gx_map_get(&seen, key, 0):
                        continue
                    if gx_map_set(&seen, key, 1) < 0:
                        raise MemoryError
                    push_pair(region, canonical.a, canonical.b)
        finally:
            gx_map_free(&seen)
        for i in range(region.count):
            a = region.items[i].a
            b = region.items[i].b
            store_remove(&self.store, a, b, self._get(a, b))
        return region.count

    def carve_exterior(self):
        """``ops.carve_exterior_in`` when ``exterior_triangles`` is not empty (else
        nothing, no step): returns the number of triangles removed."""
        self._open()
        cdef Py_ssize_t removed
        cdef uint64_t slot = 0
        cdef int64_t u, v, w
        cdef Pair canonical
        cdef PairStack region
        open_pair_stack(&region, 64)
        try:
            while store_next_halfedge(&self.store, &slot, &u, &v, &w):
                if self._get(v, u) >= 0 or self._constrained(u, v):
                    continue
                # one seed per triangle: a triangle may have several boundary edges
                store_canonical(u, v, w, &canonical)
                if not self._first_boundary(canonical.a, canonical.b, u, v):
                    continue
                push_pair(&region, canonical.a, canonical.b)
            removed = self._flood_remove(&region)
        finally:
            free(region.items)
        if removed:
            self._record(OP_CARVE_EXTERIOR, -1, -1, -1, -1)
        return removed

    cdef bint _first_boundary(self, int64_t a, int64_t b, int64_t u, int64_t v) noexcept:
        """For the canonical triangle (a, b, c) and its seeding half-edge (u, v): True when
        (u, v) is the first of its unconstrained boundary half-edges (a, b), (b, c),
        (c, a) — so each triangle is seeded once."""
        cdef int64_t c = self._get(a, b), e0, e1
        cdef int64_t ring[4]
        cdef int k
        ring[0], ring[1], ring[2], ring[3] = a, b, c, a
        for k in range(3):
            e0, e1 = ring[k], ring[k + 1]
            if self._get(e1, e0) < 0 and not self._constrained(e0, e1):
                return e0 == u and e1 == v
        return False

    cdef int _probe_orient(self, int64_t a, int64_t b) except -2:
        """orient2d(points[a], points[b], the probe)."""
        cdef int result = filtered_orient(&self.store.vs[a].at, &self.store.vs[b].at, &self.probe)
        if result != 2:
            return result
        from geomexact.kernel.predicates2d import orient2d_exact
        return int(orient2d_exact(self.points[a], self.points[b], self.probe_point))

    def carve(self, point, args):
        """``ops.carve_in`` at ``point`` (a Point2) when a triangle contains it (the
        smallest canonical one whose closure does, ``ops.containing_triangle``), recording
        ``carve`` with ``args``; returns the number removed, or -1 when no triangle
        contains the point (the seed is ignored, no step)."""
        self._open()
        cdef Py_ssize_t removed
        cdef uint64_t slot = 0
        cdef int64_t a, b, c, ba = -1, bb = -1, bc = -1
        cdef double value
        cdef PairStack region
        self.probe_point = point
        self.probe.fx = point[2]
        self.probe.fy = point[3]
        self.probe.grid = 0
        if (self._grid_value(self.probe.fx, &value)
                and point[0] == self.probe.fx and point[1] == self.probe.fy):
            self.probe.gx = <int64_t>value
            if self._grid_value(self.probe.fy, &value):
                self.probe.gy = <int64_t>value
                self.probe.grid = 1
        while store_next_halfedge(&self.store, &slot, &a, &b, &c):
            if not (a < b and a < c):
                continue
            if ba >= 0 and (a > ba or (a == ba and (b > bb or (b == bb and c >= bc)))):
                continue
            if (self._probe_orient(a, b) != -1 and self._probe_orient(b, c) != -1
                    and self._probe_orient(c, a) != -1):
                ba, bb, bc = a, b, c
        if ba < 0:
            return -1
        open_pair_stack(&region, 64)
        try:
            push_pair(&region, ba, bb)
            removed = self._flood_remove(&region)
        finally:
            free(region.items)
        self.carve_args.append(args)
        self._record(OP_CARVE, len(self.carve_args) - 1, -1, -1, -1)
        return removed

    def finish_constrained(self):
        """(halfedges, hints, segments, triangle count, digest) as ``Transient2.seal``
        makes them after the constrained phase: the half-edges as a (H x 3) int64 array of
        rows (u, v, apex), the outgoing hint of each vertex as an int64 array (-1 for
        none), the segments as an ``immutables.Map``.  A broken hint (its half-edge
        removed) is repaired to the smallest neighbour, or dropped for an isolated
        vertex."""
        cdef uint64_t slot = 0, key
        cdef int64_t marker
        halfedges, hints = self._sealed_arrays()
        segments = {}
        while gx_map_next(&self.segments, &slot, &key, &marker):
            segments[(<int64_t>(key >> 32), <int64_t><uint32_t>key)] = marker
        return (halfedges, hints, immutables.Map(segments), halfedges.shape[0] // 3,
                _from_u128(self.store.digest))

    def run(self, int64_t a, int64_t b, int64_t c, rest):
        """``make_triangle(a, b, c)``, then ``insert`` each vertex of ``rest`` (a sequence
        of ids) in order."""
        self._open()
        cdef int64_t vertex
        cdef Py_ssize_t count
        cdef const int64_t[::1] ids = np.ascontiguousarray(rest, dtype=np.int64)
        for vertex in (a, b, c):
            if not 0 <= vertex < self.store.nv:
                raise IndexError(vertex)
        for count in range(ids.shape[0]):
            if not 0 <= ids[count] < self.store.nv:
                raise IndexError(ids[count])
        self._make_triangle(a, b, c)
        for count in range(ids.shape[0]):
            self._insert(ids[count])
            if not (count + 1) & 4095:
                PyErr_CheckSignals()  # Ctrl-C stops a long run (C loops never check it)

    def finish(self):
        """(halfedges, hints, triangle count, digest) of the result, as
        ``Transient2.seal`` makes them: the half-edges as a (H x 3) int64 array of rows
        (u, v, apex), the outgoing hint of each vertex (-1 for none) as an int64 array."""
        halfedges, hints = self._sealed_arrays()
        return halfedges, hints, halfedges.shape[0] // 3, _from_u128(self.store.digest)

    cdef tuple _sealed_arrays(self):
        """The half-edge rows and the hints as ``Transient2.seal`` leaves them; then the
        half-edge table is freed (only the step records are read after)."""
        self._open()
        store_repair_hints(&self.store)
        halfedges = store_halfedge_rows(&self.store)
        hints = store_hint_array(&self.store)
        self.sealed = True
        store_release_table(&self.store)
        return halfedges, hints

    def steps(self):
        """The recorded steps, as ``Step`` objects."""
        cdef Py_ssize_t i
        cdef StepRecord *record
        cdef object op, args
        names = _OP_NAMES
        result = []
        for i in range(self.store.nrec):
            record = &self.store.records[i]
            op = names[record.op]
            if record.op == OP_FLIP:
                args = (record.a, record.b)
            elif record.op == OP_CARVE_EXTERIOR:
                args = ()
            elif record.op == OP_CARVE:
                args = self.carve_args[record.a]
            elif record.op == OP_ATTACH_IN_TRIANGLE:
                args = (record.a, record.b, record.c, record.d)
            else:
                args = (record.a, record.b, record.c)
            result.append(make_step(Step, &_STEP_LAYOUT, op, args))
        return result

    @property
    def grid(self):
        """(F, number of grid vertices) (for tests)."""
        return self.F, self.grid_vertices

    def vertex_state(self, Py_ssize_t i):
        """(on grid, grid x, grid y) of vertex ``i`` (for tests)."""
        if not 0 <= i < self.store.nv:
            raise IndexError(i)
        return bool(self.store.vs[i].at.grid), self.store.vs[i].at.gx, self.store.vs[i].at.gy


# -- the insertion order's shuffle ------------------------------------------------------
cdef struct _Twister:
    uint32_t mt[624]
    int index


cdef uint32_t _next_word(_Twister *state) noexcept nogil:
    """MT19937's next 32-bit output (Matsumoto & Nishimura), as CPython's random module
    makes it."""
    cdef int k
    cdef uint32_t y
    cdef uint32_t *mt = state.mt
    if state.index >= 624:
        for k in range(624):
            y = (mt[k] & 0x80000000U) | (mt[(k + 1) % 624] & 0x7fffffffU)
            mt[k] = mt[(k + 397) % 624] ^ (y >> 1) ^ (0x9908b0dfU if y & 1 else 0U)
        state.index = 0
    y = mt[state.index]
    state.index += 1
    y ^= y >> 11
    y ^= (y << 7) & 0x9d2c5680U
    y ^= (y << 15) & 0xefc60000U
    y ^= y >> 18
    return y


def shuffled_ids(Py_ssize_t count, seed):
    """``random.Random(seed).shuffle(list(range(count)))`` made in C: the same Mersenne
    Twister state (read from ``random.Random(seed).getstate()``), the same Fisher-Yates
    swaps from the end, the same ``_randbelow`` (the top bits of one 32-bit word,
    rejected until below the bound); ``count`` below 2**31.  A list of ints."""
    import random

    cdef _Twister state
    cdef Py_ssize_t i, j, k
    cdef uint32_t bound
    cdef int64_t swap
    cdef int64_t[::1] view
    if not 0 <= count < 2**31:
        raise ValueError(f"count {count} is outside 0..2**31 - 1")
    version, words, _ = random.Random(seed).getstate()
    if version != 3 or len(words) != 625:
        raise ValueError("not CPython's Mersenne Twister state")
    for k in range(624):
        state.mt[k] = words[k]
    state.index = words[624]
    ids = np.arange(count, dtype=np.int64)
    view = ids
    with nogil:
        for i in range(count - 1, 0, -1):
            bound = <uint32_t>(i + 1)
            k = 32
            while k > 0 and not (bound >> (k - 1)) & 1:  # k = bound.bit_length()
                k -= 1
            while True:
                j = _next_word(&state) >> (32 - k)
                if j < bound:
                    break
            swap = view[i]
            view[i] = view[j]
            view[j] = swap
    return ids


def cell_hash(int64_t a, int64_t b, int64_t c):
    """``geomexact.kernel.digest.cell_hash((a, b, c))`` computed by the kernel (for tests)."""
    return _from_u128(gx_cell_hash(_digest.vertex_key(a), _digest.vertex_key(b),
                                   _digest.vertex_key(c)))
