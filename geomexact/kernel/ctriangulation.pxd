# cython: language_level=3
"""The compiled triangulation store both 2D kernels run on (``cimport`` only: there is no
module of this name at run time).

A :class:`TriangleStore` holds what a triangle mesh under construction is, apart from
the algorithm working on it — the way CGAL separates its triangulation data structure
from the algorithms:

* the vertices (their doubles and exact grid coordinates for the predicates, their digest
  key, their ``outgoing`` hint and a region-membership cache);
* the half-edge table ``(u, v) -> apex`` keyed by ``u << 32 | v``, open addressing with
  linear probing, a half-edge's home slot near its origin's: each vertex gets a rank
  when it first becomes an origin and its half-edges live from slot ``16 * rank`` on, so
  vertices inserted one after another (a biased randomized order walks the plane along
  a curve) share cache lines instead of scattering over the whole table;
* the incremental digest (the sum mod 2**128 of the cell hashes and whatever else the
  caller adds);
* the step records (an op code, up to four ids, the digest after the step);
* a stack of half-edges for legalization.

Its primitive steps: :func:`store_add` (the ops' ``add_triangle``: three half-edges, the
hints a -> b, b -> c, c -> a, the cell hash), :func:`store_remove`,
:func:`store_remove_edge` (the two triangles of an interior edge), :func:`store_flip`
(``ops.flip_in``), :func:`store_split_side` (a triangle split at a new vertex on one of its
edges, as ``ops.bisect_in`` does each side) and the boundary walk.  The kernels keep
only their own loops, rules and bookkeeping (attributes, area sums, queues) on top.
"""

from libc.stdint cimport int64_t, int8_t, uint32_t, uint64_t
from libc.stdlib cimport free, malloc

from geomexact.kernel.ckernel cimport (
    GX_EMPTY,
    GridPoint,
    Pair,
    PairStack,
    _from_u128,
    grow_array,
    gx_cell_hash,
    gx_edge,
    gx_map,
    gx_map_alloc,
    gx_map_free,
    gx_map_next,
    gx_u128,
    incircle_sign,
    open_pair_stack,
    orient_sign,
)


cdef struct TriVertex:
    GridPoint at       # the doubles; gx, gy: the exact coordinates times 2**F, when grid
    uint64_t key       # geomexact.kernel.digest.vertex_key
    int64_t hint       # the outgoing hint, -1 for none
    int64_t rank       # where its half-edges live in the table (above), -1 for none yet
    int8_t inside      # region membership, -1 not known yet (refinement only)


cdef struct StepRecord:
    gx_u128 digest     # the digest after the step
    int64_t a
    int64_t b
    int64_t c
    int64_t d
    int8_t op          # the kernel's own op code


cdef struct TriangleStore:
    TriVertex *vs
    Py_ssize_t nv, cap_v
    gx_map apex        # (u, v) -> apex (store_put, store_apex, store_delete: not gx_map_*)
    int64_t ranks      # the ranks given so far
    gx_u128 digest
    StepRecord *records
    Py_ssize_t nrec, cap_rec
    PairStack pending  # the half-edges to legalize


cdef enum:
    SPREAD_BITS = 4  # 16 slots a rank: about 6 half-edges each, a local load of 3/8


cdef inline int store_init(TriangleStore *s, Py_ssize_t vertices, Py_ssize_t vertex_room,
                           uint64_t slots, Py_ssize_t record_room) except -1:
    """Allocate a store of ``vertices`` vertices (room for ``vertex_room``; their fields
    but ``rank`` are the caller's to fill), a half-edge table of at least ``slots`` slots
    (a power of two; at least 16 a vertex) and room for ``record_room`` records.  A store
    starts zeroed (a Cython object's C fields are): :func:`store_free` releases what this
    reached."""
    cdef Py_ssize_t i
    s.nv = vertices
    s.cap_v = max(1, vertex_room)
    s.vs = <TriVertex *>malloc(s.cap_v * sizeof(TriVertex))
    s.cap_rec = max(64, record_room)
    s.records = <StepRecord *>malloc(s.cap_rec * sizeof(StepRecord))
    if not s.vs or not s.records:
        raise MemoryError
    open_pair_stack(&s.pending, 64)
    while slots < (<uint64_t>vertices << SPREAD_BITS) + 64:
        slots *= 2
    if gx_map_alloc(&s.apex, slots) < 0:
        raise MemoryError
    for i in range(vertices):
        s.vs[i].rank = -1
    s.ranks = 0
    s.nrec = 0
    s.digest = 0
    return 0


cdef inline void store_free(TriangleStore *s) noexcept:
    free(s.vs)
    free(s.records)
    free(s.pending.items)
    gx_map_free(&s.apex)
    s.vs = NULL
    s.records = NULL
    s.pending.items = NULL


