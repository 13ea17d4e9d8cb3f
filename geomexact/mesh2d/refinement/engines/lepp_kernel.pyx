# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, infer_types=False
"""Typed Lepp refinement kernel: ``refine(..., engine="compiled")`` on C data structures.

Contract: :class:`Kernel` runs exactly the loop of
``geomexact.mesh2d.refinement.engines.reference.ReferenceRefinement`` (``Refinement.run``
on the ops of ``geomexact.mesh2d.ops``) for the methods ``"bisection"``, ``"centroid"`` and
``"quasi"`` (with or without Delaunay flips; every centroid kind and every rule of the
presets: both orders, the three second-longest rules, both factor stops), a criterion
rating single triangles (no angle threshold, ``AnyOf`` of such criteria included, with
triangle attributes where it reads them), ``MinAngle``, ``AnyOf((MinAngle, X, ...))``
(the angle first: entries carry their group) or ``AverageAreaFactor`` (the region-wide
mean-area target), any region, triangle and vertex attributes, with ``max_steps`` and
``on_step``.  It records the same steps, the
same digest after every step, the same counters, and seals the same ``Mesh2``
(``geomexact.mesh2d.refinement.engines.compiled`` checks the subset and is the only caller).

Where the C data live:

* the mesh in a ``TriangleStore`` (``geomexact/kernel/ctriangulation.pxd``, shared with the
  Delaunay kernel): the half-edges ``(u, v) -> apex`` keyed by ``u << 32 | v`` (ids are
  below ``MAX_VERTICES = 2**32``), per vertex the doubles of the ``Point2`` (for the float
  filters), the coordinates times ``2**F`` as int64 when the exact rational lies on that
  grid (the *grid* vertices), the 64-bit digest key, the ``outgoing`` hint and the cached
  region membership; the digest (the sum mod 2**128 of ``geomexact.kernel.digest``) and
  the step records; its primitive steps (add, flip, split a side, remove an edge's two
  triangles) are the ones this kernel edits the mesh with;
* the constrained segments in an open-addressing table of the same kind;
* the work queue as a binary heap of (key, triangle), keys exact: an ``__int128`` doubled
  area in units of ``2**-2F`` (``MaxArea`` on grid triangles) or a Python key;
* for ``AverageAreaFactor``, the region's doubled area as an exact ``__int128`` sum in grid
  units over its grid triangles plus an exact rational sum over the others (empty on
  dyadic inputs), and its triangle count.  The mean test ``area2 <= target2 * count`` is
  decided by a float filter with a wide margin, else exactly in Python.

Every geometric decision is exact: on grid vertices by integer arithmetic in ``__int128``;
otherwise by the certified float filters of ``geomexact.kernel.predicates2d`` and
``geomexact.kernel.comparisons`` (same formulas and constants), falling back to the exact
Python predicate on the ``Point2`` objects.
"""

cimport cython
from libc.stdint cimport int64_t, uint64_t, int8_t, uint8_t, uint32_t
from libc.stdlib cimport calloc, malloc, free
from libc.string cimport memcpy
from libc.math cimport fabs, floor, frexp, isfinite, ldexp
from cpython.exc cimport PyErr_CheckSignals
from cpython.ref cimport PyObject, Py_DECREF, Py_INCREF
from cpython.tuple cimport PyTuple_SET_ITEM

import hashlib
import math
import os
import struct

import gmpy2
import immutables
import numpy as np

from geomexact.kernel import digest as _digest
from geomexact.kernel import comparisons as _comparisons
from geomexact.kernel import filter_bounds as _bounds
from geomexact.kernel.angles import compare_angle as _compare_angle
from geomexact.mesh2d.ops import quadrilateral_area_centroid, quadrilateral_vertex_centroid
from geomexact.mesh2d.vertex_interpolation import (interpolated_in_quadrilateral,
                                                   interpolated_on_edge)
from geomexact.mesh2d.refinement.centroids import CENTROID_BITS, rounded_area_centroid
from geomexact.mesh2d.refinement.criteria import doubled_area as _doubled_area
from geomexact.mesh2d.refinement.criteria import smallest_angle_cos2 as _smallest_angle_cos2
from geomexact.mesh2d.refinement.driver import TIP_DEPTH
from geomexact.mesh2d.refinement.driver import squared_length as _squared_length
from geomexact.errors import PreconditionError
from geomexact.mesh2d.refinement.queue import rank as _rank
from geomexact.mesh2d.snapshot import MAX_VERTICES, Mesh2, TableSource
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, point2
from geomexact.trace.step import Step

# the triangulation store: its types and store_* steps (names prefixed, see the .pxd)
from geomexact.kernel.ctriangulation cimport *
from geomexact.kernel.triangle_store cimport RecordedStore
from geomexact.kernel.ckernel cimport *

# the C pieces (hash tables, 128-bit digest, grid predicates, float filters, the predicates
# with their exact fallback) live in geomexact/kernel/ckernel.h and ckernel.pxd, shared with
# geomexact/mesh2d/delaunay/delaunay_kernel.pyx
_init_constants()

cdef StepLayout _STEP_LAYOUT = step_layout(Step)

# the op of each record code (``_step``)
_OP_NAMES = ("bisect", "flip", "insert_in_quadrilateral", "insert_vertex_centroid",
             "insert_centroid")

cdef extern from "grid_rational.h":
    int gx_gmpy2_import(const char *runtime_version, const char *module_path)
    const char *gx_gmpy2_built_version()
    PyObject *gx_grid_mpq(int64_t g, int F)
    bint gx_off_grid_denominator(object value)

cdef bytes _GMPY2_VERSION = gmpy2.version().encode()
# the compiled module: gmpy2.gmpy2 in a package, gmpy2 itself in a single-file install
cdef bytes _GMPY2_MODULE = os.fsencode(
    getattr(getattr(gmpy2, "gmpy2", gmpy2), "__file__", None) or "")
GRID_MPQ_IN_C = bool(gx_gmpy2_import(_GMPY2_VERSION, _GMPY2_MODULE))
"""True when grid coordinates become mpq objects in C (``grid_rational.h``)."""
cdef bint _GRID_MPQ_IN_C = GRID_MPQ_IN_C
GMPY2_BUILT_VERSION = (<bytes>gx_gmpy2_built_version()).decode()
"""The gmpy2 whose C headers the kernel was built with ("" when none were found)."""


cdef inline object _grid_mpq(object inverse_unit, int64_t g, int F):
    """mpq(g, 2**F), ``inverse_unit`` being mpq(1, 2**F)."""
    cdef PyObject *raw = gx_grid_mpq(g, F)
    if raw == NULL:
        # (an mpq times an int: faster in gmpy2 than mpq(numerator, denominator))
        return inverse_unit * g
    result = <object>raw
    Py_DECREF(result)  # <object> took a second reference
    return result


# a Point2 is a tuple subclass adding no fields (a NamedTuple): made as tuple.__new__ makes
# one (tuple_subtype_new: the type's tp_alloc, then the items), without the call through
# the method and the temporary tuple
cdef bint _POINT2_DIRECT = (issubclass(Point2, tuple)
                            and Point2.__basicsize__ == tuple.__basicsize__
                            and Point2.__itemsize__ == tuple.__itemsize__)


cdef inline object _new_point2(object x, object y, object fx, object fy):
    """``tuple.__new__(Point2, (x, y, fx, fy))``."""
    if not _POINT2_DIRECT:
        return tuple.__new__(Point2, (x, y, fx, fy))
    point = allocated(Point2, 4)
    # (PyTuple_SET_ITEM steals a reference)
    Py_INCREF(x)
    PyTuple_SET_ITEM(point, 0, x)
    Py_INCREF(y)
    PyTuple_SET_ITEM(point, 1, y)
    Py_INCREF(fx)
    PyTuple_SET_ITEM(point, 2, fx)
    Py_INCREF(fy)
    PyTuple_SET_ITEM(point, 3, fy)
    return point


def grid_rational(int64_t g, int F):
    """mpq(g, 2**F) as the kernel builds it, 0 <= F <= 62 (for tests)."""
    if not 0 <= F <= 62:
        raise ValueError(f"F={F} is outside 0..62")
    return _grid_mpq(mpq(1, 2 ** int(F)), g, F)


def cell_hash(int64_t a, int64_t b, int64_t c):
    """``geomexact.kernel.digest.cell_hash((a, b, c))`` computed by the kernel (for tests)."""
    return _from_u128(gx_cell_hash(_digest.vertex_key(a), _digest.vertex_key(b),
                                   _digest.vertex_key(c)))


# ---------------------------------------------------------------------------------------
cdef struct Entry:
    gx_i128 ikey       # the exact key when py < 0
    double rank        # geomexact.mesh2d.refinement.queue.rank(key) when py >= 0
    int64_t py         # index of the Python key in Kernel.pykeys, or -1
    # MinAngle: rank is −cos² of the smallest angle within rad (certified); the exact key
    # is made (py) only when two entries' intervals meet
    double rad
    int64_t a
    int64_t b
    int64_t c
    # AnyOf((MinAngle, X)): 0 for a triangle queued for its angle, 1 for X
    int group



cdef object GRID_LIMIT = 1 << 60
cdef object _HALF = mpq(1, 2)
# the imported constants as C values (compared with C integers without making Python ones)
cdef int64_t _MAX_VERTICES = MAX_VERTICES
cdef int64_t _CENTROID_BITS = CENTROID_BITS
cdef int _TIP_DEPTH = TIP_DEPTH

# the constants of compare_angle's float filter (geomexact.kernel.angles)
cdef double DOT_C = _bounds.DOT_C
cdef double DOT_K = _bounds.DOT_K
cdef double ANGLE_C = _bounds.ANGLE_C
cdef double ANGLE_K = _bounds.ANGLE_K
cdef double UNIT = 2.0 ** -53  # the unit roundoff of doubles
cdef double INFINITY = float("inf")

SHARP_CORNER = "sharp-corner"
PROTECTED_TIP = "protected-tip"


cdef inline bint _pair_less(int64_t a, int64_t b, int64_t c, int64_t d) nogil:
    """(min(a, b), max(a, b)) < (min(c, d), max(c, d))."""
    cdef int64_t p0 = a if a < b else b
    cdef int64_t p1 = b if a < b else a
    cdef int64_t q0 = c if c < d else d
    cdef int64_t q1 = d if c < d else c
    return p0 < q0 or (p0 == q0 and p1 < q1)


cdef inline bint _before(int order, int64_t a, int64_t b, int64_t c, int64_t d) nogil:
    """The edge order of ``specs/lepp.md``: {a, b} before {c, d}, given the comparison
    of their squared lengths."""
    return order > 0 or (order == 0 and _pair_less(a, b, c, d))


cdef object _pack_id = struct.Struct("<Q").pack
cdef object _blake2b = hashlib.blake2b
cdef object _to_binary = gmpy2.to_binary
cdef object _vertex_hasher = hashlib.blake2b(digest_size=16, person=b"vertex")


cdef gx_u128 _vertex_hash(int64_t vertex, x, y) except *:
    """geomexact.kernel.digest.vertex_hash(vertex, (x, y)), inlined (checked by the tests):
    BLAKE2b in C when its message fits one block."""
    cdef bytes message = _pack_id(vertex) + _to_binary(x) + _to_binary(y)
    if len(message) <= 128:
        return gx_blake2b_vertex_message(<const uint8_t *><const char *>message,
                                         <unsigned>len(message))
    hasher = _vertex_hasher.copy()
    hasher.update(message)
    return _to_u128(int.from_bytes(hasher.digest(), "little"))


def vertex_hash(int64_t vertex, x, y):
    """The kernel's vertex hash (for tests)."""
    return _from_u128(_vertex_hash(vertex, x, y))


def grid_vertex_hash(int64_t vertex, int64_t gx, int64_t gy, int F):
    """The kernel's vertex hash of the grid point (gx / 2**F, gy / 2**F), 0 <= F <= 62,
    computed in C (for tests)."""
    if not 0 <= F <= 62:
        raise ValueError(f"F={F} is outside 0..62")
    return _from_u128(gx_grid_vertex_hash(vertex, gx, gy, F))


cdef object _coordinate_bound(list points):
    """max(floor(|c|) + 1) over the coordinates c of the ``Point2``s ``points`` (0 when
    there are none).  The nearest doubles pick the candidates: a coordinate whose double is below
    (1 - 2**-50) times the largest one is below every coordinate whose double is that
    largest, so only those near the top are read exactly (all of them when a double
    overflowed)."""
    cdef double top = 0.0, value
    cdef tuple fields
    for point in points:
        fields = <tuple>point  # a Point2 is a tuple: indexed as one
        value = fabs(<double>fields[2])
        if value > top or not isfinite(value):
            top = value
        value = fabs(<double>fields[3])
        if value > top or not isfinite(value):
            top = value
    cdef double threshold = top * (1.0 - 2.0 ** -50) if isfinite(top) else -1.0
    bound = 0
    for point in points:
        fields = <tuple>point
        for k in range(2):
            if not fabs(<double>fields[2 + k]) >= threshold:
                continue
            bound = max(bound, int(abs(fields[k])) + 1)
    return bound


