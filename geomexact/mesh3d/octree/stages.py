"""The mesher's four stages as swappable strategies (the source's Strategy-pattern design):
each is a plain callable behind a ``Protocol``, with an identity implementation that stands
where a stage is skipped.  Users pass their own callables.

=============  ===============================  ==========================================
stage          implementations                  identity
=============  ===============================  ==========================================
InitialMesh    :class:`SingleBox`, BoxGrid      :class:`SingleBox` (the domain itself)
Refinement     :class:`RefineWhere`             :class:`NoRefinement`
Improvement    :class:`BalanceTwoToOne`,        :class:`NoImprovement`
               :class:`DerefineWhere`
FinalMesh      :class:`PatternPartition`,       :class:`PatternPartition` (see below)
               :class:`DelaunayPartition`
CellFinalMesh  :class:`MixedPartition`,         (none: a cell final is chosen)
               :class:`PolyhedralPartition`
=============  ===============================  ==========================================

A :class:`FinalMesh` makes tetrahedra (a :class:`LeafMesh`); a :class:`CellFinalMesh`
makes a mixed-cell mesh (a :class:`~geomexact.mesh3d.octree.cell_final.CellLeafMesh`:
hexahedra, wedges, pyramids, tetrahedra and, for the polyhedral final, polyhedra).

A final mesh must conform, so the final stage cannot be skipped: its minimum is the
pattern partition.  It also cannot partition a leaf that is not 1-irregular (no cuboid
pattern describes it), so it balances whatever octree it is given first and reports the
splits that took (``forced_splits``; zero after :class:`BalanceTwoToOne`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final, Protocol

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.balance import balance_two_to_one
from geomexact.mesh3d.octree.cell_final import CellLeafMesh, cell_final
from geomexact.mesh3d.octree.criteria import RefineToMaxLevel
from geomexact.mesh3d.octree.lattice import OctreeLattice, octree_lattice
from geomexact.mesh3d.octree.leaf_partition import (
    FinalKind,
    assemble_tetrahedra,
    octree_trace,
)
from geomexact.mesh3d.octree.refinement import derefine_octree, refine_octree
from geomexact.mesh3d.octree.regions import WholeDomain
from geomexact.mesh3d.octree.tree import Octree, octree_of_grid
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_positive_arrays
from geomexact.trace.record import Trace

__all__ = [
    "BALANCE_TWO_TO_ONE",
    "NO_REFINEMENT",
    "PATTERN_PARTITION",
    "SINGLE_BOX",
    "BalanceTwoToOne",
    "BoxGrid",
    "CellFinalMesh",
    "DelaunayPartition",
    "DerefineWhere",
    "FinalMesh",
    "Improvement",
    "InitialMesh",
    "LeafMesh",
    "MixedPartition",
    "NoImprovement",
    "NoRefinement",
    "PatternPartition",
    "PolyhedralPartition",
    "RefineWhere",
    "Refinement",
    "SingleBox",
]


class InitialMesh(Protocol):
    """The octree's first leaves over the domain."""

    def __call__(self, domain: Box, /) -> Octree: ...


class Refinement(Protocol):
    """A finer octree (leaves split into octants)."""

    def __call__(self, octree: Octree, /) -> Octree: ...


class Improvement(Protocol):
    """A better octree for the final mesh (e.g. balanced)."""

    def __call__(self, octree: Octree, /) -> Octree: ...


@attrs.frozen(slots=True, eq=False)
class LeafMesh:
    """What a final stage makes: the ``octree`` it partitioned (after any forced splits),
    its ``lattice``, the ``tetrahedra`` (T x 4 global vertex ids), the snapshot ``mesh``;
    with a trace, the ``start`` snapshot and the ``trace`` that replays ``mesh`` from it."""

    octree: Octree
    lattice: OctreeLattice
    tetrahedra: object
    mesh: Mesh3
    forced_splits: int
    start: Mesh3 | None = None
    trace: Trace | None = None


class FinalMesh(Protocol):
    """The tetrahedral mesh of an octree (with its trace when ``trace``)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> LeafMesh: ...


class CellFinalMesh(Protocol):
    """The mixed-cell mesh of an octree (with its trace when ``trace``)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> CellLeafMesh: ...


@attrs.frozen(slots=True)
class SingleBox:
    """One leaf: the domain (the identity initial mesh)."""

    def __call__(self, domain: Box, /) -> Octree:
        return octree_of_grid(domain)