cdef inline int store_vertex_room(TriangleStore *s) except -1:
    """Room for one more vertex (``s.vs`` may move), ``s.vs[s.nv]``, with no rank yet."""
    if s.nv == s.cap_v:
        grow_array(<void **>&s.vs, &s.cap_v, sizeof(TriVertex))
    s.vs[s.nv].rank = -1
    return 0


# -- the half-edge table ----------------------------------------------------------------
cdef inline uint64_t store_home(const TriangleStore *s, uint64_t key) noexcept nogil:
    """The home slot of the half-edge ``key`` (its origin has a rank): 16 slots from the
    origin's ``16 * rank``, the destination picking one of them."""
    return ((<uint64_t>s.vs[key >> 32].rank << SPREAD_BITS)
            + ((<uint64_t><uint32_t>key * <uint64_t>0x9E3779B97F4A7C15) >> (64 - SPREAD_BITS))
            ) & s.apex.mask


cdef inline uint64_t store_slot(const TriangleStore *s, uint64_t key) noexcept nogil:
    """The slot of ``key``, or the empty slot where its probe ends."""
    cdef uint64_t i = store_home(s, key)
    while s.apex.keys[i] != GX_EMPTY and s.apex.keys[i] != key:
        i = (i + 1) & s.apex.mask
    return i


cdef inline int64_t store_apex(const TriangleStore *s, int64_t u, int64_t v) noexcept nogil:
    """apex(u, v), or -1."""
    cdef uint64_t key, i
    if s.vs[u].rank < 0:
        return -1
    key = gx_edge(u, v)
    i = store_slot(s, key)
    return s.apex.values[i] if s.apex.keys[i] == key else -1


cdef inline int store_grow(TriangleStore *s) except -1:
    """Double the table (every half-edge moved to its new home)."""
    cdef gx_map old = s.apex
    cdef uint64_t i, j
    if gx_map_alloc(&s.apex, 2 * (old.mask + 1)) < 0:
        s.apex = old
        raise MemoryError
    for i in range(old.mask + 1):
        if old.keys[i] != GX_EMPTY:
            j = store_slot(s, old.keys[i])
            s.apex.keys[j] = old.keys[i]
            s.apex.values[j] = old.values[i]
            s.apex.count += 1
    gx_map_free(&old)
    return 0


cdef inline int store_put(TriangleStore *s, int64_t u, int64_t v, int64_t w) except -1:
    """apex[(u, v)] = w (u gets the next rank if it has none)."""
    cdef uint64_t key = gx_edge(u, v), i
    if s.vs[u].rank < 0:
        s.vs[u].rank = s.ranks
        s.ranks += 1
    while (2 * (s.apex.count + 1) > s.apex.mask + 1
           or (<uint64_t>s.ranks << SPREAD_BITS) > s.apex.mask + 1):
        store_grow(s)
    i = store_slot(s, key)
    if s.apex.keys[i] != key:
        s.apex.keys[i] = key
        s.apex.count += 1
    s.apex.values[i] = w
    return 0


cdef inline void store_delete(TriangleStore *s, int64_t u, int64_t v) noexcept nogil:
    """Remove the half-edge (u, v) if present (backward-shift deletion: every later
    half-edge of the probe run whose home allows it moves into the hole)."""
    cdef uint64_t key, i, j, home, mask = s.apex.mask
    if s.vs[u].rank < 0:
        return
    key = gx_edge(u, v)
    i = store_slot(s, key)
    if s.apex.keys[i] != key:
        return
    j = i
    while True:
        j = (j + 1) & mask
        if s.apex.keys[j] == GX_EMPTY:
            break
        home = store_home(s, s.apex.keys[j])
        # the entry at j may fill the hole at i unless its home lies in (i, j]
        if ((j - home) & mask) >= ((j - i) & mask):
            s.apex.keys[i] = s.apex.keys[j]
            s.apex.values[i] = s.apex.values[j]
            i = j
    s.apex.keys[i] = GX_EMPTY
    s.apex.count -= 1


cdef inline bint store_next_halfedge(const TriangleStore *s, uint64_t *slot, int64_t *u,
                                    int64_t *v, int64_t *w) noexcept nogil:
    """The next live half-edge (u, v) -> w in slot order from ``slot[0]`` (start at 0);
    False at the end."""
    cdef uint64_t key
    cdef int64_t value
    if not gx_map_next(&s.apex, slot, &key, &value):
        return False
    u[0] = <int64_t>(key >> 32)
    v[0] = <int64_t><uint32_t>key
    w[0] = value
    return True


