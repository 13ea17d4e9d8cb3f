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
from geomexact._version import __version__
from geomexact.mesh2d import _HOMES as _MESH2D_HOMES

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
    "from_arrays": "geomexact.io.arrays",
    "to_arrays": "geomexact.io.arrays",
    "triangulate_arrays": "geomexact.io.arrays",
    **{name: home for name, home in _MESH2D_HOMES.items() if name in _FACADE_2D},
}
"""Public name -> the module that defines it (the 2D ones as in :mod:`geomexact.mesh2d`)."""

__all__ = [
    "PSLG",
    "AnyOf",
    "AverageAreaFactor",
    "Circle",
    "CircleLocation",
    "Comparison",
    "Construction",
    "ConvexDecomposition",
    "ConvexDecompositionError",
    "DoubleRangeError",
    "EdgeLabels",
    "FormatError",
    "GeomexactError",
    "InvalidMeshError",
    "Lepp",
    "MaxArea",
    "MaxEdgeLength",
    "Mesh2",
    "MinAngle",
    "MissingDependencyError",
    "Orientation",
    "OverwriteError",
    "Point2",
    "Point3",
    "Polygon",
    "PolygonMesh",
    "PolyllaError",
    "PolyllaRun",
    "PreconditionError",
    "RationalParseError",
    "Rectangle",
    "RefineStats",
    "RegionAreas",
    "Result",
    "SegmentError",
    "SphereLocation",
    "Step",
    "Trace",
    "TraceError",
    "Transient2",
    "TransientSealedError",
    "Violation",
    "__version__",
    "apply",
    "bisect",
    "canonical_triangle",
    "check",
    "check_polygon_mesh",
    "convex_decomposition",
    "empty_mesh",
    "first_divergence",
    "flip",
    "format_rational",
    "from_arrays",
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
    "mesh_from_triangles",
    "mesh_stats",
    "mesh_summary",
    "mpq",
    "non_delaunay_edges",
    "orient2d",
    "orient3d",
    "parse_rational",
    "point2",
    "point3",
    "polylla",
    "polylla_run",
    "read_trace",
    "refine",
    "replay",
    "signed_area",
    "to_arrays",
    "to_rational",
    "total_area",
    "trace_of",
    "triangle_area",
    "triangulate",
    "triangulate_arrays",
    "triangulate_points",
    "validate",
    "validate_polygon_mesh",
    "vertices_mesh",
    "write_trace",
]


__getattr__, __dir__ = lazy_exports(__name__, globals(), _HOMES)
