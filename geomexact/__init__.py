"""geomexact: exact, reproducible, replayable mesh generation and refinement.

Coordinates are exact rationals (gmpy2 ``mpq``); predicates are adaptive and exact; a mesh
is an immutable snapshot; every algorithm is a sequence of pure steps recorded in a trace
that replays bit for bit.  The documented API is re-exported here (see ``__all__``); each
name lives in the module named beside it below (``docs/design.md``).  The names are loaded
on first use, so ``import geomexact`` costs almost nothing.

>>> import geomexact
>>> geomexact.mpq("0.1") + geomexact.mpq("0.2") == geomexact.mpq(3, 10)
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from geomexact._lazy_exports import lazy_exports
from geomexact._public_names import MESH2D_HOMES as _MESH2D_HOMES
from geomexact._version import __version__

if TYPE_CHECKING:
    from geomexact.errors import (
        ConvexDecompositionError,
        DoubleRangeError,
        FormatError,
        GeomexactError,
        InvalidMeshError,
        MissingDependencyError,
        OverwriteError,
        PolyllaError,
        PreconditionError,
        RationalParseError,
        SegmentError,
        TraceError,
        TransientSealedError,
        Violation,
    )
    from geomexact.io.arrays import from_arrays, to_arrays, triangulate_arrays
    from geomexact.io.meshio_objects import from_meshio, to_meshio
    from geomexact.io.surface_files import read_surface
    from geomexact.io.trace_file import read_trace, write_trace
    from geomexact.kernel.numbers import format_rational, mpq, parse_rational, to_rational
    from geomexact.kernel.points import Point2, Point3, point2, point3
    from geomexact.kernel.predicate_results import (
        CircleLocation,
        Comparison,
        Orientation,
        SphereLocation,
    )
    from geomexact.kernel.predicates2d import incircle, orient2d
    from geomexact.kernel.predicates3d import insphere, orient3d
    from geomexact.mesh2d import (
        PSLG,
        AnyOf,
        AverageAreaFactor,
        Circle,
        Construction,
        ConvexDecomposition,
        EdgeLabels,
        Lepp,
        MaxArea,
        MaxEdgeLength,
        Mesh2,
        MinAngle,
        Polygon,
        PolygonMesh,
        PolyllaRun,
        Rectangle,
        RefineStats,
        RegionAreas,
        Result,
        Transient2,
        apply,
        bisect,
        canonical_triangle,
        check,
        check_polygon_mesh,
        convex_decomposition,
        empty_mesh,
        flip,
        insert_centroid,
        insert_in_edge,
        insert_in_triangle,
        is_delaunay,
        label_edges,
        legalize,
        lepp,
        make_delaunay,
        mesh_from_triangles,
        mesh_stats,
        mesh_summary,
        non_delaunay_edges,
        polylla,
        polylla_run,
        refine,
        signed_area,
        total_area,
        triangle_area,
        triangulate,
        triangulate_points,
        validate,
        validate_polygon_mesh,
        vertices_mesh,
    )
    from geomexact.mesh3d.cuboid.boxes import Box
    from geomexact.mesh3d.mixed.snapshot import MixedMesh3
    from geomexact.mesh3d.mixed.validation import validate_mixed
    from geomexact.mesh3d.octree.device import generate_device
    from geomexact.mesh3d.octree.domain import generate_domain
    from geomexact.mesh3d.octree.pipeline import generate, generate_cells
    from geomexact.mesh3d.octree.stages import (
        BoxGrid,
        DerefineWhere,
        MixedPartition,
        PolyhedralPartition,
        RefineWhere,
    )
    from geomexact.mesh3d.octree.tree import Octree
    from geomexact.mesh3d.quality_improvement import QualityCriterion, improve_quality
    from geomexact.mesh3d.snapshot import Mesh3
    from geomexact.mesh3d.surface.checks import check_surface, oriented_outward
    from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface
    from geomexact.mesh3d.transient import Transient3, mesh3_from_tetrahedra
    from geomexact.mesh3d.validation import validate3
    from geomexact.mesh3d.voronoi import control_volumes
    from geomexact.trace.playback import first_divergence, replay
    from geomexact.trace.record import Trace, trace_of
    from geomexact.trace.step import Step

_FACADE_2D = frozenset(
    name for name in _MESH2D_HOMES if name not in ("Edge", "Triangle")
)

_HOMES: dict[str, str] = {
    "ConvexDecompositionError": "geomexact.errors",
    "DoubleRangeError": "geomexact.errors",
    "FormatError": "geomexact.errors",
    "GeomexactError": "geomexact.errors",
    "InvalidMeshError": "geomexact.errors",
    "MissingDependencyError": "geomexact.errors",
    "OverwriteError": "geomexact.errors",
    "PolyllaError": "geomexact.errors",
    "PreconditionError": "geomexact.errors",
    "RationalParseError": "geomexact.errors",
    "SegmentError": "geomexact.errors",
    "TraceError": "geomexact.errors",
    "TransientSealedError": "geomexact.errors",
    "Violation": "geomexact.errors",
    "format_rational": "geomexact.kernel.numbers",
    "mpq": "geomexact.kernel.numbers",
    "parse_rational": "geomexact.kernel.numbers",
    "to_rational": "geomexact.kernel.numbers",
    "Point2": "geomexact.kernel.points",
    "Point3": "geomexact.kernel.points",
    "point2": "geomexact.kernel.points",
    "point3": "geomexact.kernel.points",
    "CircleLocation": "geomexact.kernel.predicate_results",
    "Comparison": "geomexact.kernel.predicate_results",
    "Orientation": "geomexact.kernel.predicate_results",
    "SphereLocation": "geomexact.kernel.predicate_results",
    "incircle": "geomexact.kernel.predicates2d",
    "orient2d": "geomexact.kernel.predicates2d",
    "insphere": "geomexact.kernel.predicates3d",
    "orient3d": "geomexact.kernel.predicates3d",
    "Step": "geomexact.trace.step",
    "Trace": "geomexact.trace.record",
    "trace_of": "geomexact.trace.record",
    "first_divergence": "geomexact.trace.playback",
    "replay": "geomexact.trace.playback",
    "read_trace": "geomexact.io.trace_file",
    "write_trace": "geomexact.io.trace_file",
    "Mesh3": "geomexact.mesh3d.snapshot",
    "Transient3": "geomexact.mesh3d.transient",
    "mesh3_from_tetrahedra": "geomexact.mesh3d.transient",
    "validate3": "geomexact.mesh3d.validation",
    "MixedMesh3": "geomexact.mesh3d.mixed.snapshot",
    "validate_mixed": "geomexact.mesh3d.mixed.validation",
    "Box": "geomexact.mesh3d.cuboid.boxes",
    "Octree": "geomexact.mesh3d.octree.tree",
    "generate": "geomexact.mesh3d.octree.pipeline",
    "generate_cells": "geomexact.mesh3d.octree.pipeline",
    "generate_domain": "geomexact.mesh3d.octree.domain",
    "generate_device": "geomexact.mesh3d.octree.device",
    "RefineWhere": "geomexact.mesh3d.octree.stages",
    "BoxGrid": "geomexact.mesh3d.octree.stages",
    "DerefineWhere": "geomexact.mesh3d.octree.stages",
    "MixedPartition": "geomexact.mesh3d.octree.stages",
    "PolyhedralPartition": "geomexact.mesh3d.octree.stages",
    "TriangleSurface": "geomexact.mesh3d.surface.value",
    "triangle_surface": "geomexact.mesh3d.surface.value",
    "check_surface": "geomexact.mesh3d.surface.checks",
    "oriented_outward": "geomexact.mesh3d.surface.checks",
    "read_surface": "geomexact.io.surface_files",
    "control_volumes": "geomexact.mesh3d.voronoi",
    "improve_quality": "geomexact.mesh3d.quality_improvement",
    "QualityCriterion": "geomexact.mesh3d.quality_improvement",
    "from_arrays": "geomexact.io.arrays",
    "to_arrays": "geomexact.io.arrays",
    "triangulate_arrays": "geomexact.io.arrays",
    "from_meshio": "geomexact.io.meshio_objects",
    "to_meshio": "geomexact.io.meshio_objects",
    **{name: home for name, home in _MESH2D_HOMES.items() if name in _FACADE_2D},
}
"""Public name -> the module that defines it (the 2D ones as in :mod:`geomexact.mesh2d`)."""

__all__ = [
    "PSLG",
    "AnyOf",
    "AverageAreaFactor",
    "Box",
    "BoxGrid",
    "Circle",
    "CircleLocation",
    "Comparison",
    "Construction",
    "ConvexDecomposition",
    "ConvexDecompositionError",
    "DerefineWhere",
    "DoubleRangeError",
    "EdgeLabels",
    "FormatError",
    "GeomexactError",
    "InvalidMeshError",
    "Lepp",
    "MaxArea",
    "MaxEdgeLength",
    "Mesh2",
    "Mesh3",
    "MinAngle",
    "MissingDependencyError",
    "MixedMesh3",
    "MixedPartition",
    "Octree",
    "Orientation",
    "OverwriteError",
    "Point2",
    "Point3",
    "Polygon",
    "PolygonMesh",
    "PolyhedralPartition",
    "PolyllaError",
    "PolyllaRun",
    "PreconditionError",
    "QualityCriterion",
    "RationalParseError",
    "Rectangle",
    "RefineStats",
    "RefineWhere",
    "RegionAreas",
    "Result",
    "SegmentError",
    "SphereLocation",
    "Step",
    "Trace",
    "TraceError",
    "Transient2",
    "Transient3",
    "TransientSealedError",
    "TriangleSurface",
    "Violation",
    "__version__",
    "apply",
    "bisect",
    "canonical_triangle",
    "check",
    "check_polygon_mesh",
    "check_surface",
    "control_volumes",
    "convex_decomposition",
    "empty_mesh",
    "first_divergence",
    "flip",
    "format_rational",
    "from_arrays",
    "from_meshio",
    "generate",
    "generate_cells",
    "generate_device",
    "generate_domain",
    "improve_quality",
    "incircle",
    "insert_centroid",
    "insert_in_edge",
    "insert_in_triangle",
    "insphere",
    "is_delaunay",
    "label_edges",
    "legalize",
    "lepp",
    "make_delaunay",
    "mesh3_from_tetrahedra",
    "mesh_from_triangles",
    "mesh_stats",
    "mesh_summary",
    "mpq",
    "non_delaunay_edges",
    "orient2d",
    "orient3d",
    "oriented_outward",
    "parse_rational",
    "point2",
    "point3",
    "polylla",
    "polylla_run",
    "read_surface",
    "read_trace",
    "refine",
    "replay",
    "signed_area",
    "to_arrays",
    "to_meshio",
    "to_rational",
    "total_area",
    "trace_of",
    "triangle_area",
    "triangle_surface",
    "triangulate",
    "triangulate_arrays",
    "triangulate_points",
    "validate",
    "validate3",
    "validate_mixed",
    "validate_polygon_mesh",
    "vertices_mesh",
    "write_trace",
]


__getattr__, __dir__ = lazy_exports(__name__, globals(), _HOMES)
