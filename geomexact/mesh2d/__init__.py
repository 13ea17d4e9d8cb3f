"""Triangle meshes in the plane: snapshots, transients, the reference steps, validation,
measures, and the 2D algorithms (Delaunay, Lepp refinement, polygonal meshes).

Layer 3 of ``docs/design.md``: imports :mod:`geomexact.kernel` and :mod:`geomexact.trace`.
The 2D names of the top-level facade are re-exported here too, loaded on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from geomexact._lazy_exports import lazy_exports

if TYPE_CHECKING:
    from geomexact.mesh2d.delaunay.triangulation import (
        Construction,
        is_delaunay,
        make_delaunay,
        non_delaunay_edges,
        triangulate,
        triangulate_points,
        vertices_mesh,
    )
    from geomexact.mesh2d.longest_edge import Lepp, lepp
    from geomexact.mesh2d.measures import signed_area, total_area, triangle_area
    from geomexact.mesh2d.ops import (
        apply,
        bisect,
        flip,
        insert_centroid,
        insert_in_edge,
        insert_in_triangle,
        legalize,
    )
    from geomexact.mesh2d.polygonal.convex import ConvexDecomposition, convex_decomposition
    from geomexact.mesh2d.polygonal.polygon_mesh import (
        PolygonMesh,
        check_polygon_mesh,
        mesh_stats,
        validate_polygon_mesh,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        EdgeLabels,
        PolyllaRun,
        label_edges,
        polylla,
        polylla_run,
    )
    from geomexact.mesh2d.pslg import PSLG
    from geomexact.mesh2d.refinement.api import RefineStats, Result, refine
    from geomexact.mesh2d.refinement.criteria import (
        AverageAreaFactor,
        MaxArea,
        MaxEdgeLength,
        MinAngle,
    )
    from geomexact.mesh2d.refinement.regions import Circle, Polygon, Rectangle
    from geomexact.mesh2d.snapshot import Edge, Mesh2, Triangle, canonical_triangle, empty_mesh
    from geomexact.mesh2d.summary import mesh_summary
    from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
    from geomexact.mesh2d.validation import Violation, check, validate

_HOMES: dict[str, str] = {
    "Construction": "geomexact.mesh2d.delaunay.triangulation",
    "is_delaunay": "geomexact.mesh2d.delaunay.triangulation",
    "make_delaunay": "geomexact.mesh2d.delaunay.triangulation",
    "non_delaunay_edges": "geomexact.mesh2d.delaunay.triangulation",
    "triangulate": "geomexact.mesh2d.delaunay.triangulation",
    "triangulate_points": "geomexact.mesh2d.delaunay.triangulation",
    "vertices_mesh": "geomexact.mesh2d.delaunay.triangulation",
    "Lepp": "geomexact.mesh2d.longest_edge",
    "lepp": "geomexact.mesh2d.longest_edge",
    "signed_area": "geomexact.mesh2d.measures",
    "total_area": "geomexact.mesh2d.measures",
    "triangle_area": "geomexact.mesh2d.measures",
    "apply": "geomexact.mesh2d.ops",
    "bisect": "geomexact.mesh2d.ops",
    "flip": "geomexact.mesh2d.ops",
    "insert_centroid": "geomexact.mesh2d.ops",
    "insert_in_edge": "geomexact.mesh2d.ops",
    "insert_in_triangle": "geomexact.mesh2d.ops",
    "legalize": "geomexact.mesh2d.ops",
    "ConvexDecomposition": "geomexact.mesh2d.polygonal.convex",
    "convex_decomposition": "geomexact.mesh2d.polygonal.convex",
    "PolygonMesh": "geomexact.mesh2d.polygonal.polygon_mesh",
    "check_polygon_mesh": "geomexact.mesh2d.polygonal.polygon_mesh",
    "mesh_stats": "geomexact.mesh2d.polygonal.polygon_mesh",
    "validate_polygon_mesh": "geomexact.mesh2d.polygonal.polygon_mesh",
    "EdgeLabels": "geomexact.mesh2d.polygonal.polylla_meshing",
    "PolyllaRun": "geomexact.mesh2d.polygonal.polylla_meshing",
    "label_edges": "geomexact.mesh2d.polygonal.polylla_meshing",
    "polylla": "geomexact.mesh2d.polygonal.polylla_meshing",
    "polylla_run": "geomexact.mesh2d.polygonal.polylla_meshing",
    "PSLG": "geomexact.mesh2d.pslg",
    "RefineStats": "geomexact.mesh2d.refinement.api",
    "Result": "geomexact.mesh2d.refinement.api",
    "refine": "geomexact.mesh2d.refinement.api",
    "AverageAreaFactor": "geomexact.mesh2d.refinement.criteria",
    "MaxArea": "geomexact.mesh2d.refinement.criteria",
    "MaxEdgeLength": "geomexact.mesh2d.refinement.criteria",
    "MinAngle": "geomexact.mesh2d.refinement.criteria",
    "Circle": "geomexact.mesh2d.refinement.regions",
    "Polygon": "geomexact.mesh2d.refinement.regions",
    "Rectangle": "geomexact.mesh2d.refinement.regions",
    "Edge": "geomexact.mesh2d.snapshot",
    "Mesh2": "geomexact.mesh2d.snapshot",
    "Triangle": "geomexact.mesh2d.snapshot",
    "canonical_triangle": "geomexact.mesh2d.snapshot",
    "empty_mesh": "geomexact.mesh2d.snapshot",
    "mesh_summary": "geomexact.mesh2d.summary",
    "Transient2": "geomexact.mesh2d.transient",
    "mesh_from_triangles": "geomexact.mesh2d.transient",
    "Violation": "geomexact.mesh2d.validation",
    "check": "geomexact.mesh2d.validation",
    "validate": "geomexact.mesh2d.validation",
}
"""Public 2D name -> the module that defines it."""

__all__ = [
    "PSLG",
    "AverageAreaFactor",
    "Circle",
    "Construction",
    "ConvexDecomposition",
    "Edge",
    "EdgeLabels",
    "Lepp",
    "MaxArea",
    "MaxEdgeLength",
    "Mesh2",
    "MinAngle",
    "Polygon",
    "PolygonMesh",
    "PolyllaRun",
    "Rectangle",
    "RefineStats",
    "Result",
    "Transient2",
    "Triangle",
    "Violation",
    "apply",
    "bisect",
    "canonical_triangle",
    "check",
    "check_polygon_mesh",
    "convex_decomposition",
    "empty_mesh",
    "flip",
    "insert_centroid",
    "insert_in_edge",
    "insert_in_triangle",
    "is_delaunay",
    "label_edges",
    "legalize",
    "lepp",
    "make_delaunay",
    "mesh_from_triangles",
    "mesh_stats",
    "mesh_summary",
    "non_delaunay_edges",
    "polylla",
    "polylla_run",
    "refine",
    "signed_area",
    "total_area",
    "triangle_area",
    "triangulate",
    "triangulate_points",
    "validate",
    "validate_polygon_mesh",
    "vertices_mesh",
]

__getattr__, __dir__ = lazy_exports(__name__, globals(), _HOMES)