cdef inline gx_u128 store_hash(const TriangleStore *s, int64_t a, int64_t b,
                               int64_t c) noexcept nogil:
    """The cell hash of the triangle (a, b, c), any rotation."""
    cdef TriVertex *vs = s.vs
    if b < a and b < c:
        return gx_cell_hash(vs[b].key, vs[c].key, vs[a].key)
    if c < a and c < b:
        return gx_cell_hash(vs[c].key, vs[a].key, vs[b].key)
    return gx_cell_hash(vs[a].key, vs[b].key, vs[c].key)


cdef inline void store_canonical(int64_t a, int64_t b, int64_t c, Pair *out) noexcept nogil:
    """The first two vertices of canonical_triangle(a, b, c) (the smallest id first)."""
    if a < b and a < c:
        out.a, out.b = a, b
    elif b < c:
        out.a, out.b = b, c
    else:
        out.a, out.b = c, a


cdef inline int store_compare_keys(const void *first, const void *second) noexcept nogil:
    """qsort's order of half-edge keys ``u << 32 | v``: by (u, v)."""
    cdef uint64_t a = (<const uint64_t *>first)[0], b = (<const uint64_t *>second)[0]
    return (a > b) - (a < b)


# -- the primitive steps ----------------------------------------------------------------
cdef inline int store_add(TriangleStore *s, int64_t a, int64_t b, int64_t c) except -1:
    """The ops' ``add_triangle``: the half-edges (a, b) -> c, (b, c) -> a, (c, a) -> b in
    that order, the hints a -> b, b -> c, c -> a, the cell hash."""
    store_put(s, a, b, c)
    store_put(s, b, c, a)
    store_put(s, c, a, b)
    s.vs[a].hint = b
    s.vs[b].hint = c
    s.vs[c].hint = a
    s.digest += store_hash(s, a, b, c)
    return 0


cdef inline void store_remove(TriangleStore *s, int64_t a, int64_t b, int64_t c) noexcept:
    """The ops' ``remove_triangle``: its three half-edges and its cell hash (the hints
    stay; a broken one is repaired when the result is sealed)."""
    store_delete(s, a, b)
    store_delete(s, b, c)
    store_delete(s, c, a)
    s.digest -= store_hash(s, a, b, c)


cdef inline void store_remove_edge(TriangleStore *s, int64_t u, int64_t v, int64_t w,
                                   int64_t x) noexcept:
    """Remove the triangles (u, v, w) and (v, u, x) of the interior edge (u, v): their
    cell hashes and the edge's two half-edges (the caller puts the other four again, with
    new apexes, in place)."""
    store_delete(s, u, v)
    store_delete(s, v, u)
    s.digest -= store_hash(s, u, v, w) + store_hash(s, v, u, x)


cdef inline int store_flip(TriangleStore *s, int64_t u, int64_t v, int64_t w,
                           int64_t x) except -1:
    """``ops.flip_in`` of the interior edge (u, v) with apexes w (left) and x (right):
    (u, v, w), (v, u, x) -> (x, w, u), (w, x, v)."""
    store_remove_edge(s, u, v, w, x)
    store_add(s, x, w, u)
    store_add(s, w, x, v)
    return 0


cdef inline int store_split_side(TriangleStore *s, int64_t p, int64_t q, int64_t r,
                                 int64_t n) except -1:
    """The triangle (p, q, r) split at the new vertex n on its edge (p, q):
    (p, n, r), (n, q, r), as ``ops.bisect_in`` does each side (the half-edges (q, r) and
    (r, p) keep their places with new apexes)."""
    store_delete(s, p, q)
    s.digest -= store_hash(s, p, q, r)
    store_add(s, p, n, r)
    store_add(s, n, q, r)
    return 0


cdef inline int store_split_edge(TriangleStore *s, int64_t u, int64_t v, int64_t w,
                                  int64_t x, int64_t n) except -1:
    """``ops.join_in_edge``: the new vertex n on the edge (u, v) joined to its apexes w
    (left) and x (right), each -1 when that side has no triangle: (u, n, w), (n, v, w)
    and (v, n, x), (n, u, x)."""
    if w >= 0:
        store_split_side(s, u, v, w, n)
    if x >= 0:
        store_split_side(s, v, u, x, n)
    return 0


cdef inline StepRecord *store_record(TriangleStore *s, int8_t op, int64_t a, int64_t b,
                                     int64_t c, int64_t d) except NULL:
    """Append a step record with the digest as it is now."""
    cdef StepRecord *record
    if s.nrec == s.cap_rec:
        grow_array(<void **>&s.records, &s.cap_rec, sizeof(StepRecord))
    record = &s.records[s.nrec]
    record.op = op
    record.a = a
    record.b = b
    record.c = c
    record.d = d
    record.digest = s.digest
    s.nrec += 1
    return record


