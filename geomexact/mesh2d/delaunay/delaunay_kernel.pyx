# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, infer_types=False
"""Typed kernel of ``geomexact.mesh2d.delaunay.triangulation.triangulate_points``: the incremental Delaunay
construction of ``BatchDelaunay`` on C data structures.

Contract: :class:`Builder` runs exactly ``BatchDelaunay.make_triangle`` then
``insert`` for every vertex of the given order (visibility walk ``locate``,
``attach_in_triangle`` / ``attach_in_edge`` / ``_attach_outside``, ``legalize_edges`` with Lawson
flips and the tie rule "no flip on cocircular").  It records the same steps, the same
digest after every step, and seals the same ``Mesh2`` — including the ``outgoing`` hints,
which the Python engine takes from the insertion order of its half-edge dict (the last
inserted live half-edge out of each vertex): every half-edge here carries the sequence
number of its insertion, kept when its apex is updated in place, as a dict does.
``geomexact.mesh2d.delaunay.compiled`` is the only caller.

Where the C data live:

* half-edges ``(u, v) -> apex`` in an open-addressing hash table keyed by ``u << 32 | v``
  (ids below ``MAX_VERTICES = 2**32``), the value ``seq << 32 | apex``;
* per vertex: the doubles of the ``Point2`` (for the float filters), the coordinates times
  ``2**F`` as int64 when the exact rational is a double on that grid (the *grid*
  vertices; ``F`` makes the largest finite coordinate below ``2**60``, so every doubles in
  [0, 1) at or above ``2**-8`` is on the grid), the 64-bit digest key;
* the steps as C records (op, ids, the digest as an ``unsigned __int128``).

Every geometric decision is exact: orient2d on grid vertices by integer arithmetic in
``__int128`` (differences below 2**61, products below 2**122); incircle on grid vertices
in ``__int128`` when the differences, divided by their common power of two, are below
2**30 (lattices: the cocircular ties); otherwise by the certified float filters of
``geomexact.kernel.predicates2d`` (same formulas and constants, compiled without FMA), falling
back to the exact Python predicate on the ``Point2`` objects.  The shared C pieces are in
``geomexact/kernel/ckernel.h``.
"""

from libc.stdint cimport int64_t, uint64_t, int8_t
from libc.stdlib cimport malloc, free
from cpython.exc cimport PyErr_CheckSignals
from libc.string cimport memset
from libc.math cimport frexp, ldexp, fabs, floor, isfinite
from cpython.object cimport PyObject_GenericSetAttr

cdef extern from "Python.h":
    void PyObject_GC_UnTrack(void *op)

import immutables

from geomexact.kernel import digest as _digest
from geomexact.trace.step import Step

from geomexact.kernel.ckernel cimport (
    GridPoint,
    Pair,
    PairStack,
    GX_EMPTY,
    _from_u128,
    _init_constants,
    _to_u128,
    gx_cell_hash,
    gx_edge,
    gx_map,
    gx_map_alloc,
    gx_map_del,
    gx_map_free,
    gx_map_get,
    gx_map_grow,
    gx_map_slot,
    gx_u128,
    grow_array,
    incircle_sign,
    orient_sign,
    pop_pair,
    push_pair,
)

_init_constants()


cdef struct Vertex:
    GridPoint at       # the doubles; gx, gy: the exact coordinates times 2**F, when grid
    uint64_t key       # geomexact.kernel.digest.vertex_key

cdef struct Record:
    gx_u128 digest
    int64_t a
    int64_t b
    int64_t c
    int64_t d
    int8_t op

cdef enum:
    OP_MAKE_TRIANGLE = 0
    OP_ATTACH_IN_TRIANGLE = 1
    OP_ATTACH_IN_EDGE = 2
    OP_ATTACH_OUTSIDE = 3
    OP_FLIP = 4

cdef enum:
    WHERE_INSIDE = 0
    WHERE_EDGE = 1
    WHERE_OUTSIDE = 2

cdef int64_t APEX_MASK = 0xFFFFFFFF
cdef int64_t SEQ_LIMIT = (<int64_t>1 << 31) - 1
cdef double GRID_BOUND = 1152921504606846976.0  # 2**60

_OP_NAMES = ("make_triangle", "attach_in_triangle", "attach_in_edge", "attach_outside",
             "flip")