cdef inline bint _length_interval(GridPoint *a, GridPoint *b, double *low,
                                  double *high) noexcept nogil:
    """Doubles ``low`` <= |ab|² <= ``high`` from the points' doubles (each the nearest
    double of its coordinate): each difference is within E = 6 u m of the exact one (u =
    2^-53, m the largest |coordinate|), so the squared length within E (2 s + 2 E) of the
    float one (s = |dx| + |dy|), plus its own three roundings (3 u s²); False when out of
    range or not bounded away from 0."""
    cdef double m = max(fabs(a.fx), fabs(a.fy), fabs(b.fx), fabs(b.fy))
    cdef double dx = b.fx - a.fx, dy = b.fy - a.fy
    cdef double s = fabs(dx) + fabs(dy), e, length, error
    if not (m < 2.0 ** 200 and s > 2.0 ** -200):
        return False
    e = 6.0 * UNIT * m
    length = dx * dx + dy * dy
    # (1.0001 and 4 u: the roundings of the bounds themselves)
    error = (e * (2.0 * s + 2.0 * e) + 3.0 * UNIT * s * s) * 1.0001
    if not length > error:
        return False
    low[0] = (length - error) * (1.0 - 4.0 * UNIT)
    high[0] = (length + error) * (1.0 + 4.0 * UNIT)
    return True


cdef inline int64_t _bit_length(gx_i128 value) noexcept:
    """``int(value).bit_length()`` of 0 <= value < 2**127."""
    cdef uint64_t high = gx_u128_hi(<gx_u128>value), low = gx_u128_lo(<gx_u128>value)
    if high:
        return 128 - gx_clz64(high)
    if low:
        return 64 - gx_clz64(low)
    return 0


cdef inline unsigned _decimal(int64_t value, uint8_t *out) noexcept nogil:
    """The decimal digits of ``value`` >= 0 written at ``out``; their count."""
    cdef uint8_t digits[20]
    cdef unsigned n = 0, i
    while True:
        digits[n] = 48 + <uint8_t>(value % 10)
        n += 1
        value //= 10
        if value == 0:
            break
    for i in range(n):
        out[i] = digits[n - 1 - i]
    return n


cdef inline tuple _canonical(int64_t a, int64_t b, int64_t c):
    """The rotation of the triangle (a, b, c) that starts at its smallest vertex."""
    if a < b and a < c:
        return (a, b, c)
    if b < c:
        return (b, c, a)
    return (c, a, b)


cdef inline int _triangle_less(Entry *x, Entry *y) noexcept nogil:
    if x.a != y.a:
        return x.a < y.a
    if x.b != y.b:
        return x.b < y.b
    return x.c < y.c


