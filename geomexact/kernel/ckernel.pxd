# cython: language_level=3
"""Cython declarations of ``geomexact/kernel/ckernel.h`` (the C pieces shared by the
compiled kernels), and the Cython pieces they share: the Python <-> 128-bit conversions,
growable arrays and the stack of half-edges to legalize, and the kernels' predicates (a
vertex as a :class:`GridPoint`: exact on the grid, else the certified float filter, else
the exact Python predicate).  ``cimport`` only: there is no module of this name at run
time."""

from libc.stdint cimport int64_t, int8_t, uint8_t, uint64_t
from libc.stdlib cimport malloc, realloc

cdef extern from "ckernel.h":
    # Cython sees the 128-bit types as 64-bit ones; they never cross into Python
    # directly (the hi/lo helpers do that).
    ctypedef long long gx_i128
    ctypedef unsigned long long gx_u128
    ctypedef struct gx_map:
        uint64_t mask
        uint64_t count
        uint64_t *keys
        int64_t *values
    uint64_t GX_EMPTY
    uint64_t gx_edge(int64_t u, int64_t v) nogil
    int gx_map_alloc(gx_map *m, uint64_t slots)
    void gx_map_free(gx_map *m)
    uint64_t gx_map_slot(const gx_map *m, uint64_t key) nogil
    int gx_map_grow(gx_map *m) nogil
    int64_t gx_map_get(const gx_map *m, uint64_t key, int64_t missing) nogil
    int gx_map_set(gx_map *m, uint64_t key, int64_t value) nogil
    int gx_map_del(gx_map *m, uint64_t key) nogil
    gx_u128 gx_u128_make(uint64_t hi, uint64_t lo)
    uint64_t gx_u128_hi(gx_u128 x)
    uint64_t gx_u128_lo(gx_u128 x)
    gx_u128 gx_cell_hash(uint64_t ka, uint64_t kb, uint64_t kc) nogil
    gx_u128 gx_grid_vertex_hash(int64_t vertex, int64_t gx, int64_t gy, int F) nogil
    gx_u128 gx_blake2b_128(const uint8_t *message, unsigned len, uint64_t personal) nogil
    gx_u128 gx_blake2b_vertex_message(const uint8_t *message, unsigned len) nogil
    uint64_t gx_vertex_key(uint64_t vertex) nogil
    uint64_t gx_cached_vertex_key(uint64_t vertex)
    int gx_ctz64(uint64_t x) nogil
    int gx_clz64(uint64_t x) nogil
    int gx_grid_lengths(int64_t, int64_t, int64_t, int64_t,
                        int64_t, int64_t, int64_t, int64_t) nogil
    int gx_grid_orient(int64_t, int64_t, int64_t, int64_t, int64_t, int64_t) nogil
    int gx_grid_dot(int64_t, int64_t, int64_t, int64_t, int64_t, int64_t) nogil
    gx_i128 gx_grid_area2(int64_t, int64_t, int64_t, int64_t, int64_t, int64_t) nogil
    int gx_grid_incircle(int64_t, int64_t, int64_t, int64_t,
                         int64_t, int64_t, int64_t, int64_t) nogil
    int gx_float_orient(double, double, double, double, double, double) nogil
    int gx_float_incircle(double, double, double, double,
                          double, double, double, double) nogil
    int gx_float_lengths(double, double, double, double,
                         double, double, double, double) nogil
    int gx_float_dot(double, double, double, double, double, double) nogil
    void gx_set_constants(gx_u128 m0, gx_u128 m1, gx_u128 m2, gx_u128 mf,
                          double orient_c, double orient_k,
                          double incircle_c, double incircle_k,
                          double lengths_c, double lengths_k,
                          double dot_c, double dot_k)


