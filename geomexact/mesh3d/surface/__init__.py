"""Closed triangulated surfaces as input to the 3D meshers (issue 24): the value
(:class:`TriangleSurface`), its exact checks, and the exact geometric queries the octree's
domain fit asks of it."""

from geomexact.mesh3d.surface.checks import (
    check_surface,
    oriented_outward,
    surface_problems,
    surfaces_intersect,
)
from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface

__all__ = [
    "TriangleSurface",
    "check_surface",
    "oriented_outward",
    "surface_problems",
    "surfaces_intersect",
    "triangle_surface",
]
