# cython: language_level=3
"""The base extension type of the compiled 2D kernels (``triangle_store.pyx``)."""

from geomexact.kernel.ctriangulation cimport TriangleStore


cdef class RecordedStore:
    # the vertices, the half-edge table, the digest, the step records and the stack to
    # legalize (ctriangulation.pxd); the subclass's loops edit it, this type owns it
    cdef TriangleStore store