cdef inline bint gx_map_next(const gx_map *m, uint64_t *slot, uint64_t *key,
                             int64_t *value) noexcept nogil:
    """The next entry of ``m`` in slot order from ``slot[0]`` (start at 0): True with
    ``key``, ``value`` set and ``slot`` past it; False at the end."""
    while slot[0] <= m.mask:
        key[0] = m.keys[slot[0]]
        slot[0] += 1
        if key[0] != GX_EMPTY:
            value[0] = m.values[slot[0] - 1]
            return True
    return False


cdef inline gx_u128 _to_u128(object value) except *:
    """A Python int taken mod 2**128."""
    value = value & ((1 << 128) - 1)
    return gx_u128_make(<uint64_t>(value >> 64), <uint64_t>(value & 0xFFFFFFFFFFFFFFFF))


from cpython.object cimport PyObject_GenericSetAttr, PyTypeObject
from cpython.ref cimport PyObject, Py_INCREF, Py_DECREF

cdef extern from "Python.h":
    object _PyLong_FromByteArray(const unsigned char *bytes, size_t n, int little_endian,
                                 int is_signed)
    void PyObject_GC_UnTrack(void *op)
    ctypedef PyObject *(*_allocfunc)(PyTypeObject *, Py_ssize_t)
    ctypedef struct _AllocatingType "PyTypeObject":
        _allocfunc tp_alloc

cdef extern from "structmember.h":
    ctypedef struct _MemberDef "PyMemberDef":
        int type
        Py_ssize_t offset
    ctypedef struct _MemberDescr "PyMemberDescrObject":
        _MemberDef *d_member
    int _T_OBJECT_EX "T_OBJECT_EX"


ctypedef struct StepLayout:
    Py_ssize_t op_offset    # where the slots ``op`` and ``args`` of a Step live
    Py_ssize_t args_offset
    bint direct             # False: set them through the attribute protocol


cdef inline Py_ssize_t _object_member_offset(object descriptor) except -2:
    """Where a slot described by ``descriptor`` lives in its instances, or -1 when it is
    not a plain object member (a ``member_descriptor`` of type ``T_OBJECT_EX``)."""
    import types

    if type(descriptor) is not types.MemberDescriptorType:
        return -1
    cdef _MemberDef *member = (<_MemberDescr *><PyObject *>descriptor).d_member
    return member.offset if member.type == _T_OBJECT_EX else -1


cdef inline StepLayout step_layout(object step_class):
    """Where a ``Step`` keeps its two slots: plain object members of its class (an attrs
    slotted class); ``direct`` False when they are not that (the slow, general path)."""
    cdef StepLayout layout
    layout.op_offset = _object_member_offset(step_class.__dict__.get("op"))
    layout.args_offset = _object_member_offset(step_class.__dict__.get("args"))
    layout.direct = layout.op_offset >= 0 and layout.args_offset >= 0
    return layout


cdef inline object allocated(object cls, Py_ssize_t items):
    """A new instance of the type ``cls`` from its ``tp_alloc`` (``items`` items for a
    tuple subtype), every field still empty: the caller fills them, as the type's own
    ``__new__`` would."""
    cdef PyObject *raw = (<_AllocatingType *><PyObject *>cls).tp_alloc(
        <PyTypeObject *><PyObject *>cls, items)
    if raw == NULL:
        raise MemoryError
    instance = <object>raw
    Py_DECREF(instance)  # <object> took a second reference
    return instance


cdef inline object make_step(object step_class, StepLayout *layout, str op, tuple args):
    """``Step(op, args)`` without the attrs ``__init__`` (``args`` is a tuple already):
    allocated by its type and its two slots written in place (``layout``), as attrs'
    frozen ``__init__`` sets them.  Neither the step nor its arguments (a str, ints,
    rationals) can be in a cycle: the cyclic collector need not scan a run's hundreds of
    thousands of them."""
    cdef PyObject *raw
    cdef PyObject **slot
    if layout.direct:
        step = allocated(step_class, 0)
        raw = <PyObject *>step
        Py_INCREF(op)
        slot = <PyObject **>((<char *>raw) + layout.op_offset)
        slot[0] = <PyObject *>op
        Py_INCREF(args)
        slot = <PyObject **>((<char *>raw) + layout.args_offset)
        slot[0] = <PyObject *>args
    else:
        step = step_class.__new__(step_class)
        PyObject_GenericSetAttr(step, "op", op)
        PyObject_GenericSetAttr(step, "args", args)
    PyObject_GC_UnTrack(<void *>args)
    PyObject_GC_UnTrack(<void *>step)
    return step


