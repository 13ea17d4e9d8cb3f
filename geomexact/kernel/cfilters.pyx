# cython: language_level=3
"""Test-facing wrappers of the C filters and grid predicates of ``ckernel.h``.

The compiled kernels (Lepp refinement, Delaunay insertion) decide with these C functions
and never expose them; this module calls the very same code (its own copy of the static
functions, with its constants filled from :mod:`geomexact.kernel.filter_bounds` at
import, compiled with the same flags) so that ``tests/kernel/test_filter_backends.py``
can check them against the exact predicates.  Nothing in the package imports it.

* ``*_filter(...)`` take the points' doubles and return the certified sign (1 or -1), or
  0 when the filter does not decide.
* ``grid_*(...)`` take dyadic-grid integer coordinates (``|value| <= 2**60``, else
  ``ValueError``) and return the exact sign (-1, 0 or 1); ``grid_incircle`` returns None
  when the reduced differences do not fit (the kernels then try the float filter).
"""

from libc.stdint cimport int64_t

from geomexact.kernel.ckernel cimport (
    _init_constants,
    gx_float_dot,
    gx_float_incircle,
    gx_float_lengths,
    gx_float_orient,
    gx_grid_dot,
    gx_grid_incircle,
    gx_grid_lengths,
    gx_grid_orient,
)

_init_constants()

GRID_LIMIT = 2**60
"""The largest magnitude of a grid coordinate the C grid predicates accept."""


cdef inline int _certified(int result) noexcept:
    return 0 if result == 2 else result


def orient2d_filter(double ax, double ay, double bx, double by, double cx, double cy):
    """The C filter of ``orient2d``: 1, -1, or 0 (undecided)."""
    return _certified(gx_float_orient(ax, ay, bx, by, cx, cy))


def incircle_filter(double ax, double ay, double bx, double by,
                    double cx, double cy, double dx, double dy):
    """The C filter of ``incircle``: 1 (inside), -1, or 0 (undecided)."""
    return _certified(gx_float_incircle(ax, ay, bx, by, cx, cy, dx, dy))


def squared_lengths_filter(double ax, double ay, double bx, double by,
                           double cx, double cy, double dx, double dy):
    """The C filter of ``compare_squared_lengths`` (the sign of ``|ab|^2 - |cd|^2``): 1,
    -1, or 0 (undecided)."""
    return _certified(gx_float_lengths(ax, ay, bx, by, cx, cy, dx, dy))


def dot_filter(double px, double py, double ax, double ay, double bx, double by):
    """The C filter of the sign of ``(a - p) . (b - p)`` (stage 1 of ``compare_angle``): 1,
    -1, or 0 (undecided)."""
    return _certified(gx_float_dot(px, py, ax, ay, bx, by))


def _grid(values):
    for value in values:
        if not -GRID_LIMIT <= value <= GRID_LIMIT:
            raise ValueError(f"grid coordinate {value} is beyond 2**60 in magnitude")


def grid_orient2d(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx, int64_t cy):
    """The exact sign of ``orient2d`` on grid coordinates."""
    _grid((ax, ay, bx, by, cx, cy))
    return gx_grid_orient(ax, ay, bx, by, cx, cy)


def grid_incircle(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                  int64_t cx, int64_t cy, int64_t dx, int64_t dy):
    """The exact sign of ``incircle`` on grid coordinates, or None (undecided)."""
    _grid((ax, ay, bx, by, cx, cy, dx, dy))
    result = gx_grid_incircle(ax, ay, bx, by, cx, cy, dx, dy)
    return None if result == 2 else result


def grid_squared_lengths(int64_t ax, int64_t ay, int64_t bx, int64_t by,
                         int64_t cx, int64_t cy, int64_t dx, int64_t dy):
    """The exact sign of ``|ab|^2 - |cd|^2`` on grid coordinates."""
    _grid((ax, ay, bx, by, cx, cy, dx, dy))
    return gx_grid_lengths(ax, ay, bx, by, cx, cy, dx, dy)


def grid_dot(int64_t px, int64_t py, int64_t ax, int64_t ay, int64_t bx, int64_t by):
    """The exact sign of ``(a - p) . (b - p)`` on grid coordinates."""
    _grid((px, py, ax, ay, bx, by))
    return gx_grid_dot(px, py, ax, ay, bx, by)
