# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, infer_types=False
"""Typed kernel of the cuboid partition, its improvement and its census row.

Contract: :func:`run_pattern` and :func:`census_rows` do exactly what
``geomexact.mesh3d.cuboid.partition.partition_cuboid`` (the splits, in the given order,
of the given corner segments, from the given template) and
``geomexact.mesh3d.cuboid.improvement.improve_in`` (the FIFO queue of sorted faces, the
pending set, the rounds) do, with the same classification as
``geomexact.mesh3d.ops.classify_face_in``: the same tetrahedra, the same steps and the
same census row (``geomexact.mesh3d.cuboid.census.census_row``).  The caller
(``geomexact.mesh3d.cuboid.compiled``) gives the box as integer corner coordinates on
which every Steiner point is an integer point (the box translated to the origin and
scaled by a positive factor: orient3d and insphere keep their signs), each below
``MAX_COORDINATE``.

Exactness: every coordinate lies in [0, M], M = MAX_COORDINATE = 2**20, so a difference
is at most 2**20 in absolute value.  orient3d's determinant is six products of three
differences: below 6 * 2**60 < 2**63 (int64).  In insphere the 2x2 minors are below 2**41,
the 3x3 ones below 3 * 2**61 < 2**63 (int64), the lifted terms below 3 * 2**40, and the
determinant (four products of the two) below 2**107, computed in __int128.

Data: at most 26 vertices (8 corners, 18 Steiner points); the face table is an array
indexed by the oriented face (rotated to start at its smallest id) ``a*676 + b*26 + c``
holding the apex or -1; tetrahedra live in slots reused through a free list.
"""

from libc.stdint cimport int64_t, uint8_t, uint64_t
from libc.string cimport memcpy, memset
from libc.stdlib cimport malloc, free, qsort

from geomexact.kernel.ckernel cimport (
    _to_u128,
    gx_blake2b_vertex_message,
    gx_cached_vertex_key,
    gx_u128,
    gx_u128_hi,
    gx_u128_lo,
)

MAX_COORDINATE = 1 << 20

DEF MAXV = 26
DEF NF = 17576          # 26 ** 3
DEF MAXT = 1024
DEF MAXSTEPS = 8192
DEF QCAP = 32768

# kinds, in the order of geomexact.mesh3d.ops.FaceKind
DEF K_T23 = 0
DEF K_T32 = 1
DEF K_T22 = 2
DEF K_T44 = 3
DEF K_N32 = 4
DEF K_N44 = 5
DEF K_N40 = 6
DEF K_N30 = 7
DEF K_N20 = 8

# step ops
DEF OP_SPLIT = 0
DEF OP_FLIP23 = 1
DEF OP_FLIP32 = 2
DEF OP_FLIP22 = 3
DEF OP_FLIP44 = 4

cdef extern from *:
    """
    typedef __int128 cuboid_i128;
    """
    ctypedef long long cuboid_i128


ctypedef struct Mesh:
    int nv
    int64_t X[MAXV]
    int64_t Y[MAXV]
    int64_t Z[MAXV]
    int slots
    int count
    int tet[MAXT][4]
    char alive[MAXT]
    int free_slots[MAXT]
    int nfree
    signed char apex[NF]
    int nsteps
    int step_op[MAXSTEPS]
    int step_arg[MAXSTEPS][3]
    int error


ctypedef struct Config:
    int kind
    int a, b, c, d, e
    int u, v     # the edge that matters (T32/N32/N40 beyond, T22/T44/N44 across), or -1
    int f        # T44's common apex, or -1


cdef inline int face_code(int a, int b, int c) noexcept nogil:
    """The oriented face abc rotated to start at its smallest id, as an index."""
    if a < b and a < c:
        return a * 676 + b * 26 + c
    if b < c:
        return b * 676 + c * 26 + a
    return c * 676 + a * 26 + b


cdef inline int get_apex(Mesh *m, int a, int b, int c) noexcept nogil:
    return m.apex[face_code(a, b, c)]


cdef inline int orient(Mesh *m, int a, int b, int c, int d) noexcept nogil:
    """The sign of det[b - a, c - a, d - a] (orient3d of geomexact)."""
    cdef int64_t bx = m.X[b] - m.X[a], by = m.Y[b] - m.Y[a], bz = m.Z[b] - m.Z[a]
    cdef int64_t cx = m.X[c] - m.X[a], cy = m.Y[c] - m.Y[a], cz = m.Z[c] - m.Z[a]
    cdef int64_t dx = m.X[d] - m.X[a], dy = m.Y[d] - m.Y[a], dz = m.Z[d] - m.Z[a]
    cdef int64_t det = (bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx)
                        + bz * (cx * dy - cy * dx))
    return (det > 0) - (det < 0)


