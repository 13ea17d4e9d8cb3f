"""The octree mixed-element mesher: a box domain covered by an octree of cuboids, refined
where asked, balanced so that every leaf is 1-irregular, and each leaf partitioned into
tetrahedra by its Steiner pattern so that the whole mesh conforms.  Each stage is a
swappable strategy (``stages``); :func:`generate` runs them and checks the result exactly.
Specification: ``specs/octree.md``; guide: ``docs/octree.md``.

>>> from geomexact.mesh3d.octree import BallRegion, RefineWhere, generate
>>> from geomexact.mesh3d.cuboid.boxes import unit_cube
>>> run = generate(unit_cube(), refinement=RefineWhere(2, region=BallRegion((0, 0, 0), "0.3")))
>>> run.octree.leaf_count, run.mesh.tetrahedron_count, run.conformity.conforming, run.volume
(15, 99, True, mpq(1,1))
>>> from geomexact.trace.playback import replay
>>> replay(run.start, run.trace) == run.mesh
True
"""

from geomexact.mesh3d.octree.criteria import (
    AllOf,
    AspectRatio,
    Criterion,
    MaxEdgeLength,
    MinEdgeLength,
    RadiusEdgeRatio,
    RefineToMaxLevel,
    ScalarFieldVariation,
    VolumeEdgeRatio,
)
from geomexact.mesh3d.octree.pipeline import OctreeMesh, generate
from geomexact.mesh3d.octree.regions import (
    BallRegion,
    BoxRegion,
    PointRegion,
    Region,
    SegmentRegion,
    SphereSurfaceRegion,
    UnionRegion,
    WholeDomain,
)
from geomexact.mesh3d.octree.stages import (
    BalanceTwoToOne,
    BoxGrid,
    DelaunayPartition,
    FinalMesh,
    Improvement,
    InitialMesh,
    LeafMesh,
    NoImprovement,
    NoRefinement,
    PatternPartition,
    Refinement,
    RefineWhere,
    SingleBox,
)
from geomexact.mesh3d.octree.tree import Octree

__all__ = [
    "AllOf",
    "AspectRatio",
    "BalanceTwoToOne",
    "BallRegion",
    "BoxGrid",
    "BoxRegion",
    "Criterion",
    "DelaunayPartition",
    "FinalMesh",
    "Improvement",
    "InitialMesh",
    "LeafMesh",
    "MaxEdgeLength",
    "MinEdgeLength",
    "NoImprovement",
    "NoRefinement",
    "Octree",
    "OctreeMesh",
    "PatternPartition",
    "PointRegion",
    "RadiusEdgeRatio",
    "RefineToMaxLevel",
    "RefineWhere",
    "Refinement",
    "Region",
    "ScalarFieldVariation",
    "SegmentRegion",
    "SingleBox",
    "SphereSurfaceRegion",
    "UnionRegion",
    "VolumeEdgeRatio",
    "WholeDomain",
    "generate",
]
