# cython: language_level=3, boundscheck=False, wraparound=False
"""The triangle store as the base type of the compiled 2D kernels.

:class:`RecordedStore` owns a :c:type:`TriangleStore` (``ctriangulation.pxd``): it frees
it, and reads back what every kernel records the same way (the digest after each step,
the step count).  The Delaunay builder and the Lepp kernel extend it with their own loops;
the C fields are reached directly, not through a vtable.
"""

from geomexact.kernel.ctriangulation cimport store_digest_at, store_digests, store_free


cdef class RecordedStore:
    """A triangle store and its step records (extended by each kernel)."""

    def __dealloc__(self):
        # (the C fields start zeroed: what the subclass's __init__ did not reach is NULL)
        store_free(&self.store)

    def digests(self):
        """The digest after each recorded step."""
        return store_digests(&self.store)

    def digest_at(self, Py_ssize_t i):
        """The digest after step ``i``."""
        return store_digest_at(&self.store, i)

    @property
    def step_count(self):
        """How many steps were recorded."""
        return self.store.nrec