# -- walks ------------------------------------------------------------------------------
cdef inline int store_boundary_step(const TriangleStore *s, int64_t u, int64_t v,
                                    bint forward, Pair *out) except -1:
    """The boundary half-edge next to the boundary half-edge (u, v), turning about v
    (``forward``: ``next_boundary_edge``, (v, z)) or about u (``previous_boundary_edge``,
    (z, u))."""
    cdef int64_t x = store_apex(s, u, v), y
    while x >= 0:
        y = store_apex(s, x, v) if forward else store_apex(s, u, x)
        if y < 0:
            if forward:
                out.a, out.b = v, x
            else:
                out.a, out.b = x, u
            return 0
        x = y
    raise ValueError(f"({u}, {v}) is not a boundary half-edge")


# -- the exact predicates on the store's vertices ---------------------------------------
cdef inline int store_orient(const TriangleStore *s, object points, int64_t a, int64_t b,
                             int64_t c) except -2:
    """The sign of orient2d(points[a], points[b], points[c])."""
    return orient_sign(&s.vs[a].at, &s.vs[b].at, &s.vs[c].at, points, a, b, c)


cdef inline int store_incircle(const TriangleStore *s, object points, int64_t a,
                               int64_t b, int64_t c, int64_t d) except -2:
    """The sign of incircle(points[a], points[b], points[c], points[d])."""
    return incircle_sign(&s.vs[a].at, &s.vs[b].at, &s.vs[c].at, &s.vs[d].at,
                         points, a, b, c, d)


# -- sealing ----------------------------------------------------------------------------
cdef inline int store_repair_hints(TriangleStore *s) except -1:
    """``Transient2.seal``'s repair: a hint whose half-edge was removed becomes the
    smallest neighbour of its vertex, or -1 for an isolated vertex."""
    cdef Py_ssize_t i
    cdef uint64_t slot = 0
    cdef int64_t u, w, x
    cdef bint broken = False
    cdef TriVertex *vs = s.vs
    cdef int8_t *repair = <int8_t *>malloc(max(1, s.nv) * sizeof(int8_t))
    if repair == NULL:
        raise MemoryError
    for i in range(s.nv):
        repair[i] = 0
        if vs[i].hint >= 0 and store_apex(s, i, vs[i].hint) < 0:
            repair[i] = 1
            vs[i].hint = -1
            broken = True
    while broken and store_next_halfedge(s, &slot, &u, &w, &x):
        if repair[u] and (vs[u].hint < 0 or w < vs[u].hint):
            vs[u].hint = w
    free(repair)
    return 0


cdef inline object store_halfedge_rows(const TriangleStore *s):
    """The half-edge table as a read-only (H x 3) int64 array of rows (u, v, apex), in
    slot order; the loop without a branch a slot (the table is mostly empty, at random):
    each slot's row is written at the next row, which only a live slot's advances, until
    the H rows are filled."""
    import numpy
    cdef uint64_t slot = 0, key
    cdef Py_ssize_t row = 0, count = s.apex.count
    cdef const uint64_t *keys = s.apex.keys
    cdef const int64_t *values = s.apex.values
    cdef int64_t[:, ::1] view
    rows = numpy.empty((count, 3), dtype=numpy.int64)
    view = rows
    while row < count:
        key = keys[slot]
        view[row, 0] = <int64_t>(key >> 32)
        view[row, 1] = <int64_t><uint32_t>key
        view[row, 2] = values[slot]
        row += key != GX_EMPTY
        slot += 1
    rows.setflags(write=False)
    return rows


cdef inline object store_digests(const TriangleStore *s):
    """The digest after each recorded step, as Python ints."""
    cdef Py_ssize_t i
    return [_from_u128(s.records[i].digest) for i in range(s.nrec)]


cdef inline object store_digest_at(const TriangleStore *s, Py_ssize_t i):
    """The digest after step ``i`` (0 <= i < nrec), as a Python int."""
    if not 0 <= i < s.nrec:
        raise IndexError(i)
    return _from_u128(s.records[i].digest)


cdef inline void store_release_table(TriangleStore *s) noexcept:
    """Free the half-edge table once the result is sealed: the vertices and the step
    records stay (a deferred trace reads them)."""
    gx_map_free(&s.apex)  # (the kernels refuse every edit and read of the table after)


cdef inline object store_hint_array(const TriangleStore *s):
    """The vertices' hints as a read-only int64 array (-1 for none)."""
    import numpy
    cdef Py_ssize_t i
    cdef int64_t[::1] view
    hints = numpy.empty(s.nv, dtype=numpy.int64)
    view = hints
    for i in range(s.nv):
        view[i] = s.vs[i].hint
    hints.setflags(write=False)
    return hints
