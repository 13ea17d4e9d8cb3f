"""Properties of a tetrahedral mesh as yes/no predicates, each decided exactly: the checks
``geomexact trace bisect --fails`` searches a trace for (with
:func:`~geomexact.mesh3d.measures.is_delaunay3`)."""

from __future__ import annotations

from geomexact.kernel.numbers import Rational
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.validation import validate3

__all__ = ["has_volume", "is_valid3"]


def is_valid3(mesh: Mesh3) -> bool:
    """True when :func:`~geomexact.mesh3d.validation.validate3` finds no violation (the
    faces agree, every tetrahedron is positive, the boundary is closed, …)."""
    return len(validate3(mesh)) == 0


def has_volume(mesh: Mesh3, volume: Rational) -> bool:
    """True when the tetrahedra's volumes sum exactly to ``volume``."""
    return bool(total_volume(mesh) == volume)