cdef class Builder:
    """One ``triangulate_points`` construction: ``run(a, b, c, rest)`` then
    ``finish(start)``."""

    cdef Vertex *vs
    cdef Py_ssize_t nv
    cdef gx_map apex
    cdef Record *records
    cdef Py_ssize_t nrec, cap_rec
    cdef PairStack pending
    cdef Pair *visible
    cdef Py_ssize_t cap_visible
    cdef gx_u128 digest
    cdef int64_t seq
    cdef int64_t last_a, last_b
    cdef int F
    cdef tuple points
    cdef public int64_t grid_vertices

    def __dealloc__(self):
        # (the C attributes start zeroed: pointers that __init__ did not reach are NULL)
        free(self.vs)
        free(self.records)
        free(self.pending.items)
        free(self.visible)
        gx_map_free(&self.apex)

    def __init__(self, points, start_digest):
        """``points``: the ``Point2`` of every vertex id; ``start_digest``: the digest of the
        mesh of isolated vertices the construction starts from."""
        cdef Py_ssize_t i, count = len(points)
        cdef Vertex *vertex
        cdef double largest = 0.0, gx, gy
        cdef int exponent = 0
        cdef uint64_t slots = 64
        self.points = tuple(points)
        self.nv = count
        self.vs = <Vertex *>malloc(max(1, count) * sizeof(Vertex))
        self.cap_rec = max(64, 5 * count)
        self.records = <Record *>malloc(self.cap_rec * sizeof(Record))
        self.pending.capacity = self.cap_visible = 64
        self.pending.items = <Pair *>malloc(self.pending.capacity * sizeof(Pair))
        self.visible = <Pair *>malloc(self.cap_visible * sizeof(Pair))
        if not self.vs or not self.records or not self.pending.items or not self.visible:
            raise MemoryError
        # at most 6n - 12 half-edges, at load <= 1/2: no growth on the way
        while slots < 12 * <uint64_t>count + 64:
            slots *= 2
        if gx_map_alloc(&self.apex, slots) < 0:
            raise MemoryError
        if count:
            _digest.vertex_key(count - 1)  # extend the cached keys once
        keys = _digest._VERTEX_KEYS
        for i in range(count):
            point = self.points[i]
            vertex = &self.vs[i]
            vertex.at.fx = point[2]
            vertex.at.fy = point[3]
            vertex.key = keys[i]
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
            vertex = &self.vs[i]
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
        self.digest = _to_u128(start_digest)
        self.nrec = 0
        self.pending.count = 0
        self.seq = 0
        self.last_a = self.last_b = -1

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

    # -- predicates (exact): ckernel.pxd's, on these vertices -----------------------------
    cdef int _orient(self, int64_t a, int64_t b, int64_t c) except -2:
        return orient_sign(&self.vs[a].at, &self.vs[b].at, &self.vs[c].at, self.points, a, b, c)

    cdef int _incircle(self, int64_t a, int64_t b, int64_t c, int64_t d) except -2:
        return incircle_sign(&self.vs[a].at, &self.vs[b].at, &self.vs[c].at, &self.vs[d].at,
                             self.points, a, b, c, d)

    # -- the half-edge table --------------------------------------------------------------
    cdef inline int64_t _get(self, int64_t u, int64_t v) noexcept nogil:
        """apex(u, v), or -1."""
        cdef int64_t value = gx_map_get(&self.apex, gx_edge(u, v), -1)
        return value if value < 0 else (value & APEX_MASK)

    cdef int _put(self, int64_t u, int64_t v, int64_t w) except -1:
        """apex[(u, v)] = w as a dict does it: an existing key keeps its place (its
        sequence number), a new one goes last."""
        cdef uint64_t key = gx_edge(u, v)
        cdef uint64_t i = gx_map_slot(&self.apex, key)
        if self.apex.keys[i] == key:
            self.apex.values[i] = (self.apex.values[i] & ~APEX_MASK) | w
            return 0
        if self.seq >= SEQ_LIMIT:
            raise OverflowError("too many half-edge insertions for the kernel")
        if 2 * (self.apex.count + 1) > self.apex.mask + 1:
            if gx_map_grow(&self.apex) < 0:
                raise MemoryError
            i = gx_map_slot(&self.apex, key)
        self.apex.keys[i] = key
        self.apex.values[i] = (self.seq << 32) | w
        self.apex.count += 1
        self.seq += 1
        return 0

    cdef inline gx_u128 _hash(self, int64_t a, int64_t b, int64_t c) noexcept nogil:
        """The cell hash of the triangle (a, b, c), any rotation."""
        if b < a and b < c:
            return gx_cell_hash(self.vs[b].key, self.vs[c].key, self.vs[a].key)
        if c < a and c < b:
            return gx_cell_hash(self.vs[c].key, self.vs[a].key, self.vs[b].key)
        return gx_cell_hash(self.vs[a].key, self.vs[b].key, self.vs[c].key)

    cdef int _add(self, int64_t a, int64_t b, int64_t c) except -1:
        self._put(a, b, c)
        self._put(b, c, a)
        self._put(c, a, b)
        self.digest += self._hash(a, b, c)
        return 0

    cdef void _remove(self, int64_t a, int64_t b, int64_t c) noexcept:
        gx_map_del(&self.apex, gx_edge(a, b))
        gx_map_del(&self.apex, gx_edge(b, c))
        gx_map_del(&self.apex, gx_edge(c, a))
        self.digest -= self._hash(a, b, c)

    cdef int _record(self, int8_t op, int64_t a, int64_t b, int64_t c,
                     int64_t d) except -1:
        cdef Record *record
        if self.nrec == self.cap_rec:
            grow_array(<void **>&self.records, &self.cap_rec, sizeof(Record))
        record = &self.records[self.nrec]
        record.op = op
        record.a = a
        record.b = b
        record.c = c
        record.d = d
        record.digest = self.digest
        self.nrec += 1
        return 0

    # -- the construction -----------------------------------------------------------------
    cdef int _make_triangle(self, int64_t a, int64_t b, int64_t c) except -1:
        if self._orient(a, b, c) == 1:
            self._add(a, b, c)
        else:
            self._add(a, c, b)
        self._record(OP_MAKE_TRIANGLE, a, b, c, -1)
        self.last_a = a
        self.last_b = b if self._get(a, b) >= 0 else c
        return 0

    cdef int _locate(self, int64_t p, int64_t *out) except -1:
        """``BatchDelaunay.locate`` for vertex p: WHERE_INSIDE (a, b, c), WHERE_EDGE
        (u, v, _) or WHERE_OUTSIDE (u, v, _), the triple in ``out``."""
        cdef int64_t a = self.last_a, b = self.last_b, c, d
        cdef int o0, o1, o2
        c = self._get(a, b)
        if self._orient(a, b, p) == -1:
            d = self._get(b, a)
            if d < 0:
                out[0], out[1] = a, b
                return WHERE_OUTSIDE
            a, b, c = b, a, d
        while True:
            o1 = self._orient(b, c, p)
            if o1 == -1:
                d = self._get(c, b)
                if d < 0:
                    out[0], out[1] = b, c
                    return WHERE_OUTSIDE
                a, b, c = c, b, d
                continue
            o2 = self._orient(c, a, p)
            if o2 == -1:
                d = self._get(a, c)
                if d < 0:
                    out[0], out[1] = c, a
                    return WHERE_OUTSIDE
                a, b, c = a, c, d
                continue
            o0 = self._orient(a, b, p)
            if o0 == -1:  # only possible in the first triangle
                d = self._get(b, a)
                if d < 0:
                    out[0], out[1] = a, b
                    return WHERE_OUTSIDE
                a, b, c = b, a, d
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
        self.pending.count = 0
        if where == WHERE_INSIDE:
            self._remove(a, b, c)
            self._add(a, b, vertex)
            self._add(b, c, vertex)
            self._add(c, a, vertex)
            self._record(OP_ATTACH_IN_TRIANGLE, vertex, a, b, c)
            push_pair(&self.pending, c, a)
            push_pair(&self.pending, b, c)
            push_pair(&self.pending, a, b)
        elif where == WHERE_EDGE:
            u, v = a, b
            w = self._get(u, v)
            x = self._get(v, u)
            if w >= 0:
                self._remove(u, v, w)
                self._add(u, vertex, w)
                self._add(vertex, v, w)
                push_pair(&self.pending, v, w)
                push_pair(&self.pending, w, u)
            if x >= 0:
                self._remove(v, u, x)
                self._add(v, vertex, x)
                self._add(vertex, u, x)
                push_pair(&self.pending, u, x)
                push_pair(&self.pending, x, v)
            self._record(OP_ATTACH_IN_EDGE, vertex, u, v, -1)
        else:
            self._attach_outside(vertex, a, b)
        self.last_a = vertex
        self.last_b = self.pending.items[0].a
        return self._legalize(vertex)

    cdef int _next_boundary(self, int64_t u, int64_t v, Pair *out) except -1:
        """``next_boundary_edge``: the boundary half-edge (v, z) after (u, v)."""
        cdef int64_t x = self._get(u, v), y
        while x >= 0:
            y = self._get(x, v)
            if y < 0:
                out.a, out.b = v, x
                return 0
            x = y
        raise ValueError(f"({u}, {v}) is not a boundary half-edge")

    cdef int _previous_boundary(self, int64_t u, int64_t v, Pair *out) except -1:
        """``previous_boundary_edge``: the boundary half-edge (z, u) before (u, v)."""
        cdef int64_t x = self._get(u, v), y
        while x >= 0:
            y = self._get(u, x)
            if y < 0:
                out.a, out.b = x, u
                return 0
            x = y
        raise ValueError(f"({u}, {v}) is not a boundary half-edge")

    cdef int _visible(self, Py_ssize_t index, Pair edge) except -1:
        if index >= self.cap_visible:
            grow_array(<void **>&self.visible, &self.cap_visible, sizeof(Pair))
        self.visible[index] = edge
        return 0

    cdef int _attach_outside(self, int64_t vertex, int64_t u, int64_t v) except -1:
        """``BatchDelaunay._attach_outside``: the visible run is the edges before (u, v)
        (collected backwards, then reversed), (u, v), the edges after it."""
        cdef Pair edge, swap
        cdef Py_ssize_t before = 0, total, i
        # the edges before (u, v), nearest first, at the front of ``visible``
        self._previous_boundary(u, v, &edge)
        while self._orient(edge.a, edge.b, vertex) == -1:
            self._visible(before, edge)
            before += 1
            self._previous_boundary(edge.a, edge.b, &edge)
        for i in range(before // 2):
            swap = self.visible[i]
            self.visible[i] = self.visible[before - 1 - i]
            self.visible[before - 1 - i] = swap
        total = before
        edge.a, edge.b = u, v
        self._visible(total, edge)
        total += 1
        self._next_boundary(u, v, &edge)
        while self._orient(edge.a, edge.b, vertex) == -1:
            self._visible(total, edge)
            total += 1
            self._next_boundary(edge.a, edge.b, &edge)
        for i in range(total):
            self._add(self.visible[i].b, self.visible[i].a, vertex)
        self._record(OP_ATTACH_OUTSIDE, vertex, u, v, -1)
        for i in range(total):
            push_pair(&self.pending, self.visible[i].b, self.visible[i].a)
        return 0

    cdef int _legalize(self, int64_t vertex) except -1:
        """``BatchTriangulation.legalize_edges``: pop (a, b) with apex(a, b) == vertex; flip when
        the vertex is strictly inside the circle of (a, b, q) across it."""
        cdef int64_t a, b, q
        while pop_pair(&self.pending, &a, &b):
            q = self._get(b, a)
            if q < 0 or self._get(a, b) != vertex:
                continue
            if self._incircle(a, b, vertex, q) != 1:
                continue
            # (a, b, vertex), (b, a, q) -> (q, vertex, a), (vertex, q, b)
            gx_map_del(&self.apex, gx_edge(a, b))
            gx_map_del(&self.apex, gx_edge(b, a))
            self._put(q, vertex, a)
            self._put(vertex, a, q)
            self._put(a, q, vertex)
            self._put(vertex, q, b)
            self._put(q, b, vertex)
            self._put(b, vertex, q)
            self.digest += self._hash(q, vertex, a) + self._hash(vertex, q, b)
            self.digest -= self._hash(a, b, vertex) + self._hash(b, a, q)
            self._record(OP_FLIP, a, b, -1, -1)
            push_pair(&self.pending, q, b)
            push_pair(&self.pending, a, q)
        return 0

    def run(self, int64_t a, int64_t b, int64_t c, rest):
        """``make_triangle(a, b, c)``, then ``insert`` each vertex of ``rest`` in order."""
        cdef int64_t vertex
        for vertex in (a, b, c):
            if not 0 <= vertex < self.nv:
                raise IndexError(vertex)
        self._make_triangle(a, b, c)
        for count, item in enumerate(rest, 1):
            vertex = item
            if not 0 <= vertex < self.nv:
                raise IndexError(vertex)
            self._insert(vertex)
            if not count & 4095:
                PyErr_CheckSignals()  # Ctrl-C stops a long run (C loops never check it)

    def finish(self):
        """(halfedges, outgoing, triangle count, digest) of the result, as
        ``BatchDelaunay.seal`` makes them: the half-edge map, the outgoing hints (the
        last inserted live half-edge out of each vertex) as ``immutables.Map``s."""
        cdef Py_ssize_t i, slots = self.apex.mask + 1
        cdef uint64_t key
        cdef int64_t u, value, seq
        cdef int64_t *best = <int64_t *>malloc(max(1, self.nv) * sizeof(int64_t))
        cdef int64_t *hint = <int64_t *>malloc(max(1, self.nv) * sizeof(int64_t))
        if not best or not hint:
            free(best)
            free(hint)
            raise MemoryError
        try:
            for i in range(self.nv):
                best[i] = -1
                hint[i] = -1
            halfedges = {}
            for i in range(slots):
                key = self.apex.keys[i]
                if key == GX_EMPTY:
                    continue
                u = <int64_t>(key >> 32)
                value = self.apex.values[i]
                seq = value >> 32
                edge = (u, <int64_t>(key & 0xFFFFFFFF))
                # a tuple of ints is in no cycle: untracked now rather than by the first
                # collection after the run (CPython's own lazy untracking of tuples)
                PyObject_GC_UnTrack(<void *>edge)
                halfedges[edge] = value & APEX_MASK
                if seq > best[u]:
                    best[u] = seq
                    hint[u] = <int64_t>(key & 0xFFFFFFFF)
            outgoing = {}
            for i in range(self.nv):
                if hint[i] >= 0:
                    outgoing[i] = hint[i]
        finally:
            free(best)
            free(hint)
        count = len(halfedges) // 3
        return (immutables.Map(halfedges), immutables.Map(outgoing), count,
                _from_u128(self.digest))

    def steps(self):
        """The recorded steps, as ``Step`` objects."""
        cdef Py_ssize_t i
        cdef Record *record
        cdef object op, args
        names = _OP_NAMES
        new = Step.__new__
        op_name = "op"
        args_name = "args"
        result = []
        for i in range(self.nrec):
            record = &self.records[i]
            op = names[record.op]
            if record.op == OP_FLIP:
                args = (record.a, record.b)
            elif record.op == OP_ATTACH_IN_TRIANGLE:
                args = (record.a, record.b, record.c, record.d)
            else:
                args = (record.a, record.b, record.c)
            # Step(op, args) without the attrs __init__ (args is a tuple already): the
            # slots set as attrs' own frozen __init__ sets them
            step = new(Step)
            PyObject_GenericSetAttr(step, op_name, op)
            PyObject_GenericSetAttr(step, args_name, args)
            # a step (a str and a tuple of ints, frozen) is in no cycle: no need for the
            # cyclic collector to scan the run's hundreds of thousands of them
            PyObject_GC_UnTrack(<void *>args)
            PyObject_GC_UnTrack(<void *>step)
            result.append(step)
        return result

    def digests(self):
        """The digest after each recorded step."""
        cdef Py_ssize_t i
        return [_from_u128(self.records[i].digest) for i in range(self.nrec)]

    @property
    def grid(self):
        """(F, number of grid vertices) (for tests)."""
        return self.F, self.grid_vertices

    def vertex_state(self, Py_ssize_t i):
        """(on grid, grid x, grid y) of vertex ``i`` (for tests)."""
        if not 0 <= i < self.nv:
            raise IndexError(i)
        return bool(self.vs[i].at.grid), self.vs[i].at.gx, self.vs[i].at.gy


def cell_hash(int64_t a, int64_t b, int64_t c):
    """``geomexact.kernel.digest.cell_hash((a, b, c))`` computed by the kernel (for tests)."""
    return _from_u128(gx_cell_hash(_digest.vertex_key(a), _digest.vertex_key(b),
                                   _digest.vertex_key(c)))
