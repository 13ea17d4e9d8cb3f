"""When a pass over many items is worth NumPy: the vectorised accelerations (bulk mesh
building, array summaries, the vectorised Delaunay check) give the same answers as their
scalar definitions, so choosing one is a question of time only -- and a small command
that would import NumPy for one pass pays more for the import (about 50 ms) than the
pass saves."""

from __future__ import annotations

import sys

__all__ = ["COLD_FROM", "worth_vectorising"]

COLD_FROM = 4096
"""Items from which a pass is vectorised even when NumPy is not imported yet."""


def worth_vectorising(count: int, loaded_from: int) -> bool:
    """True when a pass over ``count`` items should run on arrays: from ``loaded_from``
    items once NumPy is imported, from :data:`COLD_FROM` (or ``loaded_from`` if larger)
    while importing it would be paid for this pass."""
    if "numpy" in sys.modules:
        return count >= loaded_from
    return count >= max(loaded_from, COLD_FROM)
