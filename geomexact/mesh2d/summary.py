"""Statistics of a mesh, as reported by ``geomexact info``: counts, angles, areas,
Delaunay-ness and digest.

:func:`mesh_summary` computes them in one vectorised pass
(:mod:`~geomexact.mesh2d.mesh_arrays`) with the same answers as :func:`scalar_mesh_summary`,
the definition written triangle by triangle (used for meshes whose tables are
inconsistent).  Exactness of each key: ``docs/cli.md``.
"""

from __future__ import annotations

from typing import Any

from geomexact.kernel.numbers import ZERO
from geomexact.kernel.vectorising import worth_vectorising
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.measures import (
    angle_and_area_report,
    signed_area,
    triangle_angles_degrees,
)
from geomexact.mesh2d.snapshot import Mesh2


def mesh_summary(mesh: Mesh2, *, check_delaunay: bool = True) -> dict[str, Any]:
    """A JSON-ready dict: ``vertices``, ``triangles``, ``edges``, ``boundary_edges``,
    ``constrained_edges``, ``min_angle_deg``, ``max_angle_deg`` (floats, for reading),
    ``min_area``, ``max_area``, ``mean_area`` (nearest doubles of the exact values),
    ``total_area`` (exact, ``"p/q"`` or decimal text), ``is_delaunay`` (exact; None when
    ``check_delaunay`` is false) and ``digest``.  Angle and area entries are None for a
    mesh without triangles.  O(n log n) in numpy; exact arithmetic only where the floats
    cannot decide.  A small mesh is summarised by :func:`scalar_mesh_summary` (the same
    answers) unless NumPy is loaded already."""
    if not worth_vectorising(mesh.triangle_count, 0):
        return scalar_mesh_summary(mesh, check_delaunay=check_delaunay)
    from geomexact.mesh2d.mesh_arrays import mesh_arrays

    arrays = mesh_arrays(mesh)
    if arrays is None:
        return scalar_mesh_summary(mesh, check_delaunay=check_delaunay)
    count = mesh.triangle_count
    boundary = arrays.boundary_count
    areas = arrays.area_extremes()
    angles = arrays.angle_extremes()
    smallest, largest = (None, None) if areas is None else areas
    return {
        "vertices": mesh.vertex_count,
        "triangles": count,
        "edges": (len(arrays.hu) + boundary) // 2,
        "boundary_edges": boundary,
        "constrained_edges": len(mesh.segments),
        **angle_and_area_report((None, None) if angles is None else angles, smallest,
                                largest, arrays.total_area(), count),
        "is_delaunay": not arrays.non_delaunay_edges() if check_delaunay else None,
        "digest": mesh.digest_text,
    }


def scalar_mesh_summary(mesh: Mesh2, *, check_delaunay: bool = True) -> dict[str, Any]:
    """:func:`mesh_summary` computed triangle by triangle and edge by edge with the scalar
    definitions (:mod:`~geomexact.mesh2d.measures`,
    :func:`~geomexact.mesh2d.delaunay.triangulation.is_delaunay`).  O(n), slow."""
    vertices = mesh.vertices
    min_angle = max_angle = None
    min_area = max_area = None
    total = ZERO
    for a, b, c in mesh.iter_triangles():
        pa, pb, pc = vertices[a], vertices[b], vertices[c]
        area = signed_area(pa, pb, pc)
        total += area
        if min_area is None or area < min_area:
            min_area = area
        if max_area is None or area > max_area:
            max_area = area
        angles = triangle_angles_degrees(pa, pb, pc)
        low, high = min(angles), max(angles)
        if min_angle is None or low < min_angle:
            min_angle = low
        if max_angle is None or high > max_angle:
            max_angle = high
    count = mesh.triangle_count
    edges = len(mesh.halfedges)
    boundary = len(mesh.boundary_edges())
    return {
        "vertices": mesh.vertex_count,
        "triangles": count,
        "edges": (edges + boundary) // 2,
        "boundary_edges": boundary,
        "constrained_edges": len(mesh.segments),
        **angle_and_area_report((min_angle, max_angle), min_area, max_area, total, count),
        "is_delaunay": is_delaunay(mesh) if check_delaunay else None,
        "digest": mesh.digest_text,
    }
