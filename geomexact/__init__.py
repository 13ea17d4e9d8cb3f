"""geomexact: exact, reproducible, replayable mesh refinement.

Coordinates are exact rationals (gmpy2 ``mpq``); predicates are adaptive and exact; a mesh
is an immutable snapshot; every algorithm is a sequence of pure steps recorded in a trace
that replays bit for bit.  The documented API is re-exported here (see ``__all__``).
"""

from __future__ import annotations

__version__ = "0.1.0"

from geomexact.errors import (
    FormatError,
    GeomexactError,
    InvalidMeshError,
    OverwriteError,
    PreconditionError,
    RationalParseError,
    TraceError,
    TransientSealedError,
)
from geomexact.kernel.numbers import (
    format_rational,
    mpq,
    parse_rational,
    to_rational,
)
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicates import (
    CircleLocation,
    Comparison,
    Orientation,
    SphereLocation,
    incircle,
    insphere,
    orient2d,
    orient3d,
)
from geomexact.mesh2d.delaunay.triangulation import (
    Construction,
    SegmentError,
    is_delaunay,
    make_delaunay,
    non_delaunay_edges,
    triangulate,
    triangulate_points,
    vertices_mesh,
)
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
from geomexact.mesh2d.polygonal.convex import (
    ConvexDecomposition,
    ConvexDecompositionError,
    convex_decomposition,
)
from geomexact.mesh2d.polygonal.polygon_mesh import (
    PolygonMesh,
    check_polygon_mesh,
    mesh_stats,
    validate_polygon_mesh,
)
from geomexact.mesh2d.polygonal.polylla_meshing import (
    EdgeLabels,
    PolyllaError,
    PolyllaRun,
    label_edges,
    polylla,
    polylla_run,
)
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2, canonical_triangle, empty_mesh
from geomexact.mesh2d.summary import mesh_summary
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.mesh2d.validation import Violation, check, validate
from geomexact.trace.record import (
    Trace,
    first_divergence,
    read_trace,
    replay,
    trace_of,
    write_trace,
)
from geomexact.trace.step import Step

__all__ = [
    "PSLG",
    "CircleLocation",
    "Comparison",
    "Construction",
    "ConvexDecomposition",
    "ConvexDecompositionError",
    "EdgeLabels",
    "FormatError",
    "GeomexactError",
    "InvalidMeshError",
    "Mesh2",
    "Orientation",
    "OverwriteError",
    "Point2",
    "Point3",
    "PolygonMesh",
    "PolyllaError",
    "PolyllaRun",
    "PreconditionError",
    "RationalParseError",
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
    "incircle",
    "insert_centroid",
    "insert_in_edge",
    "insert_in_triangle",
    "insphere",
    "is_delaunay",
    "label_edges",
    "legalize",
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
    "replay",
    "signed_area",
    "to_rational",
    "total_area",
    "trace_of",
    "triangle_area",
    "triangulate",
    "triangulate_points",
    "validate",
    "validate_polygon_mesh",
    "vertices_mesh",
    "write_trace",
]

# -- Lepp refinement (geomexact.mesh2d.refinement.api; issue 4)
# ---------------------------------------------
# Kept as one block: importing geomexact.mesh2d.refinement.api also registers the step
# ``insert_in_quadrilateral`` (geomexact.mesh2d.refinement.centroids), so that refinement traces
# replay after
# a plain ``import geomexact``.
from geomexact.mesh2d.longest_edge import Lepp, lepp
from geomexact.mesh2d.refinement.api import RefineStats, Result, refine
from geomexact.mesh2d.refinement.criteria import (
    AverageAreaFactor,
    MaxArea,
    MaxEdgeLength,
    MinAngle,
)
from geomexact.mesh2d.refinement.regions import Circle, Polygon, Rectangle

__all__ += [
    "AverageAreaFactor",
    "Circle",
    "Lepp",
    "MaxArea",
    "MaxEdgeLength",
    "MinAngle",
    "Polygon",
    "Rectangle",
    "RefineStats",
    "Result",
    "lepp",
    "refine",
]
