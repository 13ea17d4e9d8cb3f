"""Pausing Python's cyclic garbage collector during batch work.

Building a large mesh creates millions of small acyclic objects (rationals, tuples, map
nodes, steps); every automatic collection walks all live objects, so long runs slow down
quadratically (measured here: 2× for reading a 100k-triangle mesh, more for a 10^5-point
Delaunay triangulation).  Batch builders run inside :func:`collector_paused`.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def collector_paused() -> Iterator[None]:
    """Disable the cyclic collector for the block; restore its previous state after.

    When the collector was enabled, everything the block made is first moved into the
    oldest generation (``gc.freeze()`` then ``gc.unfreeze()``): the block's results are
    long-lived, and otherwise the first young collection after the block would walk every
    object it allocated (0.2 s for a 10^5-point triangulation).  This is process-wide:
    every tracked object then lives in the oldest generation, which is only a scheduling
    change (nothing is leaked or kept alive).  When the caller has frozen objects itself
    (``gc.freeze()``, e.g. before forking workers) the move is skipped: ``gc.unfreeze()``
    would thaw the caller's objects too."""
    enabled = gc.isenabled()
    caller_froze = gc.get_freeze_count() > 0
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            if not caller_froze:
                gc.freeze()
                gc.unfreeze()
            gc.enable()