@cython.final  # no subclasses: its cdef methods are called directly, not through a vtable
cdef class Kernel(RecordedStore):
    """One Lepp-bisection run (see the module docstring).  ``run()`` then ``finish()``;
    the store, the digests and the step count: :class:`RecordedStore`."""

    cdef Py_ssize_t n0
    cdef gx_map segs
    cdef Entry *heap
    cdef Py_ssize_t nheap, cap_heap
    cdef int64_t *created
    cdef Py_ssize_t ncreated, cap_created
    cdef int64_t limit
    cdef int64_t triangles
    cdef int F
    cdef bint whole, delaunay, max_area
    # the method: 0 bisection, 1 centroid, 2 quasi; legalize: Delaunay legalization after
    # insertions (delaunay and not quasi); quasi_flips: quasi with delaunay
    cdef int method
    cdef bint legalize, quasi_flips, constraint_midpoints, grid_centroids
    # the rules of presets (Refinement): the centroid's step (2 insert_in_quadrilateral,
    # 3 insert_vertex_centroid, 4 insert_centroid; -1 the midpoint of the terminal edge),
    # the "passes" order (keys are pass numbers), the literal second-longest rule, and when
    # an average-area factor is checked (after every action, else after every target)
    cdef int centroid_op
    cdef bint passes, bisect_longest, stop_per_action
    cdef int64_t pass_number
    cdef object unit  # 2**F
    cdef object inv_unit  # mpq(1, 2**F)
    cdef gx_i128 area_limit
    # AverageAreaFactor: the region's doubled area (grid part in grid units, the rest as
    # a rational), its triangle count, and the target mean doubled area
    cdef bint tracking, filtered
    cdef gx_i128 gsum
    cdef int64_t count, pycount
    cdef double target_grid
    cdef object pysum, target2, target_scaled
    cdef public int64_t targets, searches, hops
    cdef list points, pykeys, step_objects
    cdef dict segments, new_markers
    cdef object rate, contains, on_step, progress, scale, centroid
    # a MinAngle criterion (rated in C): its AngleThreshold, cos2 as a double (maybe nan)
    # and the sign of cos θ; the left triangles and why; the input's tip limits
    cdef bint min_angle
    cdef bint combined
    cdef object area_rate
    cdef bint grouped  # area_rate gives (group, key): AnyOf((MinAngle, X, Y, ...))
    cdef object threshold
    cdef double cos2f
    cdef int cos_sign
    cdef dict left
    cdef object start_segments
    # the start's half-edges sorted by (origin, end): start_offsets[u] ..
    # start_offsets[u + 1] index the ends and apexes of u's (the canonical triangles are
    # read off them in order; min angle: the tip limits read them)
    cdef int64_t *start_offsets
    cdef int64_t *start_ends
    cdef int64_t *start_apexes
    cdef int64_t *start_hints
    # per vertex: 1 once a walk round it found at most one constraint edge (an interior
    # vertex), so it has no sector (``_sector``); 0 not known.  Exact for the whole run:
    # no edit changes how many constraint edges a vertex has (flips and centroids never
    # touch one, a split keeps each end's), nor makes an interior vertex a boundary one
    cdef uint8_t *sectorless
    cdef Py_ssize_t cap_sectorless
    cdef dict tip_grid
    # per input vertex: its tip limit's state (0 not known yet, 1 none, 2 within
    # [tip_low, tip_high], the exact value made only when that interval does not decide)
    cdef uint8_t *tip_state
    cdef double *tip_low
    cdef double *tip_high
    # triangle attributes (a mesh with regions): each canonical triangle (a, b, c) with
    # attributes has an entry (a, b) -> the id of its attribute tuple in ``tattr``; the
    # tuples by id and the tail of their digest text; the start's attributes (the tip
    # limits read them); the id of the triangle a step is replacing, -1 for none (its new
    # triangles take it, as the ops' join_in_* do); rate_attributes: the criterion reads
    # them (RegionAreas)
    cdef bint attributed, rate_attributes
    cdef gx_map tattr
    cdef list attribute_values, attribute_tails
    cdef dict attribute_ids, start_tattrs
    cdef int64_t cur_attr
    # RegionAreas rated in C on grid triangles: its doubled areas in grid units by region
    cdef dict region_limits
    # vertex attributes: the table (new vertices get them interpolated), when any
    cdef bint vattributed
    cdef object vtable
    cdef bint sealed  # finish sealed the result and freed the half-edge tables
    cdef dict exact_lengths  # (edge, edge) -> the sign of |e|^2 - |f|^2, decided exactly

    def __dealloc__(self):
        # (the C attributes start zeroed: pointers that __init__ did not reach are NULL;
        # RecordedStore frees the store)
        free(self.heap)
        free(self.created)
        gx_map_free(&self.segs)
        self._free_start_halfedges()
        gx_map_free(&self.tattr)
        free(self.start_hints)
        free(self.sectorless)
        free(self.tip_state)
        free(self.tip_low)
        free(self.tip_high)

    def __init__(self, start, run):
        """One run on the snapshot ``start``, as ``run`` (a
        :class:`~geomexact.mesh2d.refinement.engines.compiled.KernelRun`) says:
        ``criterion`` rated by its ``rate`` (``rate_attributed`` with ``rate_attributes``)
        in ``region``; ``max_area_doubled``: twice the area of a ``MaxArea`` (rated in C on
        grid triangles); ``average``: an ``AverageAreaFactor`` (every triangle of the
        region is bad, key −(doubled area); the run stops when the region's mean area
        reaches ``criterion.target_mean_area``); ``threshold``: the ``AngleThreshold`` of a
        ``MinAngle`` rated in C, with the small-angle rules of ``Refinement``;
        ``area_rate``: the size criterion after the angle (``grouped``: its key is
        (position, key), AnyOf's ``rate_beyond_angle``); ``region_doubled``: a
        ``RegionAreas``'s doubled areas by region, rated in C on grid triangles;
        ``method``, ``delaunay``, ``constraint_midpoints``, ``centroid_kind``, ``order``,
        ``second_longest_rule`` and ``factor_stop``: as ``refine()`` and the rules of
        ``geomexact.mesh2d.refinement.presets``; ``max_steps``, ``on_step`` (called with
        ``progress(...)``) as ``refine()``."""
        criterion, region = run.criterion, run.region
        cdef bint whole = run.whole, delaunay = run.delaunay, average = run.average
        cdef bint constraint_midpoints = run.constraint_midpoints
        cdef bint grouped = run.grouped, rate_attributes = run.rate_attributes
        max_steps, on_step, progress = run.max_steps, run.on_step, run.progress
        max_area_doubled, method, threshold = run.max_area_doubled, run.method, run.threshold
        area_rate, centroid_kind, order = run.area_rate, run.centroid_kind, run.order
        second_longest_rule, factor_stop = run.second_longest_rule, run.factor_stop
        region_doubled = run.region_doubled
        centroid = rounded_area_centroid
        cdef Py_ssize_t i, count = start.vertex_count
        cdef TriVertex *vertex
        cdef Py_ssize_t k
        cdef int64_t a, b, c
        cdef int64_t g
        cdef tuple fields
        self.points = start.point_list()
        self.n0 = count
        slots = 64
        while slots < 12 * start.triangle_count:  # the start's half-edges, then room to grow
            slots *= 2
        store_init(&self.store, count, max(16, 2 * count), slots, 64)
        self.cap_heap = self.cap_created = 64
        self.heap = <Entry *>malloc(self.cap_heap * sizeof(Entry))
        self.created = <int64_t *>malloc(3 * self.cap_created * sizeof(int64_t))
        self.cap_sectorless = max(16, 2 * count)
        self.sectorless = <uint8_t *>calloc(self.cap_sectorless, sizeof(uint8_t))
        if not self.heap or not self.created or not self.sectorless:
            raise MemoryError
        if gx_map_alloc(&self.segs, 64) < 0:
            raise MemoryError
        # the grid: 2**-F with every input coordinate (hence every midpoint) below 2**60
        bound = _coordinate_bound(self.points)
        self.F = max(0, 60 - int(bound).bit_length())
        self.scale = mpq(2) ** (2 * self.F)
        self.unit = 2 ** int(self.F)
        self.inv_unit = mpq(1, self.unit)
        for i in range(count):
            fields = <tuple>self.points[i]  # a Point2 is a tuple: indexed as one
            vertex = &self.store.vs[i]
            vertex.at.fx = fields[2]
            vertex.at.fy = fields[3]
            vertex.at.grid = self._on_grid(fields[0], vertex.at.fx, &vertex.at.gx) and (
                self._on_grid(fields[1], vertex.at.fy, &vertex.at.gy))
            vertex.key = gx_cached_vertex_key(<uint64_t>i)  # digest.vertex_key, in C
            vertex.inside = -1
        self._read_start_tables(start)
        self.triangles = start.triangle_count
        self.segments = dict(start.segments.items())
        for key in self.segments:
            if gx_map_set(&self.segs, gx_edge(key[0], key[1]), 0) < 0:
                raise MemoryError
        self.new_markers = {}
        self.store.digest = _to_u128(start.digest)
        self.limit = -1 if max_steps is None else max_steps
        self.whole = whole
        self.delaunay = delaunay
        if method == "bisection":
            self.method = 0
        elif method == "centroid":
            self.method = 1
        elif method == "quasi":
            self.method = 2
        else:
            raise ValueError(f"unknown method {method!r}")
        self.legalize = delaunay and self.method != 2
        self.quasi_flips = delaunay and self.method == 2
        self.constraint_midpoints = constraint_midpoints
        if second_longest_rule is not None:
            self.constraint_midpoints = second_longest_rule != "centroid"
        self.bisect_longest = second_longest_rule == "bisect-longest"
        self.passes = order == "passes"
        if order not in ("worst-first", "passes"):
            raise ValueError(f"unknown order {order!r}")
        self.pass_number = -1
        self.stop_per_action = factor_stop == "action"
        self.centroid_op = 2
        if centroid_kind == "area-exact":
            centroid, self.centroid_op = quadrilateral_area_centroid, 4
        elif centroid_kind == "vertices":
            centroid, self.centroid_op = quadrilateral_vertex_centroid, 3
        elif centroid_kind == "midpoint":
            self.centroid_op = -1
        elif centroid_kind != "area":
            raise ValueError(f"unknown centroid kind {centroid_kind!r}")
        self.centroid = centroid
        # rounded_area_centroid computed on grid quadrilaterals in integers
        self.grid_centroids = centroid is rounded_area_centroid and self.centroid_op == 2
        self.contains = region.contains
        self.start_tattrs = dict(start.triangle_attributes.items())
        self.attributed = bool(self.start_tattrs)
        self.attribute_values, self.attribute_tails, self.attribute_ids = [], [], {}
        self.cur_attr = -1
        if self.attributed:
            slots = 64
            while slots < 4 * len(self.start_tattrs):
                slots *= 2
            if gx_map_alloc(&self.tattr, slots) < 0:
                raise MemoryError
            for key, attributes in self.start_tattrs.items():
                if attributes and gx_map_set(&self.tattr, gx_edge(key[0], key[1]),
                                             self._attribute_id(attributes)) < 0:
                    raise MemoryError
        self.rate_attributes = rate_attributes
        self.vattributed = bool(len(start.vertex_attributes))
        self.vtable = start.vertex_attributes.mutate() if self.vattributed else None
        self.rate = criterion.rate_attributed if rate_attributes else criterion.rate
        self.min_angle = threshold is not None
        # AnyOf((MinAngle, X)): the angle first, then X (area_rate: X's rate; a MaxArea X
        # is rated in C on grid triangles, max_area_doubled)
        self.combined = self.min_angle and area_rate is not None
        self.area_rate = self.rate if area_rate is None else area_rate
        # AnyOf((MinAngle, X, Y, ...)): area_rate is its rate_beyond_angle, whose
        # (position, key) gives the entry's group (the position in the AnyOf) and key
        self.grouped = grouped
        self.threshold = threshold
        self.left = {}
        self.tip_grid = {}
        self.exact_lengths = {}
        if self.min_angle:
            if average:
                raise ValueError("a minimum angle is rated alone or with one other criterion")
            self.cos2f = threshold.cos2_float
            self.cos_sign = threshold.cos_sign
            # Refinement.tip_limit reads the start mesh: its half-edges and outgoing hints
            self.start_segments = start.segments
            self.start_hints = <int64_t *>malloc(max(1, count) * sizeof(int64_t))
            self.tip_state = <uint8_t *>calloc(max(1, count), sizeof(uint8_t))
            self.tip_low = <double *>malloc(max(1, count) * sizeof(double))
            self.tip_high = <double *>malloc(max(1, count) * sizeof(double))
            if not (self.start_hints and self.tip_state and self.tip_low and self.tip_high):
                raise MemoryError
            for i in range(count):
                self.start_hints[i] = self.store.vs[i].hint
        self.on_step = on_step
        self.progress = progress
        self.step_objects = [] if on_step is not None else None
        self.pykeys = []
        self.max_area = max_area_doubled is not None
        self.area_limit = 0
        if self.max_area:
            # area2 (grid units, an integer) > doubled * 2**2F  <=>  area2 > floor(...)
            limit = int(math.floor(max_area_doubled * self.scale))
            self.area_limit = _to_i128(min(limit, 1 << 124))
        self.region_limits = None
        if region_doubled is not None:
            self.region_limits = {
                region: _to_i128(min(int(math.floor(doubled * self.scale)), 1 << 124))
                for region, doubled in region_doubled.items()}
        self.targets = self.searches = self.hops = 0
        self.tracking = False
        self.filtered = False
        self.gsum = 0
        self.count = self.pycount = 0
        self.target_grid = 0.0
        self.pysum = mpq(0)
        self.target2 = self.target_scaled = None
        # sorted(start.iter_triangles()): the half-edges (a, b) -> c with a < b, a < c,
        # in (a, b) order
        if average:
            # Refinement.start_queue: the region's initial doubled area and count
            self.max_area = True
            self.area_limit = -(<gx_i128>1 << 126)  # every grid triangle is bad
            for a in range(count):
                for k in range(self.start_offsets[a], self.start_offsets[a + 1]):
                    b, c = self.start_ends[k], self.start_apexes[k]
                    if a < b and a < c:
                        self._account(a, b, c, 1)
            total = _from_i128(self.gsum) / self.scale + self.pysum
            target = criterion.target_mean_area(total / 2, self.count)
            self.target2 = 2 * target
            self.target_scaled = self.target2 * self.scale
            try:
                self.target_grid = float(self.target_scaled)
            except OverflowError:
                self.target_grid = math.inf
            # the filter needs a normal, moderate double (relative error below 2**-50)
            self.filtered = 2.0 ** -500 < self.target_grid < 2.0 ** 500
            self.tracking = True
        for a in range(count):
            for k in range(self.start_offsets[a], self.start_offsets[a + 1]):
                b, c = self.start_ends[k], self.start_apexes[k]
                if a < b and a < c:
                    self._consider(a, b, c)

    cdef int _read_start_tables(self, start) except -1:
        """The start's half-edges into the C table (and sorted, ``_sort_start_halfedges``)
        and its outgoing hints into the vertices: from its arrays while its tables are not
        built (a kernel's result, a bulk-read file: building them here would cost more
        than the run), else from its tables."""
        cdef Py_ssize_t i, count
        cdef const int64_t[:, ::1] rows
        cdef const int64_t[::1] hints
        cdef int64_t *table = NULL
        source = start.source
        try:
            if source is not None:
                rows = np.ascontiguousarray(source.halfedges, dtype=np.int64)
                hints = np.ascontiguousarray(source.hints, dtype=np.int64)
                for i in range(self.store.nv):
                    self.store.vs[i].hint = hints[i]
                count = rows.shape[0]
                table = <int64_t *>malloc(max(1, 3 * count) * sizeof(int64_t))
                if table == NULL:
                    raise MemoryError
                for i in range(count):
                    store_put(&self.store, rows[i, 0], rows[i, 1], rows[i, 2])
                    table[3 * i] = rows[i, 0]
                    table[3 * i + 1] = rows[i, 1]
                    table[3 * i + 2] = rows[i, 2]
            else:
                outgoing = start.outgoing
                for i in range(self.store.nv):
                    hint = outgoing.get(i)
                    self.store.vs[i].hint = -1 if hint is None else hint
                halfedges = start.halfedges
                count = len(halfedges)
                table = <int64_t *>malloc(max(1, 3 * count) * sizeof(int64_t))
                if table == NULL:
                    raise MemoryError
                i = 0
                for key, w in halfedges.items():
                    store_put(&self.store, (<tuple>key)[0], (<tuple>key)[1], w)
                    table[3 * i] = (<tuple>key)[0]
                    table[3 * i + 1] = (<tuple>key)[1]
                    table[3 * i + 2] = w
                    i += 1
            self._sort_start_halfedges(table, count)
        finally:
            free(table)
        return 0

    cdef int _sort_start_halfedges(self, const int64_t *rows, Py_ssize_t count) except -1:
        """``start_offsets``, ``start_ends``, ``start_apexes`` from the ``count`` rows
        (u, v, w) put in the table: sorted by (u, v) by two stable counting sorts (by v,
        then by u), a repeated half-edge keeping its last apex as the table does."""
        cdef Py_ssize_t n = self.n0, i, k, end, position
        cdef int64_t u, v
        cdef int64_t *offsets
        cdef int64_t *by_end = NULL
        cdef int64_t *order = NULL
        for i in range(3 * count):
            if not 0 <= rows[i] < n:
                raise ValueError(
                    f"the start's half-edges name a vertex {rows[i]} outside 0..{n - 1}")
        self.start_offsets = offsets = <int64_t *>calloc(n + 1, sizeof(int64_t))
        self.start_ends = <int64_t *>malloc(max(1, count) * sizeof(int64_t))
        self.start_apexes = <int64_t *>malloc(max(1, count) * sizeof(int64_t))
        by_end = <int64_t *>malloc(max(1, count) * sizeof(int64_t))
        order = <int64_t *>malloc(max(1, count) * sizeof(int64_t))
        try:
            if not (offsets and self.start_ends and self.start_apexes and by_end and order):
                raise MemoryError
            # by v: the counts in offsets[v + 1], summed to the starts, each row placed
            for i in range(count):
                offsets[rows[3 * i + 1] + 1] += 1
            for v in range(n):
                offsets[v + 1] += offsets[v]
            for i in range(count):
                v = rows[3 * i + 1]
                by_end[offsets[v]] = i
                offsets[v] += 1
            # then by u, in that order
            for v in range(n + 1):
                offsets[v] = 0
            for i in range(count):
                offsets[rows[3 * i] + 1] += 1
            for u in range(n):
                offsets[u + 1] += offsets[u]
            for k in range(count):
                i = by_end[k]
                u = rows[3 * i]
                order[offsets[u]] = i
                offsets[u] += 1
            # offsets[u] is now the end of u's rows in ``order``: their ends and apexes, a
            # run of rows of one half-edge reduced to its last
            position = 0
            k = 0
            for u in range(n):
                end = offsets[u]
                offsets[u] = position
                while k < end:
                    i = order[k]
                    k += 1
                    if k < end and rows[3 * order[k] + 1] == rows[3 * i + 1]:
                        continue
                    self.start_ends[position] = rows[3 * i + 1]
                    self.start_apexes[position] = rows[3 * i + 2]
                    position += 1
            offsets[n] = position
        finally:
            free(by_end)
            free(order)
        return 0

    cdef void _free_start_halfedges(self) noexcept:
        free(self.start_offsets)
        free(self.start_ends)
        free(self.start_apexes)
        self.start_offsets = self.start_ends = self.start_apexes = NULL

    cdef inline int64_t _start_apex(self, int64_t u, int64_t v) noexcept:
        """The apex of the start's half-edge (u, v), or -1: a binary search among u's
        ends."""
        cdef int64_t low, high, middle
        if not 0 <= u < self.n0:
            return -1
        low = self.start_offsets[u]
        high = self.start_offsets[u + 1]
        while low < high:
            middle = (low + high) >> 1
            if self.start_ends[middle] < v:
                low = middle + 1
            else:
                high = middle
        if low < self.start_offsets[u + 1] and self.start_ends[low] == v:
            return self.start_apexes[low]
        return -1

    # -- vertices -----------------------------------------------------------------------
    cdef bint _on_grid(self, value, double nearest, int64_t *out) except -1:
        """True (and ``out`` set) when the rational ``value`` is k / 2**F, |k| <= 2**60.
        ``nearest``: its nearest double.  A grid value has a nearest double that is a
        multiple of 2**-F (it is the value itself below 2**(53 - F), else a multiple of
        a coarser power of two), so a finite one that is not decides at once."""
        cdef double scaled_nearest = ldexp(nearest, self.F)
        if isfinite(scaled_nearest) and scaled_nearest != floor(scaled_nearest):
            return False
        if gx_off_grid_denominator(value):
            return False
        denominator = value.denominator
        if denominator & (denominator - 1):
            return False
        exponent = int(denominator).bit_length() - 1
        if exponent > self.F:
            return False
        scaled = int(value.numerator) << (self.F - exponent)
        if abs(scaled) > GRID_LIMIT:
            return False
        out[0] = scaled
        return True

    cdef int64_t _add_midpoint(self, int64_t u, int64_t v) except -1:
        """The vertex at the exact midpoint of u and v (as ``ops.bisect_in``)."""
        cdef TriVertex *vu = &self.store.vs[u]
        cdef TriVertex *vv = &self.store.vs[v]
        cdef int64_t sx = 0, sy = 0
        cdef int grid = -1, half = self.F + 1
        cdef tuple pu, pv
        point = None
        if vu.at.grid and vv.at.grid:
            # the midpoint is (sx, sy) / 2**(F + 1): on the grid when both sums are even
            sx = vu.at.gx + vv.at.gx
            sy = vu.at.gy + vv.at.gy
            grid = not (sx & 1) and not (sy & 1)
            if _GRID_MPQ_IN_C and half <= 62:
                # built in C (GMP); the doubles: one rounding of |s| < 2**61, then an
                # exact scaling (2**-63 is far from the subnormals)
                point = _new_point2(
                    _grid_mpq(None, sx, half), _grid_mpq(None, sy, half),
                    ldexp(<double>sx, -half), ldexp(<double>sy, -half))
        if point is None:
            pu = <tuple>self.points[u]
            pv = <tuple>self.points[v]
            # (times 1/2: dividing by 2 would convert the int 2 to a rational each time)
            mx = (pu[0] + pv[0]) * _HALF
            my = (pu[1] + pv[1]) * _HALF
            try:
                # Point2(mx, my, fx, fy) without the Python-level __new__ of the NamedTuple
                point = _new_point2(mx, my, float(mx), float(my))
            except OverflowError:
                point = point2(mx, my)
        return self._add_point(point, grid, sx >> 1, sy >> 1)

    cdef int64_t _add_point(self, point, int grid=-1, int64_t gx=0,
                            int64_t gy=0) except -1:
        """A new vertex at the ``Point2`` ``point`` (as the ops' ``add_vertex``,
        no marker).  ``grid``: 1 when it is the grid point (gx, gy), 0 when it is off the
        grid, -1 when not known (then its coordinates are tested)."""
        cdef int64_t n = self.store.nv
        cdef TriVertex *vertex
        # a Point2 is a tuple: indexed as one (its class's item lookup is slower)
        cdef tuple fields = <tuple>point
        if n >= _MAX_VERTICES:
            raise PreconditionError("add_vertex", f"more than {MAX_VERTICES} vertices")
        store_vertex_room(&self.store)
        if n == self.cap_sectorless:
            grow_array(<void **>&self.sectorless, &self.cap_sectorless, sizeof(uint8_t))
        self.sectorless[n] = 0
        self.points.append(point)
        vertex = &self.store.vs[n]
        vertex.at.fx = fields[2]
        vertex.at.fy = fields[3]
        if grid < 0:
            vertex.at.grid = self._on_grid(fields[0], vertex.at.fx, &vertex.at.gx) and (
                self._on_grid(fields[1], vertex.at.fy, &vertex.at.gy))
        else:
            vertex.at.grid = grid
            if grid:
                vertex.at.gx = gx
                vertex.at.gy = gy
        vertex.key = gx_cached_vertex_key(<uint64_t>n)  # digest.vertex_key, in C
        vertex.hint = -1
        vertex.inside = -1
        self.store.nv = n + 1
        if vertex.at.grid:
            self.store.digest += gx_grid_vertex_hash(n, vertex.at.gx, vertex.at.gy, self.F)
        else:
            self.store.digest += _vertex_hash(n, fields[0], fields[1])
        return n

    cdef bint _grid_centroid(self, int64_t u, int64_t v, int64_t w, int64_t x,
                             int64_t *out) except -1:
        """``rounded_area_centroid(u, v, w, x)`` in grid integers when the four corners
        and the first candidate are grid points and that candidate is strictly inside
        (``out``: its grid coordinates); False otherwise (the caller asks Python).

        With s the shortest squared side in grid units, the rounding exponent is
        e = floor(log2(s × 2^-2F)) // 2 − CENTROID_BITS, i.e. 2^(e + F) grid units; the
        exact centroid is u + n / D (D = 3 (A1 + A2), Ai the doubled areas), rounded
        half up to a multiple of 2^(e + F)."""
        cdef TriVertex *pu = &self.store.vs[u]
        cdef TriVertex *pv = &self.store.vs[v]
        cdef TriVertex *pw = &self.store.vs[w]
        cdef TriVertex *px = &self.store.vs[x]
        cdef gx_i128 shortest, length, dx, dy
        cdef int64_t exponent, cx, cy
        cdef int k
        cdef TriVertex *ends[5]
        if not (pu.at.grid and pv.at.grid and pw.at.grid and px.at.grid):
            return False
        ends[0], ends[1], ends[2], ends[3], ends[4] = pu, px, pv, pw, pu
        shortest = -1
        for k in range(4):
            dx = <gx_i128>ends[k + 1].at.gx - ends[k].at.gx
            dy = <gx_i128>ends[k + 1].at.gy - ends[k].at.gy
            length = dx * dx + dy * dy
            if shortest < 0 or length < shortest:
                shortest = length
        # (>> 1: floor division by 2, as // in Python)
        exponent = ((_bit_length(shortest) - 1 - 2 * self.F) >> 1) - _CENTROID_BITS + self.F
        if exponent < 0 or exponent > 62:
            return False
        a1 = _from_i128(gx_grid_area2(pu.at.gx, pu.at.gy, pv.at.gx, pv.at.gy,
                                      pw.at.gx, pw.at.gy))
        a2 = _from_i128(gx_grid_area2(pv.at.gx, pv.at.gy, pu.at.gx, pu.at.gy,
                                      px.at.gx, px.at.gy))
        denominator = 3 * (a1 + a2)
        if denominator <= 0:
            return False
        half = denominator << exponent
        whole = half << 1
        for k in range(2):
            if k == 0:
                base = pu.at.gx
                offset = (a1 * ((pv.at.gx - pu.at.gx) + (pw.at.gx - pu.at.gx))
                          + a2 * ((pv.at.gx - pu.at.gx) + (px.at.gx - pu.at.gx)))
            else:
                base = pu.at.gy
                offset = (a1 * ((pv.at.gy - pu.at.gy) + (pw.at.gy - pu.at.gy))
                          + a2 * ((pv.at.gy - pu.at.gy) + (px.at.gy - pu.at.gy)))
            # floor((base + offset / D) / 2^e + 1/2), base = q 2^e + r
            q = base >> exponent
            r = base - (q << exponent)
            rounded = (q + (2 * (r * denominator + offset) + half) // whole) << exponent
            if abs(rounded) > GRID_LIMIT:
                return False
            out[k] = rounded
        cx, cy = out[0], out[1]
        return (
            gx_grid_orient(pu.at.gx, pu.at.gy, px.at.gx, px.at.gy, cx, cy) == 1
            and gx_grid_orient(px.at.gx, px.at.gy, pv.at.gx, pv.at.gy, cx, cy) == 1
            and gx_grid_orient(pv.at.gx, pv.at.gy, pw.at.gx, pw.at.gy, cx, cy) == 1
            and gx_grid_orient(pw.at.gx, pw.at.gy, pu.at.gx, pu.at.gy, cx, cy) == 1
        )

    cdef bint _float_centroid(self, int64_t u, int64_t v, int64_t w, int64_t x,
                              int64_t *out) except -1:
        """``rounded_area_centroid(u, v, w, x)`` from the doubles of corners off the grid,
        when a certified float evaluation decides it: the rounding exponent (the shortest
        squared side's floor(log2), from intervals around each side) and each rounded
        coordinate floor(C / 2^e + 1/2) (no integer within the error bound of the float
        value), giving a grid point that is then tested strictly inside the four new
        triangles (``orient2d``, filter then exact).  ``out``: its grid coordinates; False
        (the caller asks Python) when anything is undecided or off the kernel's grid.

        Error bounds (u = 2^-53): each double is within u of its exact coordinate, so each
        difference of two is within E = 6 u m (m the largest |coordinate|); products and
        sums carry the errors of their operands plus u per rounding, every bound taken
        with a margin."""
        cdef GridPoint *pu = &self.store.vs[u].at
        cdef GridPoint *pv = &self.store.vs[v].at
        cdef GridPoint *pw = &self.store.vs[w].at
        cdef GridPoint *px = &self.store.vs[x].at
        cdef GridPoint *ring[5]
        cdef GridPoint candidate
        cdef double m, e, dx, dy, big, side, err, low, high
        cdef double ax, ay, bx, by, cx, cy, sa, sb, sc, a1, a2, ea1, ea2, total, etotal
        cdef double p1, p2, ep1, ep2, q1, q2, eq1, eq2, num, enum, off, eoff, base, value
        cdef double ev, scaled, delta, slack, lower, upper
        cdef int k, exp_low, exp_high, shift
        cdef int64_t exponent, whole
        ring[0], ring[1], ring[2], ring[3], ring[4] = pu, px, pv, pw, pu
        m = 0.0
        for k in range(4):
            m = max(m, fabs(ring[k].fx), fabs(ring[k].fy))
        if not (2.0 ** -400 < m < 2.0 ** 400):
            return False
        e = 6.0 * UNIT * m
        # the exponent: floor(log2(shortest squared side)) // 2 - CENTROID_BITS
        low = high = INFINITY
        for k in range(4):
            dx = ring[k + 1].fx - ring[k].fx
            dy = ring[k + 1].fy - ring[k].fy
            big = fabs(dx) + fabs(dy)
            side = dx * dx + dy * dy
            err = (e * (2.0 * big + 2.0 * e) + 3.0 * UNIT * big * big) * 1.0001
            low = min(low, side - err)
            high = min(high, side + err)
        low *= 1.0 - 4.0 * UNIT
        high *= 1.0 + 4.0 * UNIT
        if not low > 0.0:
            return False
        frexp(low, &exp_low)
        frexp(high, &exp_high)
        if exp_low != exp_high:
            return False
        exponent = ((exp_low - 1) >> 1) - _CENTROID_BITS
        shift = <int>(exponent + self.F)
        if shift < 0 or shift > 62:
            return False
        # the centroid, from u: u + (A1 (a + b) + A2 (a + c)) / 3 (A1 + A2)
        ax = pv.fx - pu.fx
        ay = pv.fy - pu.fy
        bx = pw.fx - pu.fx
        by = pw.fy - pu.fy
        cx = px.fx - pu.fx
        cy = px.fy - pu.fy
        sa = fabs(ax) + fabs(ay)
        sb = fabs(bx) + fabs(by)
        sc = fabs(cx) + fabs(cy)
        a1 = ax * by - ay * bx
        a2 = cx * ay - cy * ax
        ea1 = e * (sa + sb) + 2.0 * e * e + 3.0 * UNIT * sa * sb
        ea2 = e * (sc + sa) + 2.0 * e * e + 3.0 * UNIT * sc * sa
        total = 3.0 * (a1 + a2)
        etotal = (3.0 * (ea1 + ea2) + 6.0 * UNIT * (fabs(a1) + fabs(a2))) * 1.0001
        if not total > 2.0 * etotal:
            return False
        for k in range(2):
            if k == 0:
                p1, p2, base = ax + bx, ax + cx, pu.fx
            else:
                p1, p2, base = ay + by, ay + cy, pu.fy
            ep1 = 2.0 * e + UNIT * fabs(p1)
            ep2 = 2.0 * e + UNIT * fabs(p2)
            q1 = a1 * p1
            q2 = a2 * p2
            eq1 = fabs(a1) * ep1 + fabs(p1) * ea1 + ea1 * ep1 + UNIT * fabs(q1)
            eq2 = fabs(a2) * ep2 + fabs(p2) * ea2 + ea2 * ep2 + UNIT * fabs(q2)
            num = q1 + q2
            enum = eq1 + eq2 + UNIT * (fabs(q1) + fabs(q2))
            off = num / total
            eoff = (enum + fabs(off) * etotal) / (total - etotal) + UNIT * fabs(off)
            value = base + off
            ev = (eoff + e + UNIT * fabs(value)) * 1.001
            # floor(C / 2^e + 1/2): no integer between the bounds of the float value
            scaled = ldexp(value, <int>-exponent) + 0.5
            if not fabs(scaled) < 2.0 ** 48:
                return False
            delta = (ldexp(ev, <int>-exponent) + UNIT * fabs(scaled)) * 1.001
            slack = 8.0 * UNIT * fabs(scaled) + 2.0 ** -30
            lower = floor(scaled - delta - slack)
            upper = floor(scaled + delta + slack)
            if lower != upper:
                return False
            whole = <int64_t>lower
            if whole > (<int64_t>1 << (60 - shift)) or whole < -(<int64_t>1 << (60 - shift)):
                return False
            out[k] = whole << shift
        candidate.grid = 1
        candidate.gx = out[0]
        candidate.gy = out[1]
        candidate.fx = ldexp(<double>out[0], -self.F)
        candidate.fy = ldexp(<double>out[1], -self.F)
        return (self._orient_candidate(u, x, &candidate, out) == 1
                and self._orient_candidate(x, v, &candidate, out) == 1
                and self._orient_candidate(v, w, &candidate, out) == 1
                and self._orient_candidate(w, u, &candidate, out) == 1)

    cdef int _orient_candidate(self, int64_t a, int64_t b, GridPoint *c,
                               int64_t *at) except -2:
        """The sign of orient2d(a, b, the grid point ``at``) (its GridPoint ``c``)."""
        cdef int result = filtered_orient(&self.store.vs[a].at, &self.store.vs[b].at, c)
        if result != 2:
            return result
        from geomexact.kernel.predicates2d import orient2d_exact
        points = self.points
        return int(orient2d_exact(points[a], points[b],
                                  point2(mpq(at[0], self.unit), mpq(at[1], self.unit))))

    # -- predicates (exact): ckernel.pxd's, on these vertices -----------------------------
    cdef int _orient(self, int64_t a, int64_t b, int64_t c) except -2:
        return orient_sign(&self.store.vs[a].at, &self.store.vs[b].at, &self.store.vs[c].at, self.points, a, b, c)

    cdef int _incircle(self, int64_t a, int64_t b, int64_t c, int64_t d) except -2:
        return incircle_sign(&self.store.vs[a].at, &self.store.vs[b].at, &self.store.vs[c].at, &self.store.vs[d].at,
                             self.points, a, b, c, d)

    cdef int _lengths(self, int64_t a, int64_t b, int64_t c, int64_t d) except -2:
        """The sign of |ab|² - |cd|² (compare_squared_lengths)."""
        cdef int result = filtered_lengths(&self.store.vs[a].at, &self.store.vs[b].at, &self.store.vs[c].at,
                                           &self.store.vs[d].at)
        if result != 2:
            return result
        # undecided: nearly or exactly equal lengths off the grid (isosceles triangles
        # of decimal inputs), which Lepp searches compare again and again: each pair of
        # edges is decided exactly once
        cdef int64_t p0 = min(a, b), p1 = max(a, b), q0 = min(c, d), q1 = max(c, d)
        cdef int flip = 1
        if (p0, p1) > (q0, q1):
            p0, p1, q0, q1, flip = q0, q1, p0, p1, -1
        key = (p0, p1, q0, q1)
        found = self.exact_lengths.get(key)
        if found is None:
            points = self.points
            found = self.exact_lengths[key] = int(_comparisons.compare_squared_lengths(
                points[p0], points[p1], points[q0], points[q1]))
        return flip * <int>found

    cdef int _dot_sign(self, int64_t p, int64_t a, int64_t b) nogil:
        """The sign of (a - p).(b - p), or 2 when the float filter cannot tell."""
        return filtered_dot(&self.store.vs[p].at, &self.store.vs[a].at, &self.store.vs[b].at)

    # -- region, rating, queue ----------------------------------------------------------
    cdef bint _in_region(self, int64_t a, int64_t b, int64_t c) except -1:
        """True when a vertex of the triangle is in the region (cached per vertex)."""
        if self.whole:
            return True
        return self._inside(a) or self._inside(b) or self._inside(c)

    cdef bint _inside(self, int64_t vertex) except -1:
        cdef TriVertex *record = &self.store.vs[vertex]
        if record.inside < 0:
            record.inside = 1 if self.contains(self.points[vertex]) else 0
        return record.inside

    cdef int _account(self, int64_t a, int64_t b, int64_t c, int sign) except -1:
        """``Refinement.account`` for one triangle (any rotation) added (sign 1) or
        removed (sign -1): its doubled area and itself counted when it is in the region."""
        cdef TriVertex *va
        cdef TriVertex *vb
        cdef TriVertex *vc
        if not self.whole and not self._in_region(a, b, c):
            return 0
        va = &self.store.vs[a]
        vb = &self.store.vs[b]
        vc = &self.store.vs[c]
        self.count += sign
        if va.at.grid and vb.at.grid and vc.at.grid:
            if sign > 0:
                self.gsum += gx_grid_area2(va.at.gx, va.at.gy, vb.at.gx, vb.at.gy,
                                           vc.at.gx, vc.at.gy)
            else:
                self.gsum -= gx_grid_area2(va.at.gx, va.at.gy, vb.at.gx, vb.at.gy,
                                           vc.at.gx, vc.at.gy)
            return 0
        points = self.points
        area2 = _doubled_area(points[a], points[b], points[c])
        self.pycount += sign
        if sign > 0:
            self.pysum += area2
        else:
            self.pysum -= area2
        return 0

    cdef bint _mean_reached(self) except -1:
        """``Refinement.mean_reached``: no triangle in the region, or its doubled area
        at most ``target2 * count``, exact."""
        cdef double s, t
        if self.count == 0:
            return True
        if self.pycount == 0:
            # all on the grid: gsum <= target2 * 2**2F * count; the float filter's error
            # is below 2**-50 (relative), its margin 2**-40
            if self.filtered:
                s = <double>self.gsum
                t = self.target_grid * <double>self.count
                if s < t * (1.0 - 2.0 ** -40):
                    return True
                if s > t * (1.0 + 2.0 ** -40):
                    return False
            return bool(_from_i128(self.gsum) <= self.target_scaled * self.count)
        total = _from_i128(self.gsum) / self.scale + self.pysum
        return bool(total <= self.target2 * self.count)

    def mean_state(self):
        """(region doubled area, count, target doubled mean area), exact (for tests)."""
        if not self.tracking:
            return None
        return (_from_i128(self.gsum) / self.scale + self.pysum, self.count, self.target2)

    cdef int _consider(self, int64_t a, int64_t b, int64_t c) except -1:
        """Queue the canonical triangle (a, b, c) when it is bad (the caller checked the
        region, except at the start)."""
        cdef Entry entry
        if not self.whole and not self._in_region(a, b, c):
            return 0
        entry.a = a
        entry.b = b
        entry.c = c
        entry.group = 0
        if self.min_angle:
            return self._consider_angle(&entry)
        if self.max_area:  # MaxArea, AverageAreaFactor: grid triangles rated in C
            self._consider_area(&entry)
            return 0
        points = self.points
        if self.rate_attributes:
            key = self.rate(points[a], points[b], points[c], self._attributes(a, b))
        else:
            key = self.rate(points[a], points[b], points[c])
        if key is None:
            return 0
        return self._push_key(&entry, key)

    cdef int _push_key(self, Entry *entry, object key) except -1:
        """Queue the entry with a Python key (its float rank for most comparisons)."""
        entry.ikey = 0
        entry.rank = _rank(key)
        entry.py = len(self.pykeys)
        self.pykeys.append(key)
        return self._push(entry)

    # -- the minimum angle (MinAngle.rate and the small-angle rules of Refinement) ---------
    cdef int _angle(self, int64_t a, int64_t b, int64_t c) except -2:
        """``compare_angle(points[a], points[b], points[c], threshold)`` (the angle at b)
        as -1, 0, 1: its two-stage float filter, same formulas and constants, else the
        exact Python comparison."""
        cdef GridPoint *pa = &self.store.vs[a].at
        cdef GridPoint *pb = &self.store.vs[b].at
        cdef GridPoint *pc = &self.store.vs[c].at
        cdef double bx = pb.fx, by = pb.fy
        cdef double ux = pa.fx - bx, uy = pa.fy - by, vx = pc.fx - bx, vy = pc.fy - by
        cdef double dot = ux * vx + uy * vy
        cdef double lu = ux * ux + uy * uy
        cdef double lv = vx * vx + vy * vy
        cdef double t = fabs(ux) + fabs(uy) + fabs(vx) + fabs(vy) + DOT_K
        cdef double mt = fabs(bx) + fabs(by) + t
        cdef double bound = t * mt * DOT_C
        cdef double difference
        cdef int dot_sign
        if dot > bound:
            dot_sign = 1
        elif -dot > bound:
            dot_sign = -1
        else:
            return self._angle_exact(a, b, c)
        if dot_sign != self.cos_sign:
            return -dot_sign
        difference = self.cos2f * lu * lv - dot * dot
        t += ANGLE_K
        bound = t * t * t * (mt + ANGLE_K) * ANGLE_C
        if difference > bound or -difference > bound:
            return self.cos_sign if difference > 0.0 else -self.cos_sign
        return self._angle_exact(a, b, c)

    cdef int _angle_exact(self, int64_t a, int64_t b, int64_t c) except -2:
        points = self.points
        return int(_compare_angle(points[a], points[b], points[c], self.threshold))

    cdef int _consider_angle(self, Entry *entry) except -1:
        """``Refinement.consider`` for ``MinAngle``: its ``rate`` (the angle opposite the
        shortest edge against the threshold; key −cos² of it, exact), then the
        sharp-corner rule (left, not queued)."""
        cdef int64_t a = entry.a, b = entry.b, c = entry.c, p, q, r
        # the corner p opposite the shortest edge, and its arms q, r (smallest_angle_cos2)
        if self._lengths(a, b, b, c) != 1:
            if self._lengths(a, b, c, a) != 1:
                p, q, r = c, a, b
            else:
                p, q, r = b, c, a
        elif self._lengths(b, c, c, a) != 1:
            p, q, r = a, b, c
        else:
            p, q, r = b, c, a
        if self._angle(q, p, r) != -1:
            return self._consider_area(entry) if self.combined else 0
        if self._unimprovable(a, b, c):
            if self.combined and self._consider_area(entry):
                return 1  # too large still: queued for its area
            self.left[(a, b, c)] = SHARP_CORNER
            return 0
        entry.ikey = 0
        entry.py = -1
        self._angle_rank(entry, p, q, r)
        return self._push(entry)

    cdef int _consider_area(self, Entry *entry) except -1:
        """An area criterion (``MaxArea``, ``AverageAreaFactor``, or AnyOf's second
        criterion): queue the entry in group 1 when its triangle is bad (a MaxArea or a
        factor: key −(doubled area), in grid units on the grid; else the criterion's own
        exact key); 1 when queued."""
        cdef TriVertex *va = &self.store.vs[entry.a]
        cdef TriVertex *vb = &self.store.vs[entry.b]
        cdef TriVertex *vc = &self.store.vs[entry.c]
        entry.group = 1
        if va.at.grid and vb.at.grid and vc.at.grid:
            if self.max_area:
                return self._queue_grid_area(entry, self.area_limit)
            if self.region_limits is not None:
                # RegionAreas.rate_attributed: the region is the first attribute
                attributes = self._attributes(entry.a, entry.b)
                limit = self.region_limits.get(attributes[0]) if attributes else None
                return 0 if limit is None else self._queue_grid_area(entry, limit)
        points = self.points
        if self.rate_attributes:
            key = self.area_rate(points[entry.a], points[entry.b], points[entry.c],
                                 self._attributes(entry.a, entry.b))
        else:
            key = self.area_rate(points[entry.a], points[entry.b], points[entry.c])
        if key is None:
            return 0
        if self.grouped:
            entry.group, key = key
        self._push_key(entry, key)
        return 1

    cdef int _queue_grid_area(self, Entry *entry, gx_i128 limit) except -1:
        """Queue the entry's grid triangle, key −(doubled area in grid units), when that
        area exceeds ``limit``; 1 when queued."""
        cdef TriVertex *va = &self.store.vs[entry.a]
        cdef TriVertex *vb = &self.store.vs[entry.b]
        cdef TriVertex *vc = &self.store.vs[entry.c]
        cdef gx_i128 area2 = gx_grid_area2(va.at.gx, va.at.gy, vb.at.gx, vb.at.gy,
                                           vc.at.gx, vc.at.gy)
        if area2 <= limit:
            return 0
        entry.ikey = -area2
        entry.rank = 0.0
        entry.py = -1
        self._push(entry)
        return 1

    cdef int _angle_rank(self, Entry *entry, int64_t p, int64_t q, int64_t r) except -1:
        """Set ``rank`` and ``rad``: −cos² of the angle at p between q and r lies within
        ``rad`` of ``rank``.  On the grid from the exact ``__int128`` dot product and
        squared lengths (four roundings to double and three operations: relative error
        below 12 u, 16 u taken); off the grid from the doubles, with the error of each
        coordinate difference bounded by E = 6 u max|coordinate| and carried through the
        dot product and lengths; else (extreme magnitudes) the exact key."""
        cdef TriVertex *vp = &self.store.vs[p]
        cdef TriVertex *vq = &self.store.vs[q]
        cdef TriVertex *vr = &self.store.vs[r]
        cdef gx_i128 gux, guy, gvx, gvy
        cdef double dot, lu, lv, cos2, ux, uy, vx, vy, m, e, su, sv, edot, elu, elv
        cdef double low, high
        if vp.at.grid and vq.at.grid and vr.at.grid:
            gux = <gx_i128>vq.at.gx - vp.at.gx
            guy = <gx_i128>vq.at.gy - vp.at.gy
            gvx = <gx_i128>vr.at.gx - vp.at.gx
            gvy = <gx_i128>vr.at.gy - vp.at.gy
            dot = <double>(gux * gvx + guy * gvy)
            lu = <double>(gux * gux + guy * guy)
            lv = <double>(gvx * gvx + gvy * gvy)
            cos2 = (dot * dot) / (lu * lv)
            entry.rank = -cos2
            entry.rad = 16.0 * UNIT * cos2
            return 0
        m = fabs(vp.at.fx)
        m = max(m, fabs(vp.at.fy), fabs(vq.at.fx), fabs(vq.at.fy), fabs(vr.at.fx),
                fabs(vr.at.fy))
        ux = vq.at.fx - vp.at.fx
        uy = vq.at.fy - vp.at.fy
        vx = vr.at.fx - vp.at.fx
        vy = vr.at.fy - vp.at.fy
        su = fabs(ux) + fabs(uy)
        sv = fabs(vx) + fabs(vy)
        if not (m < 2.0 ** 200 and su > 2.0 ** -200 and sv > 2.0 ** -200
                and m * 2.0 ** -100 < min(su, sv)):
            return self._exact_rank(entry)
        e = 6.0 * UNIT * m
        dot = ux * vx + uy * vy
        lu = ux * ux + uy * uy
        lv = vx * vx + vy * vy
        # (1.0001: the roundings of the bounds themselves)
        edot = (e * (su + sv + 2.0 * e) + 3.0 * UNIT * su * sv) * 1.0001
        elu = (e * (2.0 * su + 2.0 * e) + 3.0 * UNIT * su * su) * 1.0001
        elv = (e * (2.0 * sv + 2.0 * e) + 3.0 * UNIT * sv * sv) * 1.0001
        if not (dot > edot and lu > elu and lv > elv):
            return self._exact_rank(entry)
        low = (dot - edot) * (dot - edot) / ((lu + elu) * (lv + elv)) * (1.0 - 8.0 * UNIT)
        high = (dot + edot) * (dot + edot) / ((lu - elu) * (lv - elv)) * (1.0 + 8.0 * UNIT)
        entry.rank = -0.5 * (low + high)
        entry.rad = 0.5 * (high - low) + 8.0 * UNIT * high
        return 0

    cdef int _exact_rank(self, Entry *entry) except -1:
        """``rank`` from the exact key (correctly rounded, so within 2^-53 of it)."""
        key = self._angle_key(entry)
        entry.rank = float(key)
        entry.rad = 2.0 * UNIT * abs(entry.rank)
        return 0

    cdef bint _sector(self, int64_t p, int64_t q, int64_t r, int64_t *ends) except -1:
        """``Refinement.constraint_sector(p, q, r)``: False when p has no sector, else
        True with the far ends of its two constraint edges in ``ends``."""
        cdef int64_t first, last
        if self.sectorless[p]:
            return False
        first = self._walk_to_constraint(p, q, r, True, r)
        if first < 0:
            self.sectorless[p] = 1
            return False  # all the way round
        last = self._walk_to_constraint(p, r, q, False, -1)
        ends[0] = first
        ends[1] = last
        return True

    cdef int64_t _walk_to_constraint(self, int64_t p, int64_t e, int64_t inner,
                                     bint forward, int64_t stop) except -2:
        """Walk round p from the edge p-e, whose triangle on the side walked from has the
        apex ``inner`` (apex(p, e) when ``forward``, else apex(e, p)), to the first
        constraint edge p-e: its far end e, or -1 when the walk reaches p-``stop``."""
        cdef int64_t outer, left, right
        while True:
            # of the edge's two apexes only the next one is looked up
            if forward:
                outer = store_apex(&self.store, e, p)
                left, right = inner, outer
            else:
                outer = store_apex(&self.store, p, e)
                left, right = outer, inner
            if self._constraint_known(p, e, left, right):
                return e
            e, inner = outer, e
            if e == stop:
                return -1

    cdef bint _sharp(self, int64_t p, int64_t q, int64_t r) except -1:
        """``Refinement.sharp``: the triangle (p, q, r) lies in a sector at p whose
        constraint edges meet at an angle below the threshold (under 180°)."""
        cdef int64_t ends[2]
        if not self._sector(p, q, r, ends):
            return False
        # the angle first: at a vertex of a straight constraint line the filter decides it
        # (180°) where orient2d, exactly 0, would need the exact predicate
        return (self._angle(ends[0], p, ends[1]) == -1
                and self._orient(p, ends[0], ends[1]) == 1)

    cdef bint _unimprovable(self, int64_t a, int64_t b, int64_t c) except -1:
        """``Refinement.unimprovable``: an angle of (a, b, c) below the threshold lies in
        an input angle below it."""
        cdef int64_t p, q, r
        cdef int k
        for k in range(3):
            if k == 0:
                p, q, r = a, b, c
            elif k == 1:
                p, q, r = b, c, a
            else:
                p, q, r = c, a, b
            if self.sectorless[p] or self._angle(q, p, r) != -1:
                continue
            if self._sharp(p, q, r):
                return True
        return False

    cdef list _start_constraint_ends(self, int64_t vertex):
        """The far ends of the constraint edges at the input vertex ``vertex`` in the start
        mesh, its star walked as ``snapshot.walk_star`` walks it, on the start's
        half-edges."""
        cdef int64_t first, previous, w, x, hint = self.start_hints[vertex]
        cdef list ends = []
        cdef list constrained = []
        cdef int64_t left, right
        if hint < 0:
            return constrained
        first = hint
        while True:  # clockwise to the boundary, or all the way round
            previous = self._start_apex(first, vertex)
            if previous < 0:
                break
            if previous == hint:
                first = hint
                break
            first = previous
        w = first
        x = -1
        while True:
            x = self._start_apex(vertex, w)
            if x < 0:
                break
            ends.append(w)
            w = x
            if w == first:
                break
        if ends and x < 0:
            ends.append(w)  # a boundary vertex: the last edge of the fan
        for w in ends:
            # is_constraint_edge on the start: a boundary edge, a segment or an
            # attribute border
            left = self._start_apex(vertex, w)
            right = self._start_apex(w, vertex)
            if (left >= 0 and right >= 0
                    and ((vertex, w) if vertex < w else (w, vertex))
                    not in self.start_segments
                    and not (self.attributed and self.start_tattrs.get(
                        _canonical(vertex, w, left)) != self.start_tattrs.get(
                            _canonical(w, vertex, right)))):
                continue
            constrained.append(w)
        return constrained

    cdef object _tip_limit(self, int64_t vertex):
        """``Refinement.tip_limit`` of the input vertex ``vertex``: (2^-TIP_DEPTH × its
        shortest constraint edge in the start mesh)², or None with fewer than two."""
        cdef TriVertex *a = &self.store.vs[vertex]
        cdef TriVertex *b
        cdef gx_i128 dx, dy
        lengths = []
        for w in self._start_constraint_ends(vertex):
            b = &self.store.vs[<int64_t>w]
            if a.at.grid and b.at.grid:
                dx = <gx_i128>b.at.gx - a.at.gx
                dy = <gx_i128>b.at.gy - a.at.gy
                lengths.append(_from_i128(dx * dx + dy * dy) / self.scale)
            else:
                lengths.append(_squared_length(self.points[vertex], self.points[w]))
        if len(lengths) < 2:
            return None
        return min(lengths) / 4**TIP_DEPTH

    cdef int _tip_interval(self, int64_t vertex) except -1:
        """Set ``tip_state`` of the input vertex ``vertex``, and when it has a tip limit,
        doubles around it (unbounded where the doubles cannot bound it): the least of
        its constraint edges' squared-length bounds, times 4^-TIP_DEPTH (exact)."""
        cdef double low = INFINITY, high = INFINITY, edge_low, edge_high
        cdef bint bounded = True
        ends = self._start_constraint_ends(vertex)
        if len(ends) < 2:
            self.tip_state[vertex] = 1
            return 0
        for w in ends:
            if not _length_interval(&self.store.vs[vertex].at,
                                    &self.store.vs[<int64_t>w].at, &edge_low, &edge_high):
                bounded = False
                break
            low = min(low, edge_low)
            high = min(high, edge_high)
        # (2^-1000: the scaled bounds stay normal doubles, so the scaling is exact)
        if bounded and low > 2.0 ** -1000:
            self.tip_low[vertex] = ldexp(low, -2 * _TIP_DEPTH)
            self.tip_high[vertex] = ldexp(high, -2 * _TIP_DEPTH)
        else:
            self.tip_low[vertex] = -INFINITY
            self.tip_high[vertex] = INFINITY
        self.tip_state[vertex] = 2
        return 0

    cdef bint _under_tip(self, int64_t p, int64_t u, int64_t v) except -1:
        """True when p (an input vertex) has a tip limit and the edge {u, v} is shorter
        than it (``Refinement.protected``'s length test, exact): the doubles' bounds of
        both decide where they are apart, else the exact values."""
        cdef TriVertex *vu
        cdef TriVertex *vv
        cdef gx_i128 dx, dy
        cdef double low, high
        if p >= self.n0:
            return False  # only input vertices have tip limits
        if self.tip_state[p] == 0:
            self._tip_interval(p)
        if self.tip_state[p] == 1:
            return False
        vu = &self.store.vs[u]
        vv = &self.store.vs[v]
        if _length_interval(&vu.at, &vv.at, &low, &high):
            if high < self.tip_low[p]:
                return True
            if low >= self.tip_high[p]:
                return False
        entry = self.tip_grid.get(p)
        if entry is None:
            limit = self._tip_limit(p)
            # the limit in grid units, rounded up: a grid length (an integer) is below the
            # limit exactly when it is below this
            bound = None if limit is None else min(-((-limit * self.scale) // 1), 1 << 124)
            entry = self.tip_grid[p] = (limit, bound)
        limit, bound = entry
        if limit is None:
            return False
        if vu.at.grid and vv.at.grid:
            dx = <gx_i128>vv.at.gx - vu.at.gx
            dy = <gx_i128>vv.at.gy - vu.at.gy
            return _from_i128(dx * dx + dy * dy) < bound
        points = self.points
        pu, pv = <tuple>points[u], <tuple>points[v]
        ex = (<tuple>pv)[0] - (<tuple>pu)[0]
        ey = (<tuple>pv)[1] - (<tuple>pu)[1]
        return ex * ex + ey * ey < limit

    cdef bint _protected(self, int64_t u, int64_t v) except -1:
        """``Refinement.protected``: the constraint edge {u, v} bounds a sharp input angle
        at u or v and is shorter than that corner's tip limit."""
        cdef int64_t p, s, left, right
        cdef int k
        if not self.min_angle:
            return False
        for k in range(2):
            if k == 0:
                p, s = u, v
            else:
                p, s = v, u
            if not self._under_tip(p, u, v):
                continue
            left = store_apex(&self.store, p, s)
            right = store_apex(&self.store, s, p)
            if left >= 0 and self._sharp(p, s, left):
                return True
            if right >= 0 and self._sharp(p, right, s):
                return True
        return False

    def left_triangles(self):
        """``Refinement.left_triangles``: the left triangles still in the mesh, sorted."""
        return tuple(sorted(self.left if self.sealed else self._still_left()))

    cdef dict _still_left(self):
        """The left triangles still in the mesh, with why they were left."""
        return {t: why for t, why in self.left.items()
                if store_apex(&self.store, t[0], t[1]) == t[2]}

    def left_reasons(self):
        """``Refinement.left_reasons``: why each of :meth:`left_triangles` was left."""
        return tuple(self.left[t] for t in self.left_triangles())

    cdef inline int _less(self, Entry *x, Entry *y) except -1:
        """(key, triangle) of x < that of y, keys compared exactly (AnyOf: its group,
        then the group's key; the "passes" order: the pass, then the triangle)."""
        if self.passes:
            if x.ikey != y.ikey:
                return x.ikey < y.ikey
            return _triangle_less(x, y)
        if x.group != y.group:
            return x.group < y.group
        if self.min_angle and x.group == 0:
            # the certified intervals decide, else the exact keys
            if x.rank + x.rad < y.rank - y.rad:
                return True
            if y.rank + y.rad < x.rank - x.rad:
                return False
            return self._less_exact_angle(x, y)
        if x.py < 0 and y.py < 0:
            if x.ikey != y.ikey:
                return x.ikey < y.ikey
            return _triangle_less(x, y)
        return self._less_python(x, y)

    cdef object _angle_key(self, Entry *entry):
        """The exact MinAngle key of the entry's triangle (made once)."""
        if entry.py < 0:
            points = self.points
            entry.py = len(self.pykeys)
            self.pykeys.append(-_smallest_angle_cos2(points[entry.a], points[entry.b],
                                                     points[entry.c]))
        return self.pykeys[entry.py]

    cdef int _less_exact_angle(self, Entry *x, Entry *y) except -1:
        kx = self._angle_key(x)
        ky = self._angle_key(y)
        if not (kx == ky):
            return bool(kx < ky)
        return _triangle_less(x, y)

    cdef int _less_python(self, Entry *x, Entry *y) except -1:
        """_less when a key is a Python object."""
        if x.py >= 0 and y.py >= 0:
            if x.rank != y.rank:
                return x.rank < y.rank
            kx = self.pykeys[x.py]
            ky = self.pykeys[y.py]
            if not (kx == ky):
                return bool(kx < ky)
        else:
            kx = self.pykeys[x.py] if x.py >= 0 else _from_i128(x.ikey) / self.scale
            ky = self.pykeys[y.py] if y.py >= 0 else _from_i128(y.ikey) / self.scale
            if not (kx == ky):
                return bool(kx < ky)
        return _triangle_less(x, y)

    cdef int _push(self, Entry *entry) except -1:
        cdef Py_ssize_t i, parent
        if self.passes:  # Refinement.consider: the key is the next pass, whatever the rating
            entry.group = 0
            entry.ikey = self.pass_number + 1
            entry.py = -1
            entry.rank = 0.0
            entry.rad = 0.0
        if self.nheap == self.cap_heap:
            grow_array(<void **>&self.heap, &self.cap_heap, sizeof(Entry))
        i = self.nheap
        self.nheap += 1
        while i > 0:
            parent = (i - 1) >> 1
            if not self._less(entry, &self.heap[parent]):
                break
            self.heap[i] = self.heap[parent]
            i = parent
        self.heap[i] = entry[0]
        return 0

    cdef bint _pop(self, Entry *out) except -1:
        cdef Py_ssize_t i = 0, child, n
        cdef Entry last
        if self.nheap == 0:
            return False
        out[0] = self.heap[0]
        self.nheap -= 1
        n = self.nheap
        if n == 0:
            return True
        last = self.heap[n]
        while True:
            child = 2 * i + 1
            if child >= n:
                break
            if child + 1 < n and self._less(&self.heap[child + 1], &self.heap[child]):
                child += 1
            if not self._less(&self.heap[child], &last):
                break
            self.heap[i] = self.heap[child]
            i = child
        self.heap[i] = last
        return True

    cdef int _drain(self) except -1:
        """Queue the triangles the last action created that are alive and bad."""
        cdef Py_ssize_t i
        cdef int64_t a, b, c
        for i in range(self.ncreated):
            a = self.created[3 * i]
            b = self.created[3 * i + 1]
            c = self.created[3 * i + 2]
            if store_apex(&self.store, a, b) != c:
                continue
            self._consider(a, b, c)
        self.ncreated = 0
        return 0

    # -- mesh edits ---------------------------------------------------------------------
    cdef int _created(self, int64_t a, int64_t b, int64_t c) except -1:
        """Note the canonical triangle (a, b, c) as created (the store added its cell
        hash): to be considered, with ``cur_attr``'s attributes, in the region's sums."""
        if self.ncreated == self.cap_created:
            grow_array(<void **>&self.created, &self.cap_created, 3 * sizeof(int64_t))
        self.created[3 * self.ncreated] = a
        self.created[3 * self.ncreated + 1] = b
        self.created[3 * self.ncreated + 2] = c
        self.ncreated += 1
        if self.attributed and self.cur_attr >= 0:
            if gx_map_set(&self.tattr, gx_edge(a, b), self.cur_attr) < 0:
                raise MemoryError
            self.store.digest += self._triangle_attribute_hash(a, b, c, self.cur_attr)
        if self.tracking:
            self._account(a, b, c, 1)
        return 0

    cdef inline int _removed(self, int64_t a, int64_t b, int64_t c) except -1:
        """What the triangle (a, b, c), any rotation, leaves beyond the store (which
        subtracts its cell hash): its attributes (their id becomes ``cur_attr``) and its
        place in the region's sums."""
        cdef int64_t p = a, q = b, r = c
        if b < a and b < c:
            p, q, r = b, c, a
        elif c < a and c < b:
            p, q, r = c, a, b
        if self.attributed:
            self.cur_attr = gx_map_get(&self.tattr, gx_edge(p, q), -1)
            if self.cur_attr >= 0:
                gx_map_del(&self.tattr, gx_edge(p, q))
                self.store.digest -= self._triangle_attribute_hash(p, q, r, self.cur_attr)
        if self.tracking:
            self._account(a, b, c, -1)
        return 0

    cdef int64_t _attribute_id(self, attributes) except -1:
        """The id of the attribute tuple ``attributes`` (numbered on first sight, with
        the tail of its digest text)."""
        found = self.attribute_ids.get(attributes)
        if found is None:
            found = self.attribute_ids[attributes] = len(self.attribute_values)
            self.attribute_values.append(attributes)
            self.attribute_tails.append((":" + _digest.attribute_text(attributes)).encode())
        return found

    cdef inline object _attributes(self, int64_t a, int64_t b):
        """The attributes of the canonical triangle whose first edge is (a, b), or None."""
        cdef int64_t found = gx_map_get(&self.tattr, gx_edge(a, b), -1)
        return None if found < 0 else self.attribute_values[found]

    cdef inline int64_t _attribute_of(self, int64_t a, int64_t b, int64_t c) noexcept:
        """The attribute id of the triangle (a, b, c), any rotation; -1 for none."""
        if b < a and b < c:
            return gx_map_get(&self.tattr, gx_edge(b, c), -1)
        if c < a and c < b:
            return gx_map_get(&self.tattr, gx_edge(c, a), -1)
        return gx_map_get(&self.tattr, gx_edge(a, b), -1)

    cdef gx_u128 _triangle_attribute_hash(self, int64_t a, int64_t b, int64_t c,
                                          int64_t attribute) except *:
        """``attribute_hash("ta", (a, b, c), attributes)`` of the attributes with id
        ``attribute`` (their text made once)."""
        cdef uint8_t message[128]
        cdef unsigned length = 4
        cdef const char *text
        cdef Py_ssize_t size
        tail = self.attribute_tails[attribute]
        size = len(<bytes>tail)
        if size <= 64:  # "ata:" and three ids (at most 60 bytes), then the tail, in C
            memcpy(message, b"ata:", 4)
            length += _decimal(a, message + length)
            message[length] = 44  # ","
            length += 1 + _decimal(b, message + length + 1)
            message[length] = 44
            length += 1 + _decimal(c, message + length + 1)
            text = <bytes>tail
            memcpy(message + length, text, size)
            return gx_blake2b_128(message, length + <unsigned>size, 0)
        payload = b"ata:%d,%d,%d" % (a, b, c) + tail
        return _to_u128(int.from_bytes(_blake2b(payload, digest_size=16).digest(), "little"))

    cdef object _step(self, StepRecord *record):
        """The Step of a record."""
        u, v = record.a, record.b
        cdef str name = <str>(<tuple>_OP_NAMES)[record.op]
        if record.op == 2:  # insert_in_quadrilateral names its point
            point = <tuple>self.points[record.c]
            x, y = (<tuple>point)[0], (<tuple>point)[1]
            return make_step(Step, &_STEP_LAYOUT, name, (u, v, x, y))
        return make_step(Step, &_STEP_LAYOUT, name, (u, v))

    cdef int _record(self, int op, int64_t u, int64_t v, int64_t extra=-1) except -1:
        cdef StepRecord *record = store_record(&self.store, op, u, v, extra, -1)
        if not self.store.nrec & 4095:
            PyErr_CheckSignals()  # Ctrl-C stops a long run (C loops never check it)
        if self.on_step is not None:
            step = self._step(record)
            self.step_objects.append(step)
            self.on_step(self.progress(self.store.nrec, step, self.triangles, self.store.nv, self.nheap))
        return 0

    cdef int _vertex_attributes(self, int64_t n, attributes) except -1:
        """Give the new vertex n its (interpolated) attributes."""
        if attributes:
            self.vtable[n] = attributes
            self.store.digest += _to_u128(_digest.attribute_hash("va", (n,), attributes))
        return 0

    cdef int _quadrilateral_attributes(self, int64_t u, int64_t v, int64_t w, int64_t x,
                                       int64_t n) except -1:
        """The vertex attributes of n inside the quadrilateral of (u, v), as the op
        ``insert_in_quadrilateral`` interpolates them (when u has some)."""
        table = self.vtable
        if table is None or not table.get(u):
            return 0
        points = self.points
        return self._vertex_attributes(n, interpolated_in_quadrilateral(
            ((points[u], table.get(u, ())), (points[v], table.get(v, ())),
             (points[w], table.get(w, ())), (points[x], table.get(x, ()))), points[n]))

    cdef int64_t _bisect(self, int64_t u, int64_t v) except -2:
        """``ops.bisect_in``: the new vertex, or -1 at the step limit (no
        change then)."""
        cdef int64_t w, x, n, p, q, r, side
        cdef uint64_t key
        if self.limit >= 0 and self.store.nrec >= self.limit:
            return -1
        w = store_apex(&self.store, u, v)
        x = store_apex(&self.store, v, u)
        key = gx_edge(u, v) if u < v else gx_edge(v, u)
        marker = None
        if gx_map_get(&self.segs, key, -1) >= 0:
            marker = self.segments[(u, v) if u < v else (v, u)]
        n = self._add_midpoint(u, v)
        if self.vattributed:
            points = self.points
            self._vertex_attributes(n, interpolated_on_edge(
                points[u], self.vtable.get(u, ()), points[v], self.vtable.get(v, ()),
                points[n]))
        if marker:
            self.new_markers[n] = marker
            self.store.digest += _to_u128(_digest.attribute_hash("vm", (n,), (marker,)))
        store_split_edge(&self.store, u, v, w, x, n)
        # each side's attributes and sums: (p, q, r) -> (p, n, r), (n, q, r)
        for side in range(2):
            if side == 0:
                p, q, r = u, v, w
            else:
                p, q, r = v, u, x
            if r >= 0:
                self._removed(p, q, r)
                self._created_any(p, n, r)
                self._created_any(n, q, r)
                self.triangles += 1
        if marker is not None:
            segments = self.segments
            del segments[(u, v) if u < v else (v, u)]
            segments[(u, n) if u < n else (n, u)] = marker
            segments[(n, v) if n < v else (v, n)] = marker
            gx_map_del(&self.segs, key)
            if (gx_map_set(&self.segs, gx_edge(u, n) if u < n else gx_edge(n, u), 0) < 0
                    or gx_map_set(&self.segs, gx_edge(n, v) if n < v else gx_edge(v, n), 0) < 0):
                raise MemoryError
            self.store.digest += (
                _to_u128(_digest.segment_hash(min(u, n), max(u, n), marker))
                + _to_u128(_digest.segment_hash(min(n, v), max(n, v), marker))
                - _to_u128(_digest.segment_hash(min(u, v), max(u, v), marker))
            )
        self._record(0, u, v)
        return n

    cdef int _flip(self, int64_t u, int64_t v, int64_t w, int64_t x) except -2:
        """``ops.flip_in`` on a flippable edge (u, v) with apexes w (left) and x (right): 0,
        or -1 at the step limit (no change then)."""
        if self.limit >= 0 and self.store.nrec >= self.limit:
            return -1
        self._removed_edge(u, v, w, x)
        store_flip(&self.store, u, v, w, x)  # (x, w, u), (w, x, v)
        self._created_any(x, w, u)
        self._created_any(w, x, v)
        self._record(1, u, v)
        return 0

    cdef int64_t _join_in_quadrilateral(self, int64_t u, int64_t v, int64_t w, int64_t x,
                                        int64_t n, int op=2) except -2:
        """(u, v, w), (v, u, x) -> (u, x, n), (x, v, n), (v, w, n), (w, u, n) for the new
        vertex n, recorded as ``op`` (``_step``: ``insert_in_quadrilateral`` by default);
        returns n."""
        self._removed_edge(u, v, w, x)
        store_remove_edge(&self.store, u, v, w, x)
        self._triangle(u, x, n)
        self._triangle(x, v, n)
        self._triangle(v, w, n)
        self._triangle(w, u, n)
        self.triangles += 2
        self._record(op, u, v, n)
        return n

    cdef int64_t _centroid(self, int64_t u, int64_t v, int64_t w, int64_t x) except -2:
        """``ReferenceRefinement.centroid`` on the interior edge (u, v) with apexes w, x
        (the rounded area centroid on the grid or by the float path where they decide,
        else ``centroid``): the new vertex, or -1 at the step limit (no change)."""
        cdef int64_t n
        cdef int64_t at[2]
        if self.limit >= 0 and self.store.nrec >= self.limit:
            return -1
        if self.grid_centroids and (self._grid_centroid(u, v, w, x, at)
                                    or self._float_centroid(u, v, w, x, at)):
            qx = _grid_mpq(self.inv_unit, at[0], self.F)
            qy = _grid_mpq(self.inv_unit, at[1], self.F)
            # the nearest doubles of at / 2**F: one rounding (int64 to double), then an
            # exact scaling (|at| / 2**F is far from the subnormals)
            point = _new_point2(qx, qy, ldexp(<double>at[0], -self.F),
                                ldexp(<double>at[1], -self.F))
            n = self._add_point(point, 1, at[0], at[1])
        else:
            points = self.points
            point = self.centroid(points[u], points[v], points[w], points[x])
            n = self._add_point(point)
        self._quadrilateral_attributes(u, v, w, x, n)
        return self._join_in_quadrilateral(u, v, w, x, n, self.centroid_op)

    cdef int _removed_edge(self, int64_t u, int64_t v, int64_t w, int64_t x) except -1:
        """``_removed`` of the triangles (u, v, w) and (v, u, x) of the interior edge
        (u, v): the new triangles take the attributes of (u, v, w), as in the ops."""
        cdef int64_t attribute
        self._removed(u, v, w)
        attribute = self.cur_attr
        self._removed(v, u, x)
        self.cur_attr = attribute
        return 0

    cdef int _triangle(self, int64_t a, int64_t b, int64_t c) except -1:
        """The ops' ``add_triangle`` (with ``cur_attr``), noted as created."""
        store_add(&self.store, a, b, c)
        return self._created_any(a, b, c)

    cdef inline int _created_any(self, int64_t a, int64_t b, int64_t c) except -1:
        """``_created`` of the triangle (a, b, c), any rotation."""
        if a < b and a < c:
            return self._created(a, b, c)
        if b < c:
            return self._created(b, c, a)
        return self._created(c, a, b)

    cdef bint _constraint(self, int64_t u, int64_t v) except -1:
        """``Refinement.constraint``: a boundary, segment or attribute-border edge."""
        return self._constraint_known(u, v, store_apex(&self.store, u, v),
                                      store_apex(&self.store, v, u))

    cdef bint _constraint_known(self, int64_t u, int64_t v, int64_t w,
                                int64_t x) except -1:
        """``_constraint(u, v)`` given its apexes w = apex(u, v), x = apex(v, u)."""
        if w < 0 or x < 0:
            return True
        if gx_map_get(&self.segs, gx_edge(u, v) if u < v else gx_edge(v, u), -1) >= 0:
            return True
        return self.attributed and self._border(u, v, w, x)

    cdef bint _border(self, int64_t u, int64_t v, int64_t w, int64_t x) except -1:
        """The triangles (u, v, w) and (v, u, x) carry different attributes."""
        return self._attribute_of(u, v, w) != self._attribute_of(v, u, x)

    cdef int _insert_midpoint(self, int64_t u, int64_t v) except -2:
        """``Refinement.insert_midpoint``: bisect (u, v), then legalize the midpoint's
        star (as ``snapshot.walk_star`` lists it); 0, or -1 at the step limit."""
        cdef int64_t w, x, n
        cdef Pair star[4]
        w = store_apex(&self.store, u, v)
        x = store_apex(&self.store, v, u)
        n = self._bisect(u, v)
        if n < 0:
            return -1
        if not self.legalize:
            return 0
        # the star of the midpoint, counter-clockwise, after the boundary gap
        if x < 0:
            star[0].a, star[0].b = v, w
            star[1].a, star[1].b = w, u
            return self._legalize(n, star, 2)
        if w < 0:
            star[0].a, star[0].b = u, x
            star[1].a, star[1].b = x, v
            return self._legalize(n, star, 2)
        star[0].a, star[0].b = u, x
        star[1].a, star[1].b = x, v
        star[2].a, star[2].b = v, w
        star[3].a, star[3].b = w, u
        return self._legalize(n, star, 4)

    cdef int _split_pair(self, int64_t u, int64_t v, int64_t w, int64_t x) except -2:
        """``Refinement.split_pair``: the midpoint of a constraint second-longest edge of
        (u, v, w), then of (v, u, x), else the centroid of the quadrilateral; legalized
        when Delaunay.  0; -1 at the step limit; 1 (no step) when that midpoint would
        split a protected edge."""
        cdef int64_t p, q, r, n, side
        cdef Pair star[4]
        if self.constraint_midpoints:
            for side in range(2):
                if side == 0:
                    p, q, r = u, v, w
                else:
                    p, q, r = v, u, x
                # Refinement.second_edge(p, q, r): the longer of (q, r), (r, p), the
                # third vertex its apex
                if _before(self._lengths(q, r, r, p), q, r, r, p):
                    p, q, r = q, r, p
                else:
                    p, q, r = r, p, q
                if self._constraint_known(p, q, r, store_apex(&self.store, q, p)):
                    if self.bisect_longest:
                        return self._insert_midpoint(u, v)  # Mellado: the longest edge
                    if self.min_angle and self._protected(p, q):
                        return 1  # refused: the target is left
                    return self._insert_midpoint(p, q)
        if self.centroid_op < 0:  # Mellado's centroid=false: bisect the terminal edge
            return self._insert_midpoint(u, v)
        n = self._centroid(u, v, w, x)
        if n < 0:
            return -1
        if self.legalize:
            star[0].a, star[0].b = u, x
            star[1].a, star[1].b = x, v
            star[2].a, star[2].b = v, w
            star[3].a, star[3].b = w, u
            return self._legalize(n, star, 4)
        return 0

    cdef int _legalize(self, int64_t vertex, Pair *star, int size) except -2:
        """``ops.legalize_in`` with its known star: 0, or -1 at the step limit.

        The dot-product shortcut only skips pairs that incircle would not flip (two
        angles <= 90° facing {a, b} sum to <= 180°), so an undecided dot goes to incircle.
        """
        cdef int start = 0, index, first
        cdef int64_t a, b, q
        for index in range(1, size):
            if star[index].a < star[start].a:
                start = index
        self.store.pending.count = 0
        for index in range(size - 1, -1, -1):  # popped in star order from ``start``
            push_pair(&self.store.pending, star[(start + index) % size].a, star[(start + index) % size].b)
        while pop_pair(&self.store.pending, &a, &b):
            if store_apex(&self.store, vertex, a) != b:
                continue
            q = store_apex(&self.store, b, a)
            if q < 0 or gx_map_get(&self.segs, gx_edge(a, b) if a < b else gx_edge(b, a), -1) >= 0:
                continue
            first = self._dot_sign(vertex, a, b)
            if (first == 0 or first == 1) and 0 <= self._dot_sign(q, a, b) <= 1:
                continue
            if self._incircle(vertex, a, b, q) != 1:
                continue
            if self._orient(q, vertex, a) != 1 or self._orient(vertex, q, b) != 1:
                continue
            if self.attributed and self._border(a, b, vertex, q):
                continue
            if self._flip(a, b, vertex, q) < 0:
                return -1
            push_pair(&self.store.pending, q, b)
            push_pair(&self.store.pending, a, q)
        return 0

    # -- the loop -----------------------------------------------------------------------
    def run(self):
        """``Refinement.run`` (on ``ReferenceRefinement``) for Lepp-bisection: ``"complete"`` or
        ``"step-limit"``."""
        self._open()
        cdef Entry target
        cdef int64_t a, b, c, u, v, w, x, n, hops
        cdef int order, done
        cdef bint constrained
        cdef Pair star[4]
        if self.tracking and self._mean_reached():
            return "complete"
        while self._pop(&target):
            if self.passes:
                self.pass_number = <int64_t>target.ikey
            a, b, c = target.a, target.b, target.c
            if store_apex(&self.store, a, b) != c:
                continue
            self.targets += 1
            while True:
                # -- Lepp: the longest edge (u, v) of (a, b, c), apex w ------------------
                order = self._lengths(a, b, b, c)
                if _before(order, a, b, b, c):
                    order = self._lengths(a, b, c, a)
                    if _before(order, a, b, c, a):
                        u, v, w = a, b, c
                    else:
                        u, v, w = c, a, b
                else:
                    order = self._lengths(b, c, c, a)
                    if _before(order, b, c, c, a):
                        u, v, w = b, c, a
                    else:
                        u, v, w = c, a, b
                self.searches += 1
                hops = 1
                while True:
                    x = store_apex(&self.store, v, u)
                    if x < 0 or gx_map_get(
                        &self.segs, gx_edge(u, v) if u < v else gx_edge(v, u), -1
                    ) >= 0 or (self.attributed and self._border(u, v, w, x)):
                        constrained = True
                        break
                    if self._lengths(u, v, v, x) != -1 and self._lengths(u, v, x, u) != -1:
                        constrained = False
                        break
                    hops += 1
                    order = self._lengths(u, x, x, v)
                    if _before(order, u, x, x, v):
                        w, v = v, x
                    else:
                        w, u = u, x
                self.hops += hops
                # -- act ---------------------------------------------------------------
                if self.method != 0 and not constrained:
                    if self.quasi_flips and self._incircle(u, v, w, x) == 1:
                        if self._flip(u, v, w, x) < 0:
                            return "step-limit"
                    else:
                        done = self._split_pair(u, v, w, x)
                        if done < 0:
                            return "step-limit"
                        if done > 0:
                            self.left[(a, b, c)] = PROTECTED_TIP
                            break
                    self._drain()
                    if self.stop_per_action and self.tracking and self._mean_reached():
                        return "complete"
                    if store_apex(&self.store, a, b) != c:
                        break
                    continue
                if constrained and self.min_angle and self._protected(u, v):
                    self.left[(a, b, c)] = PROTECTED_TIP  # its step would split one
                    break
                # bisect, then legalize around the midpoint
                n = self._bisect(u, v)
                if n < 0:
                    return "step-limit"
                if self.legalize:
                    # the star of the midpoint, counter-clockwise, after the boundary gap
                    if x < 0:
                        star[0].a, star[0].b = v, w
                        star[1].a, star[1].b = w, u
                        if self._legalize(n, star, 2) < 0:
                            return "step-limit"
                    else:
                        star[0].a, star[0].b = u, x
                        star[1].a, star[1].b = x, v
                        star[2].a, star[2].b = v, w
                        star[3].a, star[3].b = w, u
                        if self._legalize(n, star, 4) < 0:
                            return "step-limit"
                self._drain()
                if self.stop_per_action and self.tracking and self._mean_reached():
                    return "complete"  # the region-wide target is met (CriterionMet)
                if store_apex(&self.store, a, b) != c:
                    break
            if not self.stop_per_action and self.tracking and self._mean_reached():
                return "complete"  # factor_stop "target": checked after each target
        return "complete"

    def finish(self, start):
        """(mesh, the Step objects made for ``on_step`` or None) as
        ``ReferenceRefinement.finish`` seals the mesh; the steps and digests are read off
        the records after (:meth:`steps`, :meth:`digests`).  The mesh's persistent tables
        are built from the kernel's arrays on first use (``TableSource``, sharing
        ``start``'s structure).  The half-edge tables are freed then: the kernel runs no
        more."""
        self._open()
        halfedges = store_halfedge_rows(&self.store)
        hints = store_hint_array(&self.store)
        markers = start.vertex_markers
        if self.new_markers:
            table = markers.mutate()
            for vertex, marker in self.new_markers.items():
                table[vertex] = marker
            markers = table.finish()
        mesh = Mesh2(
            vertices=None,
            halfedges=None,
            outgoing=None,
            segments=immutables.Map(self.segments),
            vertex_markers=markers,
            vertex_attributes=self.vtable.finish() if self.vattributed
            else start.vertex_attributes,
            triangle_attributes=self._triangle_attribute_map() if self.attributed
            else start.triangle_attributes,
            triangle_count=self.triangles,
            digest=_from_u128(self.store.digest),
            source=TableSource(self.points, halfedges, hints, start),
        )
        self.left = self._still_left()  # (read after the table is freed)
        self.sealed = True
        # a deferred trace keeps the kernel alive: only the vertices and records stay
        store_release_table(&self.store)
        self._free_start_halfedges()
        free(self.heap)
        free(self.created)
        self.heap = NULL
        self.created = NULL
        self.cap_heap = self.cap_created = 0
        return mesh, self.step_objects

    cdef int _open(self) except -1:
        if self.sealed:
            raise RuntimeError("the kernel has sealed its result: its tables are freed")
        return 0

    def steps(self):
        """The recorded steps, as ``Step`` objects."""
        cdef Py_ssize_t i
        if self.step_objects is not None:
            return list(self.step_objects)
        return [self._step(&self.store.records[i]) for i in range(self.store.nrec)]

    cdef object _triangle_attribute_map(self):
        """The triangles' attributes as a persistent map (canonical triangle ->
        attributes)."""
        cdef uint64_t slot = 0, edge
        cdef int64_t a, b, attribute
        values = self.attribute_values
        found = {}
        while gx_map_next(&self.tattr, &slot, &edge, &attribute):
            a = <int64_t>(edge >> 32)
            b = <int64_t><uint32_t>edge
            found[(a, b, store_apex(&self.store, a, b))] = values[attribute]
        return immutables.Map(found)

    def op_counts(self):
        """How many recorded steps of each op, by op name."""
        cdef Py_ssize_t i
        cdef int64_t counts[5]
        for i in range(5):
            counts[i] = 0
        for i in range(self.store.nrec):
            counts[self.store.records[i].op] += 1
        return {name: counts[i] for i, name in enumerate(_OP_NAMES) if counts[i]}

    @property
    def pending(self):
        """Entries in the work queue."""
        return self.nheap

    def vertex_state(self, Py_ssize_t i):
        """(on grid, grid x, grid y, F) of vertex ``i`` (for tests)."""
        if not 0 <= i < self.store.nv:
            raise IndexError(i)
        return bool(self.store.vs[i].at.grid), self.store.vs[i].at.gx, self.store.vs[i].at.gy, self.F

    def grid_centroid(self, int64_t u, int64_t v, int64_t w, int64_t x):
        """The grid path of ``rounded_area_centroid`` for the quadrilateral of triangles
        (u, v, w), (v, u, x): the Point2, or None where the kernel asks Python (for
        tests)."""
        return self._centroid_path(u, v, w, x, True)

    def float_centroid(self, int64_t u, int64_t v, int64_t w, int64_t x):
        """The certified float path of ``rounded_area_centroid`` (corners off the grid)
        for the quadrilateral of triangles (u, v, w), (v, u, x): the Point2, or None where
        the kernel asks Python (for tests)."""
        return self._centroid_path(u, v, w, x, False)

    cdef object _centroid_path(self, int64_t u, int64_t v, int64_t w, int64_t x,
                               bint grid):
        cdef int64_t at[2]
        for vertex in (u, v, w, x):
            if not 0 <= vertex < self.store.nv:
                raise IndexError(vertex)
        if not (self._grid_centroid(u, v, w, x, at) if grid
                else self._float_centroid(u, v, w, x, at)):
            return None
        return point2(mpq(at[0], self.unit), mpq(at[1], self.unit))

    def grid_area_limit(self):
        """The MaxArea bound in grid units (for tests)."""
        return _from_i128(self.area_limit)

    # -- replaying a trace ----------------------------------------------------------------
    cdef bint _has_vertex(self, object vertex):
        return type(vertex) is int and 0 <= vertex < self.store.nv

    cdef int64_t _insert_point(self, int64_t u, int64_t v, object point,
                               int op=2) except -2:
        """``insert_in_quadrilateral(u, v, x, y)`` (op 2), or with ``point`` None
        ``insert_vertex_centroid(u, v)`` (op 3) or ``insert_centroid(u, v)`` (op 4), with
        the preconditions of the op (the edge interior and unconstrained, the point
        strictly inside the four new triangles): the new vertex, or -1 (nothing changed)
        when a precondition fails."""
        cdef int64_t w, x, n
        w = store_apex(&self.store, u, v)
        x = store_apex(&self.store, v, u)
        if w < 0 or x < 0 or gx_map_get(
                &self.segs, gx_edge(u, v) if u < v else gx_edge(v, u), -1) >= 0:
            return -1
        if self.attributed and self._border(u, v, w, x):
            return -1
        if point is None:
            points = self.points
            centre = quadrilateral_vertex_centroid if op == 3 else quadrilateral_area_centroid
            point = centre(points[u], points[v], points[w], points[x])
        n = self._add_point(point)
        if (self._orient(u, x, n) != 1 or self._orient(x, v, n) != 1
                or self._orient(v, w, n) != 1 or self._orient(w, u, n) != 1):
            return -1  # the caller stops here: the added vertex is never used
        self._quadrilateral_attributes(u, v, w, x, n)
        return self._join_in_quadrilateral(u, v, w, x, n, op)

    def replay(self, list steps, list digests, Py_ssize_t count):
        """Apply the first ``count`` of ``steps`` (``bisect``, ``flip``,
        ``insert_in_quadrilateral``, ``insert_vertex_centroid`` and ``insert_centroid``,
        the steps this kernel records), each with the
        preconditions of its reference op in ``geomexact.mesh2d.ops`` checked first, and
        compare the digest after it with ``digests``; stop at the first step that is of
        another op, fails a precondition or gives another digest.  Returns the number of
        steps applied with matching digests (the caller replays the step where it stopped
        with the reference, for its message)."""
        self._open()
        cdef Py_ssize_t i
        cdef int64_t u, v, w, x
        cdef gx_u128 expected
        for i in range(count):
            step = steps[i]
            op = step.op
            args = step.args
            if op == "bisect" and len(args) == 2:
                if not (self._has_vertex(args[0]) and self._has_vertex(args[1])):
                    return i
                u, v = args[0], args[1]
                if u == v or (store_apex(&self.store, u, v) < 0
                              and store_apex(&self.store, v, u) < 0):
                    return i
                self._bisect(u, v)
            elif op == "flip" and len(args) == 2:
                if not (self._has_vertex(args[0]) and self._has_vertex(args[1])):
                    return i
                u, v = args[0], args[1]
                w = store_apex(&self.store, u, v)
                x = store_apex(&self.store, v, u)
                if w < 0 or x < 0 or gx_map_get(
                        &self.segs, gx_edge(u, v) if u < v else gx_edge(v, u), -1) >= 0:
                    return i
                if self._orient(x, w, u) != 1 or self._orient(w, x, v) != 1:
                    return i
                if self.attributed and self._border(u, v, w, x):
                    return i
                self._flip(u, v, w, x)
            elif op == "insert_in_quadrilateral" and len(args) == 4:
                if not (self._has_vertex(args[0]) and self._has_vertex(args[1])):
                    return i
                if type(args[2]) is int or type(args[3]) is int:
                    return i  # coordinates are recorded as rationals
                if self._insert_point(args[0], args[1], point2(args[2], args[3])) < 0:
                    return i
            elif op in ("insert_vertex_centroid", "insert_centroid") and len(args) == 2:
                if not (self._has_vertex(args[0]) and self._has_vertex(args[1])):
                    return i
                if self._insert_point(args[0], args[1], None,
                                      3 if op == "insert_vertex_centroid" else 4) < 0:
                    return i
            else:
                return i
            expected = _to_u128(digests[i])
            if self.store.digest != expected:
                return i
        return count
