"""The ``info`` statistics of each kind of value (JSON-ready dictionaries)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from gmpy2 import mpq

from geomexact.cli.kinds import Writable
from geomexact.kernel.numbers import format_rational
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh, mesh_stats
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh3d.measures import is_delaunay3, total_volume
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.cell_geometry import cell_volume
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, mixed_volume
from geomexact.mesh3d.snapshot import Mesh3, signed_volume6


def mesh3_summary(mesh: Mesh3) -> dict[str, Any]:
    """Counts, the exact volume (text), the Delaunay property and the digest of a
    tetrahedral mesh."""
    return {
        "vertices": mesh.vertex_count,
        "tetrahedra": mesh.tetrahedron_count,
        "boundary_faces": len(mesh.boundary_faces()),
        "volume": format_rational(total_volume(mesh)),
        "is_delaunay": is_delaunay3(mesh),
        "digest": mesh.digest_text,
    }


def cells_by_kind(mesh: MixedMesh3) -> dict[str, int]:
    """How many cells of each kind present, by the kind's plural name, in the viewer's
    order (``{"pyramids": 2, "hexahedra": 6}``)."""
    # imported here: the viewer's scene (NumPy) only for a mixed-cell mesh
    import numpy as np

    from geomexact.viz.scene3d import kind_counts

    return kind_counts(np.array([int(cell.kind) for cell in mesh.cell_list()], dtype=np.int64))


def mixed_summary(mesh: MixedMesh3) -> dict[str, Any]:
    """Counts (cells also by kind, VTK type order), the exact volume (text) and the digest
    of a mixed-cell mesh."""
    return {
        "vertices": mesh.vertex_count,
        "cells": mesh.cell_count,
        "cells_by_kind": cells_by_kind(mesh),
        "boundary_faces": len(mesh.boundary_faces()),
        "volume": format_rational(mixed_volume(mesh)),
        "digest": mesh.digest_text,
    }


def cell_volumes(mesh: Mesh3 | MixedMesh3) -> list[Any]:
    """Each cell's exact volume: a ``Mesh3``'s in ``tetrahedra()`` order, a
    ``MixedMesh3``'s in ``cell_list()`` order."""
    if isinstance(mesh, MixedMesh3):
        points = {v: mesh.point(v) for v in range(mesh.vertex_count)}
        return [cell_volume(cell, points) for cell in mesh.cell_list()]
    point = mesh.point
    return [signed_volume6(point(a), point(b), point(c), point(d)) / 6
            for a, b, c, d in mesh.tetrahedra()]


def materials_summary(mesh: Mesh3 | MixedMesh3, materials: Iterable[int]
                      ) -> dict[str, dict[str, Any]]:
    """Per material id (text keys, in increasing order): its ``cells`` and their exact
    ``volume`` (text); ``materials`` holds each cell's id, aligned with
    :func:`cell_volumes`."""
    ids = [int(m) for m in materials]
    volumes: dict[int, Any] = {}
    counts: dict[int, int] = {}
    for material, volume in zip(ids, cell_volumes(mesh), strict=True):
        volumes[material] = volumes.get(material, mpq(0)) + volume
        counts[material] = counts.get(material, 0) + 1
    return {str(material): {"cells": counts[material],
                            "volume": format_rational(volumes[material])}
            for material in sorted(volumes)}


def pslg_summary(pslg: PSLG) -> dict[str, Any]:
    """Counts and the exact bounding box (``"p/q"`` or decimal text) of a PSLG."""
    box: dict[str, str] | None = None
    if pslg.vertices:
        xs = [point.x for point in pslg.vertices]
        ys = [point.y for point in pslg.vertices]
        box = {
            "x_min": format_rational(min(xs)),
            "x_max": format_rational(max(xs)),
            "y_min": format_rational(min(ys)),
            "y_max": format_rational(max(ys)),
        }
    return {
        "vertices": len(pslg.vertices),
        "segments": len(pslg.segments),
        "holes": len(pslg.holes),
        "regions": len(pslg.regions),
        "bounding_box": box,
    }


def polygon_mesh_summary(mesh: PolygonMesh) -> dict[str, Any]:
    """Counts, polygon sizes, convexity, interior angles and areas of a polygon mesh
    (:func:`geomexact.mesh2d.polygonal.polygon_mesh.mesh_stats`); ``vertices`` counts every vertex
    of the file,
    ``used_vertices`` those of some polygon."""
    stats = mesh_stats(mesh)
    del stats["inserted_edges"]
    return {"vertices": len(mesh.vertices), "used_vertices": stats.pop("vertices"), **stats}


def summary_of(value: Writable) -> dict[str, Any]:
    """The ``info`` statistics of a mesh (2D, tetrahedral or mixed-cell), PSLG or polygon
    mesh (JSON-ready)."""
    if isinstance(value, Mesh2):
        return mesh_summary(value)
    if isinstance(value, PSLG):
        return pslg_summary(value)
    if isinstance(value, Mesh3):
        return mesh3_summary(value)
    if isinstance(value, MixedMesh3):
        return mixed_summary(value)
    if isinstance(value, MixedMeshData):
        return {**mixed_summary(value.mesh), "cell_data": sorted(value.cell_data)}
    return polygon_mesh_summary(value)


def surface_summary(surface: Any) -> dict[str, Any]:
    """Counts, whether it bounds a domain (closed, manifold, oriented, not
    self-intersecting: the exact checks), the problems by kind, the exact enclosed volume
    and bounds of a triangulated surface."""
    from geomexact.mesh3d.surface.checks import surface_problems

    problems = surface_problems(surface)
    kinds: dict[str, int] = {}
    for problem in problems:
        kinds[problem.kind] = kinds.get(problem.kind, 0) + 1
    low, high = surface.bounds()
    return {
        "vertices": surface.vertex_count,
        "triangles": surface.triangle_count,
        "closed": "boundary-edge" not in kinds,
        "bounds_a_domain": not problems,
        "problems": kinds,
        "enclosed_volume": format_rational(surface.enclosed_volume()),
        "enclosed_volume_approx": float(surface.enclosed_volume()),
        "bounding_box": {"low": [format_rational(v) for v in low],
                         "high": [format_rational(v) for v in high]},
    }