cdef inline object _from_u128(gx_u128 value):
    # one C-API call on its 16 bytes, least significant first (three Python int
    # operations otherwise: a trace of 10^6 steps converts 10^6 digests)
    cdef unsigned char buffer[16]
    cdef gx_u128 bits = value
    cdef int i
    for i in range(16):
        buffer[i] = <unsigned char>(bits & 0xFF)
        bits >>= 8
    return _PyLong_FromByteArray(buffer, 16, 1, 0)


cdef inline object _from_i128(gx_i128 value):
    cdef gx_u128 bits = <gx_u128>value
    result = _from_u128(bits)
    if gx_u128_hi(bits) >> 63:
        result -= 1 << 128
    return result


cdef inline gx_i128 _to_i128(object value) except *:
    """A Python int with |value| < 2**126."""
    return <gx_i128>_to_u128(value)


cdef inline int grow_array(void **array, Py_ssize_t *capacity, size_t item) except -1:
    """Double the capacity of the malloc'ed ``array`` of items of ``item`` bytes."""
    cdef Py_ssize_t wanted = 2 * capacity[0]
    cdef void *grown = realloc(array[0], wanted * item)
    if grown == NULL:
        raise MemoryError
    array[0] = grown
    capacity[0] = wanted
    return 0


cdef struct Pair:
    int64_t a
    int64_t b


cdef struct PairStack:
    # the kernels' stacks of half-edges to legalize: ``count`` pairs in a malloc'ed array
    # of ``capacity``
    Pair *items
    Py_ssize_t count
    Py_ssize_t capacity


cdef inline int open_pair_stack(PairStack *stack, Py_ssize_t capacity) except -1:
    """An empty stack with room for ``capacity`` pairs (MemoryError when there is none;
    ``free(stack.items)`` releases it)."""
    stack.count = 0
    stack.capacity = capacity
    stack.items = <Pair *>malloc(capacity * sizeof(Pair))
    if stack.items == NULL:
        raise MemoryError
    return 0


cdef inline int push_pair(PairStack *stack, int64_t a, int64_t b) except -1:
    if stack.count == stack.capacity:
        grow_array(<void **>&stack.items, &stack.capacity, sizeof(Pair))
    stack.items[stack.count].a = a
    stack.items[stack.count].b = b
    stack.count += 1
    return 0


cdef inline bint pop_pair(PairStack *stack, int64_t *a, int64_t *b) noexcept nogil:
    """Take the last pair off ``stack`` into ``a``, ``b``; False when it is empty."""
    if stack.count == 0:
        return False
    stack.count -= 1
    a[0] = stack.items[stack.count].a
    b[0] = stack.items[stack.count].b
    return True


cdef inline int _init_constants() except -1:
    """Fill the C constants (cell-hash multipliers, filter constants) of this module's
    copy of ckernel.h from geomexact.kernel.digest and geomexact.kernel.filter_bounds."""
    from geomexact.kernel import digest as _digest
    from geomexact.kernel import filter_bounds as _bounds
    m0, m1, m2, _ = _digest._POSITION_MULTIPLIERS
    gx_set_constants(
        _to_u128(m0), _to_u128(m1), _to_u128(m2), _to_u128(_digest._FINAL_MULTIPLIER),
        _bounds.ORIENT2D_C, _bounds.ORIENT2D_K,
        _bounds.INCIRCLE_C, _bounds.INCIRCLE_K,
        _bounds.LENGTHS_C, _bounds.LENGTHS_K,
        _bounds.DOT_C, _bounds.DOT_K,
    )
    return 0