cdef inline int64_t volume6(Mesh *m, int a, int b, int c, int d) noexcept nogil:
    cdef int64_t bx = m.X[b] - m.X[a], by = m.Y[b] - m.Y[a], bz = m.Z[b] - m.Z[a]
    cdef int64_t cx = m.X[c] - m.X[a], cy = m.Y[c] - m.Y[a], cz = m.Z[c] - m.Z[a]
    cdef int64_t dx = m.X[d] - m.X[a], dy = m.Y[d] - m.Y[a], dz = m.Z[d] - m.Z[a]
    return (bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx)
            + bz * (cx * dy - cy * dx))


cdef inline int insphere(Mesh *m, int a, int b, int c, int d, int e) noexcept nogil:
    """The sign of geomexact's insphere(a, b, c, d, e): > 0 when e is strictly inside the
    sphere of the positive tetrahedron abcd (the formula of insphere_exact)."""
    cdef int64_t aex = m.X[a] - m.X[e], aey = m.Y[a] - m.Y[e], aez = m.Z[a] - m.Z[e]
    cdef int64_t bex = m.X[b] - m.X[e], bey = m.Y[b] - m.Y[e], bez = m.Z[b] - m.Z[e]
    cdef int64_t cex = m.X[c] - m.X[e], cey = m.Y[c] - m.Y[e], cez = m.Z[c] - m.Z[e]
    cdef int64_t dex = m.X[d] - m.X[e], dey = m.Y[d] - m.Y[e], dez = m.Z[d] - m.Z[e]
    cdef int64_t ab = aex * bey - bex * aey
    cdef int64_t bc = bex * cey - cex * bey
    cdef int64_t cd = cex * dey - dex * cey
    cdef int64_t da = dex * aey - aex * dey
    cdef int64_t ac = aex * cey - cex * aey
    cdef int64_t bd = bex * dey - dex * bey
    cdef int64_t abc = aez * bc - bez * ac + cez * ab
    cdef int64_t bcd = bez * cd - cez * bd + dez * bc
    cdef int64_t cda = cez * da + dez * ac + aez * cd
    cdef int64_t dab = dez * ab + aez * bd + bez * da
    cdef int64_t alift = aex * aex + aey * aey + aez * aez
    cdef int64_t blift = bex * bex + bey * bey + bez * bez
    cdef int64_t clift = cex * cex + cey * cey + cez * cez
    cdef int64_t dlift = dex * dex + dey * dey + dez * dez
    cdef cuboid_i128 det = (<cuboid_i128> clift * dab - <cuboid_i128> dlift * abc) + (
        <cuboid_i128> alift * bcd - <cuboid_i128> blift * cda)
    return (det > 0) - (det < 0)


cdef void reset(Mesh *m) noexcept nogil:
    m.nv = 0
    m.slots = 0
    m.count = 0
    m.nfree = 0
    m.nsteps = 0
    m.error = 0
    memset(m.apex, -1, NF)


cdef int add_vertex(Mesh *m, int64_t x, int64_t y, int64_t z) noexcept nogil:
    cdef int n = m.nv
    m.X[n] = x
    m.Y[n] = y
    m.Z[n] = z
    m.nv = n + 1
    return n


cdef void add_tet(Mesh *m, int a, int b, int c, int d) noexcept nogil:
    """Add the positive tetrahedron abcd (its four faces as in tetrahedron_faces)."""
    cdef int f0 = face_code(a, b, c), f1 = face_code(a, c, d)
    cdef int f2 = face_code(a, d, b), f3 = face_code(b, d, c)
    cdef int slot
    if m.apex[f0] >= 0 or m.apex[f1] >= 0 or m.apex[f2] >= 0 or m.apex[f3] >= 0:
        m.error = 1
        return
    if m.nfree > 0:
        m.nfree -= 1
        slot = m.free_slots[m.nfree]
    else:
        if m.slots >= MAXT:
            m.error = 2
            return
        slot = m.slots
        m.slots += 1
    m.apex[f0] = d
    m.apex[f1] = b
    m.apex[f2] = c
    m.apex[f3] = a
    m.tet[slot][0] = a
    m.tet[slot][1] = b
    m.tet[slot][2] = c
    m.tet[slot][3] = d
    m.alive[slot] = 1
    m.count += 1


cdef void remove_slot(Mesh *m, int slot) noexcept nogil:
    cdef int a = m.tet[slot][0], b = m.tet[slot][1], c = m.tet[slot][2], d = m.tet[slot][3]
    m.apex[face_code(a, b, c)] = -1
    m.apex[face_code(a, c, d)] = -1
    m.apex[face_code(a, d, b)] = -1
    m.apex[face_code(b, d, c)] = -1
    m.alive[slot] = 0
    m.free_slots[m.nfree] = slot
    m.nfree += 1
    m.count -= 1


