"""Triangle meshes in the plane: snapshots, transients, the reference steps, validation,
measures, and the 2D algorithms (Delaunay, Lepp refinement, polygonal meshes).

Layer 3 of ``docs/design.md``: imports :mod:`geomexact.kernel` and :mod:`geomexact.trace`.
The 2D names of the top-level facade are re-exported here too, loaded on first use.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from geomexact._lazy_exports import lazy_exports
from geomexact._public_names import MESH2D_HOMES
from geomexact.mesh2d.ops import OPERATIONS as _OPERATIONS
from geomexact.mesh2d.snapshot import Mesh2 as _Mesh2
from geomexact.mesh2d.transient import Transient2 as _Transient2
from geomexact.trace.protocols import MeshKind as _MeshKind
from geomexact.trace.protocols import bind_kind as _bind_kind
from geomexact.trace.step import Step as _Step

if TYPE_CHECKING:
    from geomexact.mesh2d.delaunay.triangulation import (
        Construction as Construction,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        is_delaunay as is_delaunay,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        make_delaunay as make_delaunay,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        non_delaunay_edges as non_delaunay_edges,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        triangulate as triangulate,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        triangulate_points as triangulate_points,
    )
    from geomexact.mesh2d.delaunay.triangulation import (
        vertices_mesh as vertices_mesh,
    )
    from geomexact.mesh2d.longest_edge import (
        Lepp as Lepp,
    )
    from geomexact.mesh2d.longest_edge import (
        lepp as lepp,
    )
    from geomexact.mesh2d.measures import (
        signed_area as signed_area,
    )
    from geomexact.mesh2d.measures import (
        total_area as total_area,
    )
    from geomexact.mesh2d.measures import (
        triangle_area as triangle_area,
    )
    from geomexact.mesh2d.ops import (
        apply as apply,
    )
    from geomexact.mesh2d.ops import (
        bisect as bisect,
    )
    from geomexact.mesh2d.ops import (
        flip as flip,
    )
    from geomexact.mesh2d.ops import (
        insert_centroid as insert_centroid,
    )
    from geomexact.mesh2d.ops import (
        insert_in_edge as insert_in_edge,
    )
    from geomexact.mesh2d.ops import (
        insert_in_triangle as insert_in_triangle,
    )
    from geomexact.mesh2d.ops import (
        legalize as legalize,
    )
    from geomexact.mesh2d.polygonal.convex import (
        ConvexDecomposition as ConvexDecomposition,
    )
    from geomexact.mesh2d.polygonal.convex import (
        convex_decomposition as convex_decomposition,
    )
    from geomexact.mesh2d.polygonal.polygon_mesh import (
        PolygonMesh as PolygonMesh,
    )
    from geomexact.mesh2d.polygonal.polygon_mesh import (
        check_polygon_mesh as check_polygon_mesh,
    )
    from geomexact.mesh2d.polygonal.polygon_mesh import (
        mesh_stats as mesh_stats,
    )
    from geomexact.mesh2d.polygonal.polygon_mesh import (
        validate_polygon_mesh as validate_polygon_mesh,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        EdgeLabels as EdgeLabels,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        PolyllaRun as PolyllaRun,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        label_edges as label_edges,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        polylla as polylla,
    )
    from geomexact.mesh2d.polygonal.polylla_meshing import (
        polylla_run as polylla_run,
    )
    from geomexact.mesh2d.pslg import (
        PSLG as PSLG,
    )
    from geomexact.mesh2d.refinement.api import (
        RefineStats as RefineStats,
    )
    from geomexact.mesh2d.refinement.api import (
        Result as Result,
    )
    from geomexact.mesh2d.refinement.api import (
        refine as refine,
    )
    from geomexact.mesh2d.refinement.criteria import (
        AnyOf as AnyOf,
    )
    from geomexact.mesh2d.refinement.criteria import (
        AverageAreaFactor as AverageAreaFactor,
    )
    from geomexact.mesh2d.refinement.criteria import (
        MaxArea as MaxArea,
    )
    from geomexact.mesh2d.refinement.criteria import (
        MaxEdgeLength as MaxEdgeLength,
    )
    from geomexact.mesh2d.refinement.criteria import (
        MinAngle as MinAngle,
    )
    from geomexact.mesh2d.refinement.criteria import (
        RegionAreas as RegionAreas,
    )
    from geomexact.mesh2d.refinement.regions import (
        Circle as Circle,
    )
    from geomexact.mesh2d.refinement.regions import (
        Polygon as Polygon,
    )
    from geomexact.mesh2d.refinement.regions import (
        Rectangle as Rectangle,
    )
    from geomexact.mesh2d.snapshot import (
        Edge as Edge,
    )
    from geomexact.mesh2d.snapshot import (
        Mesh2 as Mesh2,
    )
    from geomexact.mesh2d.snapshot import (
        Triangle as Triangle,
    )
    from geomexact.mesh2d.snapshot import (
        canonical_triangle as canonical_triangle,
    )
    from geomexact.mesh2d.snapshot import (
        empty_mesh as empty_mesh,
    )
    from geomexact.mesh2d.summary import (
        mesh_summary as mesh_summary,
    )
    from geomexact.mesh2d.transient import (
        Transient2 as Transient2,
    )
    from geomexact.mesh2d.transient import (
        mesh_from_triangles as mesh_from_triangles,
    )
    from geomexact.mesh2d.validation import (
        check as check,
    )
    from geomexact.mesh2d.validation import (
        validate as validate,
    )

_HOMES: dict[str, str] = MESH2D_HOMES
"""Public 2D name -> the module that defines it."""

# the TYPE_CHECKING imports above re-export each name explicitly (``name as name``)
__all__ = sorted(_HOMES)

__getattr__, __dir__ = lazy_exports(__name__, globals(), _HOMES)


def _replay_compiled(start: _Mesh2, steps: Sequence[_Step], digests: Sequence[int]
                     ) -> _Mesh2 | None:
    """The compiled Lepp kernel's replay (its glue loaded on the first long replay)."""
    from geomexact.mesh2d.refinement.engines.compiled import replay_compiled

    return replay_compiled(start, steps, digests)


# The 2D mesh kind, bound here, above the modules it joins: the snapshot reaches its
# transient, the step table and the compiled replay through it, and none of them imports
# a module built on it (no import circle in mesh2d: tests/architecture).
_bind_kind(_Mesh2, _MeshKind(_Transient2, _OPERATIONS, replay_engine=_replay_compiled))