@attrs.frozen(slots=True)
class BoxGrid:
    """An nx x ny x nz grid of equal boxes."""

    nx: int
    ny: int
    nz: int

    def __call__(self, domain: Box, /) -> Octree:
        return octree_of_grid(domain, (self.nx, self.ny, self.nz))


@attrs.frozen(slots=True)
class NoRefinement:
    """The octree unchanged: the refinement or improvement stage that does nothing
    (:data:`NoImprovement` is this class)."""

    def __call__(self, octree: Octree, /) -> Octree:
        return octree


NoImprovement = NoRefinement
"""The improvement stage that leaves the octree unchanged (:class:`NoRefinement`)."""


@attrs.frozen(slots=True)
class RefineWhere:
    """Split leaves into octants while ``criterion`` fails on a leaf that ``region`` meets,
    up to ``max_level`` (:func:`~geomexact.mesh3d.octree.refinement.refine_octree`)."""

    max_level: int
    criterion: Callable[[Box], bool] = attrs.field(factory=RefineToMaxLevel)
    region: Callable[[Box], bool] = attrs.field(factory=WholeDomain)

    def __call__(self, octree: Octree, /) -> Octree:
        return refine_octree(octree, self.criterion, self.region, self.max_level)


@attrs.frozen(slots=True)
class BalanceTwoToOne:
    """2:1 balance across faces and edges, so every leaf is 1-irregular."""

    def __call__(self, octree: Octree, /) -> Octree:
        return balance_two_to_one(octree)


@attrs.frozen(slots=True)
class DerefineWhere:
    """Merge sibling leaves back into their parent where ``region`` meets the parent box
    and ``accepts`` holds on it (down to ``min_level``), then balance 2:1: the seed's
    "refine, improve and derefine"."""

    accepts: Callable[[Box], bool]
    region: Callable[[Box], bool] = attrs.field(factory=WholeDomain)
    min_level: int = 0

    def __call__(self, octree: Octree, /) -> Octree:
        merged = derefine_octree(
            octree, lambda box: self.region(box) and self.accepts(box), self.min_level)
        return balance_two_to_one(merged)


def _partition(octree: Octree, kind: FinalKind, trace: bool) -> LeafMesh:
    balanced = balance_two_to_one(octree)
    forced = balanced.leaf_count - octree.leaf_count
    if forced < 0:  # pragma: no cover - balancing only splits
        raise PreconditionError("octree", "balancing removed leaves")
    lattice = octree_lattice(balanced)
    if trace:
        start, mesh, recorded = octree_trace(lattice, kind, {"algorithm": "octree", "final": kind})
        tetrahedra = np.array(mesh.tetrahedra(), dtype=np.int64).reshape(-1, 4)
        return LeafMesh(balanced, lattice, tetrahedra, mesh, forced // 7, start, recorded)
    tetrahedra = assemble_tetrahedra(lattice, kind)
    mesh = mesh3_from_positive_arrays(lattice.exact_points(), tetrahedra)
    return LeafMesh(balanced, lattice, tetrahedra, mesh, forced // 7)


@attrs.frozen(slots=True)
class PatternPartition:
    """Each leaf partitioned by its Steiner pattern (conforming split order, template by
    position parity)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> LeafMesh:
        return _partition(octree, "patterns", trace)


@attrs.frozen(slots=True)
class DelaunayPartition:
    """The pattern partition, then Joe's flips toward Delaunay inside each leaf (boundary
    flips off, so the leaves still conform)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> LeafMesh:
        return _partition(octree, "delaunay", trace)


@attrs.frozen(slots=True)
class MixedPartition:
    """Each leaf by its mixed template: a bare leaf one hexahedron, a 1-irregular leaf the
    fewest wedges, pyramids and tetrahedra that cut its faces as the face rule does
    (:func:`~geomexact.mesh3d.cuboid.cell_templates.mixed_template`)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> CellLeafMesh:
        return cell_final(octree, "mixed", trace)


@attrs.frozen(slots=True)
class PolyhedralPartition:
    """Each leaf's exact Delaunay tessellation with every co-spherical group kept as one
    cell (:func:`~geomexact.mesh3d.cuboid.cell_templates.polyhedral_template`)."""

    def __call__(self, octree: Octree, /, *, trace: bool = False) -> CellLeafMesh:
        return cell_final(octree, "polyhedral", trace)


SINGLE_BOX: Final = SingleBox()
NO_REFINEMENT: Final = NoRefinement()
BALANCE_TWO_TO_ONE: Final = BalanceTwoToOne()
PATTERN_PARTITION: Final = PatternPartition()