cdef inline int has_vertex(Mesh *m, int slot, int v) noexcept nogil:
    return (m.tet[slot][0] == v or m.tet[slot][1] == v or m.tet[slot][2] == v
            or m.tet[slot][3] == v)


cdef int around_edge(Mesh *m, int u, int v, int *out) noexcept nogil:
    """The slots of the tetrahedra containing u and v; returns their number."""
    cdef int slot, n = 0
    for slot in range(m.slots):
        if m.alive[slot] and has_vertex(m, slot, u) and has_vertex(m, slot, v):
            out[n] = slot
            n += 1
    return n


cdef void record(Mesh *m, int op, int x, int y, int z) noexcept nogil:
    if m.nsteps >= MAXSTEPS:
        m.error = 3
        return
    m.step_op[m.nsteps] = op
    m.step_arg[m.nsteps][0] = x
    m.step_arg[m.nsteps][1] = y
    m.step_arg[m.nsteps][2] = z
    m.nsteps += 1


cdef void split_edge(Mesh *m, int u, int v) noexcept nogil:
    """split_tetra_in: the midpoint n of {u, v}; each tetrahedron T on the edge becomes T
    with the higher vertex replaced by n and T with the lower one replaced by n."""
    cdef int slots[MAXT]
    cdef int quads[MAXT][4]
    cdef int k, i, count, low = u if u < v else v, high = v if u < v else u
    count = around_edge(m, low, high, slots)
    if count == 0:
        m.error = 4
        return
    cdef int n = add_vertex(m, (m.X[low] + m.X[high]) // 2, (m.Y[low] + m.Y[high]) // 2,
                            (m.Z[low] + m.Z[high]) // 2)
    for k in range(count):
        for i in range(4):
            quads[k][i] = m.tet[slots[k]][i]
        remove_slot(m, slots[k])
    for k in range(count):
        add_tet(m, quads[k][0] if quads[k][0] != high else n,
                quads[k][1] if quads[k][1] != high else n,
                quads[k][2] if quads[k][2] != high else n,
                quads[k][3] if quads[k][3] != high else n)
        add_tet(m, quads[k][0] if quads[k][0] != low else n,
                quads[k][1] if quads[k][1] != low else n,
                quads[k][2] if quads[k][2] != low else n,
                quads[k][3] if quads[k][3] != low else n)
    record(m, OP_SPLIT, low, high, -1)


cdef inline int third_of(int a, int b, int c, int u, int v) noexcept nogil:
    if a != u and a != v:
        return a
    if b != u and b != v:
        return b
    return c


cdef int is_boundary_face(Mesh *m, int x, int y, int z) noexcept nogil:
    return (get_apex(m, x, y, z) < 0) != (get_apex(m, x, z, y) < 0)


cdef inline int pair_is(int *pair, int x, int y) noexcept nogil:
    return (pair[0] == x and pair[1] == y) or (pair[0] == y and pair[1] == x)


cdef void classify(Mesh *m, int a, int b, int c, Config *out) noexcept nogil:
    """classify_face_in of the interior face {a < b < c}."""
    cdef int d = get_apex(m, a, b, c), e = get_apex(m, a, c, b)
    cdef int s[3]
    cdef int eu[3]
    cdef int ev[3]
    cdef int zeros = 0, negatives = 0, zero_at = -1, negative_at = -1, i, count, slot
    cdef int slots[MAXT]
    cdef int u, v, w, f, k, j, x, others, ok
    cdef int pair[2][2]
    out.a = a
    out.b = b
    out.c = c
    out.d = d
    out.e = e
    out.u = -1
    out.v = -1
    out.f = -1
    eu[0] = a; ev[0] = b
    eu[1] = b; ev[1] = c
    eu[2] = c; ev[2] = a
    for i in range(3):
        s[i] = -orient(m, d, e, eu[i], ev[i])
        if s[i] == 0:
            zeros += 1
            if zero_at < 0:
                zero_at = i
        elif s[i] < 0:
            negatives += 1
            if negative_at < 0:
                negative_at = i
    if zeros == 0 and negatives == 0:
        out.kind = K_T23
        return
    if zeros == 2:
        out.kind = K_N30
        return
    if zeros == 0 and negatives == 2:
        out.kind = K_N20
        return
    if zeros == 1 and negatives > 0:
        u = eu[zero_at]
        v = ev[zero_at]
        out.u = u if u < v else v
        out.v = v if u < v else u
        out.kind = K_N40
        return
    if zeros == 0:  # one reflex edge
        u = eu[negative_at]
        v = ev[negative_at]
        out.u = u if u < v else v
        out.v = v if u < v else u
        count = around_edge(m, u, v, slots)
        out.kind = K_N32
        if count == 3:
            for k in range(3):
                if has_vertex(m, slots[k], d) and has_vertex(m, slots[k], e):
                    out.kind = K_T32
        return
    u = eu[zero_at]
    v = ev[zero_at]
    out.u = u if u < v else v
    out.v = v if u < v else u
    count = around_edge(m, u, v, slots)
    if count == 2 and is_boundary_face(m, u, v, d) and is_boundary_face(m, u, v, e):
        out.kind = K_T22
        return
    if count == 4:
        w = third_of(a, b, c, u, v)
        others = 0
        for k in range(4):
            slot = slots[k]
            if has_vertex(m, slot, w):
                continue
            if others >= 2:
                others = 3
                break
            j = 0
            for i in range(4):
                x = m.tet[slot][i]
                if x != u and x != v and j < 2:
                    pair[others][j] = x
                    j += 1
            others += 1
        if others == 2:
            f = -1
            ok = 1
            for k in range(2):
                for i in range(2):
                    x = pair[k][i]
                    if x != d and x != e:
                        if f < 0:
                            f = x
                        elif f != x:
                            ok = 0
            if ok and f >= 0 and (pair_is(pair[0], d, f) or pair_is(pair[1], d, f)) and (
                    pair_is(pair[0], e, f) or pair_is(pair[1], e, f)):
                out.kind = K_T44
                out.f = f
                return
    out.kind = K_N44


cdef void add_oriented(Mesh *m, int a, int b, int c, int d) noexcept nogil:
    """Add (a, b, c, d) or (b, a, c, d), whichever is positive (flip's _oriented)."""
    cdef int o = orient(m, a, b, c, d)
    if o > 0:
        add_tet(m, a, b, c, d)
    elif o < 0:
        add_tet(m, b, a, c, d)
    else:
        m.error = 5


cdef int find_slot(Mesh *m, int *slots, int count, int p, int q, int r, int s) noexcept nogil:
    cdef int k
    for k in range(count):
        if (has_vertex(m, slots[k], p) and has_vertex(m, slots[k], q)
                and has_vertex(m, slots[k], r) and has_vertex(m, slots[k], s)):
            return slots[k]
    return -1


cdef int apply_flip(Mesh *m, Config *cf, int *new_tets) noexcept nogil:
    """flip_in for the configuration ``cf`` (already classified); writes the vertex sets of
    the new tetrahedra into new_tets (4 ints each) and returns their number."""
    cdef int a = cf.a, b = cf.b, c = cf.c, d = cf.d, e = cf.e
    cdef int slots[MAXT]
    cdef int count, k, w, n = 0, slot, op
    cdef int apexes[2]
    cdef int napex
    if cf.kind == K_T23:
        remove_slot(m, find_slot_face(m, a, b, c, d))
        remove_slot(m, find_slot_face(m, a, c, b, e))
        add_oriented(m, d, e, a, b)
        add_oriented(m, d, e, b, c)
        add_oriented(m, d, e, c, a)
        new_tets[0] = d; new_tets[1] = e; new_tets[2] = a; new_tets[3] = b
        new_tets[4] = d; new_tets[5] = e; new_tets[6] = b; new_tets[7] = c
        new_tets[8] = d; new_tets[9] = e; new_tets[10] = c; new_tets[11] = a
        record(m, OP_FLIP23, a, b, c)
        return 3
    w = third_of(a, b, c, cf.u, cf.v)
    count = around_edge(m, cf.u, cf.v, slots)
    if cf.kind == K_T32:
        slot = find_slot(m, slots, count, cf.u, cf.v, d, e)
        remove_slot(m, find_slot_face(m, a, b, c, d))
        remove_slot(m, find_slot_face(m, a, c, b, e))
        remove_slot(m, slot)
        apexes[0] = w
        napex = 1
        op = OP_FLIP32
    else:
        for k in range(count):
            remove_slot(m, slots[k])
        apexes[0] = w
        apexes[1] = cf.f
        napex = 1 if cf.kind == K_T22 else 2
        op = OP_FLIP22 if cf.kind == K_T22 else OP_FLIP44
    for k in range(napex):
        if cf.kind == K_T32:
            add_oriented(m, apexes[k], d, e, cf.u)
            add_oriented(m, apexes[k], d, e, cf.v)
        else:
            add_oriented(m, d, e, apexes[k], cf.u)
            add_oriented(m, d, e, apexes[k], cf.v)
        new_tets[n * 4 + 0] = d; new_tets[n * 4 + 1] = e
        new_tets[n * 4 + 2] = apexes[k]; new_tets[n * 4 + 3] = cf.u
        n += 1
        new_tets[n * 4 + 0] = d; new_tets[n * 4 + 1] = e
        new_tets[n * 4 + 2] = apexes[k]; new_tets[n * 4 + 3] = cf.v
        n += 1
    record(m, op, a, b, c)
    return n


cdef int find_slot_face(Mesh *m, int a, int b, int c, int d) noexcept nogil:
    """The slot of the tetrahedron whose vertices are a, b, c, d."""
    cdef int slot
    for slot in range(m.slots):
        if (m.alive[slot] and has_vertex(m, slot, a) and has_vertex(m, slot, b)
                and has_vertex(m, slot, c) and has_vertex(m, slot, d)):
            return slot
    m.error = 6
    return 0


cdef inline int sorted_code(int a, int b, int c) noexcept nogil:
    cdef int t
    if a > b:
        t = a; a = b; b = t
    if b > c:
        t = b; b = c; c = t
    if a > b:
        t = a; a = b; b = t
    return a * 676 + b * 26 + c


cdef int compare_ints(const void *x, const void *y) noexcept nogil:
    return (<int *> x)[0] - (<int *> y)[0]


cdef inline int is_interior(Mesh *m, int code) noexcept nogil:
    cdef int a = code // 676, b = (code // 26) % 26, c = code % 26
    return get_apex(m, a, b, c) >= 0 and get_apex(m, a, c, b) >= 0


cdef inline int failing(Mesh *m, int code) noexcept nogil:
    cdef int a = code // 676, b = (code // 26) % 26, c = code % 26
    return insphere(m, a, b, c, get_apex(m, a, b, c), get_apex(m, a, c, b)) > 0


ctypedef struct Queue:
    int items[QCAP]
    int head
    int tail
    char pending[NF]


cdef inline void push(Queue *q, int code) noexcept nogil:
    if not q.pending[code]:
        q.pending[code] = 1
        q.items[q.tail % QCAP] = code
        q.tail += 1


cdef int interior_codes(Mesh *m, int *out) noexcept nogil:
    """The interior faces as sorted codes, increasing (= sorted triples)."""
    cdef int a, b, c, n = 0
    for a in range(m.nv):
        for b in range(a + 1, m.nv):
            for c in range(b + 1, m.nv):
                if m.apex[a * 676 + b * 26 + c] >= 0 and m.apex[a * 676 + c * 26 + b] >= 0:
                    out[n] = a * 676 + b * 26 + c
                    n += 1
    return n


cdef void face_masks(Mesh *m, int *present, int *failing_mask) noexcept nogil:
    cdef int codes[2600]
    cdef int n = interior_codes(m, codes), k, code
    cdef Config cf
    present[0] = 0
    failing_mask[0] = 0
    for k in range(n):
        code = codes[k]
        classify(m, code // 676, (code // 26) % 26, code % 26, &cf)
        present[0] |= 1 << cf.kind
        if failing(m, code):
            failing_mask[0] |= 1 << cf.kind


cdef int improve(Mesh *m, Queue *q, int flippable, int *flips, int *failing_after) noexcept nogil:
    """improve_in; returns the number of rounds."""
    cdef int codes[2600]
    cdef int new_tets[64]
    cdef int faces[64]
    cdef int n, k, i, j, code, nt, nfaces, rounds = 1, again
    cdef Config cf
    memset(q.pending, 0, NF)
    q.head = 0
    q.tail = 0
    n = interior_codes(m, codes)
    for k in range(n):
        push(q, codes[k])
    while True:
        while q.head < q.tail:
            code = q.items[q.head % QCAP]
            q.head += 1
            q.pending[code] = 0
            if not is_interior(m, code) or not failing(m, code):
                continue
            classify(m, code // 676, (code // 26) % 26, code % 26, &cf)
            if not (flippable >> cf.kind) & 1:
                continue
            nt = apply_flip(m, &cf, new_tets)
            flips[cf.kind] += 1
            if m.error:
                return rounds
            nfaces = 0
            for k in range(nt):
                for i in range(4):  # the face without vertex i
                    faces[nfaces] = sorted_code(new_tets[k * 4 + (i + 1) % 4],
                                                new_tets[k * 4 + (i + 2) % 4],
                                                new_tets[k * 4 + (i + 3) % 4])
                    nfaces += 1
            qsort(faces, nfaces, sizeof(int), compare_ints)
            for k in range(nfaces):
                if k == 0 or faces[k] != faces[k - 1]:
                    push(q, faces[k])
        n = interior_codes(m, codes)
        again = 0
        failing_after[0] = 0
        for k in range(n):
            if failing(m, codes[k]):
                classify(m, codes[k] // 676, (codes[k] // 26) % 26, codes[k] % 26, &cf)
                failing_after[0] |= 1 << cf.kind
                if (flippable >> cf.kind) & 1:
                    push(q, codes[k])
                    again = 1
        if not again:
            return rounds
        rounds += 1


cdef int is_valid(Mesh *m, int64_t volume6_box, int64_t *high) noexcept nogil:
    """Every tetrahedron positive, the volumes summing to the box's exactly, every face
    either shared by two tetrahedra (opposite orientations) or on a face of the box."""
    cdef int slot, i, a, b, c, d
    cdef int64_t total = 0
    cdef int fa[4][3]
    for slot in range(m.slots):
        if not m.alive[slot]:
            continue
        a = m.tet[slot][0]; b = m.tet[slot][1]; c = m.tet[slot][2]; d = m.tet[slot][3]
        if volume6(m, a, b, c, d) <= 0:
            return 0
        total += volume6(m, a, b, c, d)
        fa[0][0] = a; fa[0][1] = b; fa[0][2] = c
        fa[1][0] = a; fa[1][1] = c; fa[1][2] = d
        fa[2][0] = a; fa[2][1] = d; fa[2][2] = b
        fa[3][0] = b; fa[3][1] = d; fa[3][2] = c
        for i in range(4):
            if get_apex(m, fa[i][0], fa[i][2], fa[i][1]) < 0 and not on_box_face(
                    m, fa[i][0], fa[i][1], fa[i][2], high):
                return 0
    return total == volume6_box


cdef int on_box_face(Mesh *m, int a, int b, int c, int64_t *high) noexcept nogil:
    if m.X[a] == m.X[b] == m.X[c] and (m.X[a] == 0 or m.X[a] == high[0]):
        return 1
    if m.Y[a] == m.Y[b] == m.Y[c] and (m.Y[a] == 0 or m.Y[a] == high[1]):
        return 1
    if m.Z[a] == m.Z[b] == m.Z[c] and (m.Z[a] == 0 or m.Z[a] == high[2]):
        return 1
    return 0


cdef class Setup:
    """One box, order and template: the corners (integers, low corner at the origin), the
    18 bits in insertion order, the segment (two corners) of each bit, the template's five
    tetrahedra, whether to improve and whether T22 may flip."""

    cdef int64_t corners[8][3]
    cdef int64_t high[3]
    cdef int64_t volume6_box
    cdef int order[18]
    cdef int segment[18][2]
    cdef int template[5][4]
    cdef int improve
    cdef int flippable
    cdef Mesh *mesh
    cdef Queue *queue

    def __cinit__(self, corners, order, segments, tetrahedra, bint improve,
                  bint allow_boundary_flips):
        cdef int k, i
        self.mesh = <Mesh *> malloc(sizeof(Mesh))
        self.queue = <Queue *> malloc(sizeof(Queue))
        if self.mesh == NULL or self.queue == NULL:
            raise MemoryError()
        for k in range(8):
            for i in range(3):
                value = int(corners[k][i])
                if not 0 <= value <= MAX_COORDINATE or value % 2:
                    raise ValueError(f"corner coordinate {value} outside the even integers "
                                     f"0..{MAX_COORDINATE}")
                self.corners[k][i] = value
        for i in range(3):
            self.high[i] = self.corners[7][i]
        self.volume6_box = 6 * self.high[0] * self.high[1] * self.high[2]
        for k in range(18):
            self.order[k] = int(order[k])
            self.segment[k][0] = int(segments[k][0])
            self.segment[k][1] = int(segments[k][1])
        for k in range(5):
            for i in range(4):
                self.template[k][i] = int(tetrahedra[k][i])
        self.improve = improve
        self.flippable = (1 << K_T23) | (1 << K_T32) | (1 << K_T44)
        if allow_boundary_flips:
            self.flippable |= 1 << K_T22

    def __dealloc__(self):
        free(self.mesh)
        free(self.queue)

    cdef int run(self, int pattern, int *row) noexcept nogil:
        """Partition (and improve) ``pattern``; the row's 12 ints: tetrahedra, valid,
        kinds, failing, flip23, flip32, flip22, flip44, rounds, tetrahedra after, valid
        after, failing after (the last eight -1 without improvement).  Returns the error
        code (0: none)."""
        cdef Mesh *m = self.mesh
        cdef int k, bit
        cdef int flips[9]
        reset(m)
        for k in range(8):
            add_vertex(m, self.corners[k][0], self.corners[k][1], self.corners[k][2])
        for k in range(5):
            add_tet(m, self.template[k][0], self.template[k][1], self.template[k][2],
                    self.template[k][3])
        for k in range(18):
            bit = self.order[k]
            if (pattern >> bit) & 1:
                split_edge(m, self.segment[bit][0], self.segment[bit][1])
        row[0] = m.count
        row[1] = is_valid(m, self.volume6_box, self.high)
        face_masks(m, &row[2], &row[3])
        for k in range(4, 12):
            row[k] = -1
        if not self.improve or m.error:
            return m.error
        for k in range(9):
            flips[k] = 0
        row[8] = improve(m, self.queue, self.flippable, flips, &row[11])
        row[4] = flips[K_T23]
        row[5] = flips[K_T32]
        row[6] = flips[K_T22]
        row[7] = flips[K_T44]
        row[9] = m.count
        row[10] = is_valid(m, self.volume6_box, self.high)
        return m.error

    def run_pattern(self, int pattern):
        """(row, steps, tetrahedra) of ``pattern``: the 12 row ints, the steps as
        (op, a, b, c) with op 0 split_tetra (c = -1), 1 flip23, 2 flip32, 3 flip22,
        4 flip44, and the final tetrahedra (positive vertex quadruples)."""
        cdef int row[12]
        cdef int error, k
        cdef Mesh *m = self.mesh
        with nogil:
            error = self.run(pattern, row)
        if error:
            raise RuntimeError(f"cuboid kernel: error {error} on pattern {pattern}")
        steps = [(m.step_op[k], m.step_arg[k][0], m.step_arg[k][1], m.step_arg[k][2])
                 for k in range(m.nsteps)]
        tetrahedra = [(m.tet[k][0], m.tet[k][1], m.tet[k][2], m.tet[k][3])
                      for k in range(m.slots) if m.alive[k]]
        return tuple(row[k] for k in range(12)), steps, tetrahedra

    def census_rows(self, int start, int stop):
        """The rows of patterns start .. stop - 1 as one flat list of 12 ints each."""
        cdef int row[12]
        cdef int pattern, k, error = 0, bad = -1
        cdef int count = stop - start if stop > start else 0
        cdef int *out = <int *> malloc(sizeof(int) * 12 * (count if count > 0 else 1))
        if out == NULL:
            raise MemoryError()
        try:
            with nogil:
                for pattern in range(start, stop):
                    error = self.run(pattern, &out[(pattern - start) * 12])
                    if error:
                        bad = pattern
                        break
            if error:
                raise RuntimeError(f"cuboid kernel: error {error} on pattern {bad}")
            return [out[k] for k in range(12 * count)]
        finally:
            free(out)


def tetrahedra_hash_sum(const int64_t[:, ::1] tetrahedra, multipliers, final_multiplier):
    """Sum mod 2**128 of the cell hashes (``geomexact.kernel.digest.cell_hash``) of the
    canonical ``tetrahedra`` (T x 4 vertex ids >= 0), given the four position
    ``multipliers`` and the ``final_multiplier``, the vertex keys made in C
    (``digest.vertex_key``): the tetrahedra's part of a
    :class:`~geomexact.mesh3d.snapshot.Mesh3` digest, built in bulk (an octree's mesh)."""
    cdef gx_u128 m0 = _to_u128(multipliers[0]), m1 = _to_u128(multipliers[1])
    cdef gx_u128 m2 = _to_u128(multipliers[2]), m3 = _to_u128(multipliers[3])
    cdef gx_u128 mf = _to_u128(final_multiplier)
    cdef gx_u128 total = 0, x
    cdef Py_ssize_t i, k, n = tetrahedra.shape[0], count = 0
    cdef uint64_t *keys
    for i in range(n):
        for k in range(4):
            if tetrahedra[i, k] >= count:
                count = tetrahedra[i, k] + 1
    keys = <uint64_t *> malloc(max(count, 1) * sizeof(uint64_t))
    if keys == NULL:
        raise MemoryError()
    for i in range(count):
        keys[i] = gx_cached_vertex_key(<uint64_t> i)
    with nogil:
        for i in range(n):
            x = (<gx_u128> keys[tetrahedra[i, 0]] * m0 + <gx_u128> keys[tetrahedra[i, 1]] * m1
                 + <gx_u128> keys[tetrahedra[i, 2]] * m2 + <gx_u128> keys[tetrahedra[i, 3]] * m3)
            x ^= x >> 61
            total += x * mf
    free(keys)
    return (int(gx_u128_hi(total)) << 64) | int(gx_u128_lo(total))


def vertex_keys(Py_ssize_t start, Py_ssize_t stop):
    """``digest.vertex_key(v)`` for v in ``start .. stop - 1``, as the kernel's cache
    holds them (a list, for tests)."""
    return [gx_cached_vertex_key(<uint64_t> v) for v in range(start, stop)]


def vertex_hash_sum(const uint8_t[::1] table, const int64_t[::1] starts,
                    const int64_t[:, ::1] codes):
    """Sum mod 2**128 of ``digest.vertex_hash(v, point)`` over the vertices v = 0 .. V - 1
    whose coordinate ``a`` is the value ``codes[v, a]`` (V x 3): value k's
    ``gmpy2.to_binary`` bytes are ``table[starts[k]:starts[k + 1]]``, each at most 40
    bytes long (the message, id and three values, fits BLAKE2b's one block)."""
    cdef uint8_t message[128]
    cdef gx_u128 total = 0
    cdef Py_ssize_t v, a, k, length, at, n = codes.shape[0]
    for k in range(starts.shape[0] - 1):
        if not 0 < starts[k + 1] - starts[k] <= 40:
            raise ValueError("a coordinate's binary is empty or longer than 40 bytes")
    with nogil:
        for v in range(n):
            for k in range(8):
                message[k] = <uint8_t> ((<uint64_t> v) >> (8 * k))
            at = 8
            for a in range(3):
                k = codes[v, a]
                length = starts[k + 1] - starts[k]
                memcpy(message + at, &table[starts[k]], length)
                at += length
            total += gx_blake2b_vertex_message(message, <unsigned> at)
    return (int(gx_u128_hi(total)) << 64) | int(gx_u128_lo(total))


def lattice_faces(const int64_t[:, ::1] points, const int64_t[:, ::1] tetrahedra,
                  uint64_t base, int64_t[::1] det, uint64_t[::1] keys):
    """The octree conformity check's one pass over the tetrahedra (T x 4 ids, each in
    0 .. V - 1, checked by the caller) of the lattice ``points`` (V x 3): into ``det`` (T)
    six times each one's signed volume, into ``keys`` (4T, face by face: face n of
    tetrahedron i at n * T + i) each face's key -- its ids sorted, ``(low * base + middle)
    * base + high``, times two plus the parity of the sorting permutation.  The same
    integers as ``geomexact.mesh3d.octree.conformity``'s numpy ``_det6`` and
    ``_face_keys``: the determinant in two's complement int64 arithmetic (computed
    unsigned, so it wraps as numpy's does), the keys in uint64."""
    cdef Py_ssize_t i, n, t = tetrahedra.shape[0]
    cdef int64_t x, y, z, low, high
    cdef uint64_t b0, b1, b2, c0, c1, c2, d0, d1, d2
    cdef uint64_t p0, p1, p2
    cdef int64_t q
    cdef int faces[4][3]
    faces[0][:] = [0, 1, 2]
    faces[1][:] = [0, 2, 3]
    faces[2][:] = [0, 3, 1]
    faces[3][:] = [1, 3, 2]
    if det.shape[0] != t or keys.shape[0] != 4 * t:
        raise ValueError("det holds T values and keys 4T")
    with nogil:
        for i in range(t):
            q = tetrahedra[i, 0]
            p0 = <uint64_t> points[q, 0]
            p1 = <uint64_t> points[q, 1]
            p2 = <uint64_t> points[q, 2]
            q = tetrahedra[i, 1]
            b0 = <uint64_t> points[q, 0] - p0
            b1 = <uint64_t> points[q, 1] - p1
            b2 = <uint64_t> points[q, 2] - p2
            q = tetrahedra[i, 2]
            c0 = <uint64_t> points[q, 0] - p0
            c1 = <uint64_t> points[q, 1] - p1
            c2 = <uint64_t> points[q, 2] - p2
            q = tetrahedra[i, 3]
            d0 = <uint64_t> points[q, 0] - p0
            d1 = <uint64_t> points[q, 1] - p1
            d2 = <uint64_t> points[q, 2] - p2
            det[i] = <int64_t> (b0 * (c1 * d2 - c2 * d1) - b1 * (c0 * d2 - c2 * d0)
                                + b2 * (c0 * d1 - c1 * d0))
            for n in range(4):
                x = tetrahedra[i, faces[n][0]]
                y = tetrahedra[i, faces[n][1]]
                z = tetrahedra[i, faces[n][2]]
                low = x if x < y else y
                low = low if low < z else z
                high = x if x > y else y
                high = high if high > z else z
                keys[n * t + i] = ((<uint64_t> low * base + <uint64_t> (x + y + z - low - high))
                                   * base + <uint64_t> high) * 2 + <uint64_t> (
                                       (x > y) ^ (x > z) ^ (y > z))