cdef struct GridPoint:
    # a vertex as the predicates see it: its doubles, and when ``grid`` is set, its exact
    # coordinates times 2**F (the kernel's grid) in gx, gy
    double fx
    double fy
    int64_t gx
    int64_t gy
    int8_t grid


cdef inline int filtered_orient(GridPoint *a, GridPoint *b, GridPoint *c) noexcept nogil:
    """The sign of orient2d(a, b, c): exact on the grid, else the certified float filter;
    2 when the filter cannot decide (the caller runs the exact predicate)."""
    if a.grid and b.grid and c.grid:
        return gx_grid_orient(a.gx, a.gy, b.gx, b.gy, c.gx, c.gy)
    return gx_float_orient(a.fx, a.fy, b.fx, b.fy, c.fx, c.fy)


cdef inline int filtered_incircle(GridPoint *a, GridPoint *b, GridPoint *c,
                                  GridPoint *d) noexcept nogil:
    """The sign of incircle(a, b, c, d), as :func:`filtered_orient` (on the grid only when
    the reduced differences fit, see ``gx_grid_incircle``); 2 when undecided."""
    cdef int result = 2
    if a.grid and b.grid and c.grid and d.grid:
        result = gx_grid_incircle(a.gx, a.gy, b.gx, b.gy, c.gx, c.gy, d.gx, d.gy)
    if result == 2:
        result = gx_float_incircle(a.fx, a.fy, b.fx, b.fy, c.fx, c.fy, d.fx, d.fy)
    return result


cdef inline int filtered_lengths(GridPoint *a, GridPoint *b, GridPoint *c,
                                 GridPoint *d) noexcept nogil:
    """The sign of |ab|² - |cd|², as :func:`filtered_orient`; 2 when undecided."""
    if a.grid and b.grid and c.grid and d.grid:
        return gx_grid_lengths(a.gx, a.gy, b.gx, b.gy, c.gx, c.gy, d.gx, d.gy)
    return gx_float_lengths(a.fx, a.fy, b.fx, b.fy, c.fx, c.fy, d.fx, d.fy)


cdef inline int filtered_dot(GridPoint *p, GridPoint *a, GridPoint *b) noexcept nogil:
    """The sign of (a - p).(b - p), as :func:`filtered_orient`; 2 when undecided."""
    if p.grid and a.grid and b.grid:
        return gx_grid_dot(p.gx, p.gy, a.gx, a.gy, b.gx, b.gy)
    return gx_float_dot(p.fx, p.fy, a.fx, a.fy, b.fx, b.fy)


# The exact predicates both kernels decide with: the filter above, else the Python
# predicate on the ``Point2`` objects ``points[ia], ...`` (imported on that rare path
# only: a ``.pxd`` has no module globals).  ``a, b, ...`` are the GridPoints of those
# same vertices.

cdef inline int orient_sign(GridPoint *a, GridPoint *b, GridPoint *c, object points,
                            Py_ssize_t ia, Py_ssize_t ib, Py_ssize_t ic) except -2:
    """The sign of orient2d(points[ia], points[ib], points[ic])."""
    cdef int result = filtered_orient(a, b, c)
    if result != 2:
        return result
    from geomexact.kernel.predicates2d import orient2d_exact
    return int(orient2d_exact(points[ia], points[ib], points[ic]))


cdef inline int incircle_sign(GridPoint *a, GridPoint *b, GridPoint *c, GridPoint *d,
                              object points, Py_ssize_t ia, Py_ssize_t ib, Py_ssize_t ic,
                              Py_ssize_t id) except -2:
    """The sign of incircle(points[ia], points[ib], points[ic], points[id])."""
    cdef int result = filtered_incircle(a, b, c, d)
    if result != 2:
        return result
    from geomexact.kernel.predicates2d import incircle_exact
    return int(incircle_exact(points[ia], points[ib], points[ic], points[id]))

