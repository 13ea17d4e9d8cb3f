"""Closed triangulated surfaces as input to the 3D meshers (issue 24): the value
(:class:`TriangleSurface`), its exact checks, and the exact geometric queries the octree's
domain fit asks of it."""

from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface

__all__ = ["TriangleSurface", "triangle_surface"]
