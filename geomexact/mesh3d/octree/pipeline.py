"""``generate``: the octree mesher's pipeline, stage by stage, with the exact conformity
check of the result (``specs/octree.md``)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, Generic, Protocol, TypeVar

import attrs
import numpy as np

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import Rational
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.octree.cell_final import CellConformity, CellLeafMesh, cell_conformity
from geomexact.mesh3d.octree.conformity import (
    ConformityReport,
    FaceConformity,
    lattice_conformity,
)
from geomexact.mesh3d.octree.stages import (
    BALANCE_TWO_TO_ONE,
    NO_REFINEMENT,
    PATTERN_PARTITION,
    SINGLE_BOX,
    CellFinalMesh,
    FinalMesh,
    LeafMesh,
)
from geomexact.mesh3d.octree.tree import Octree
from geomexact.mesh3d.quality import QualitySummary, lattice_quality, quality_summary
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.trace.record import Trace

__all__ = ["OctreeCellMesh", "OctreeMesh", "StagedOctree", "generate", "generate_cells"]


_MeshT = TypeVar("_MeshT", Mesh3, MixedMesh3)
_ReportT = TypeVar("_ReportT", bound=FaceConformity)


_Mesh_co = TypeVar("_Mesh_co", covariant=True)


class _FinalOutput(Protocol[_Mesh_co]):
    """What every final stage gives (:class:`LeafMesh`, :class:`CellLeafMesh`)."""

    @property
    def octree(self) -> Octree: ...

    @property
    def mesh(self) -> _Mesh_co: ...

    @property
    def start(self) -> _Mesh_co | None: ...

    @property
    def trace(self) -> Trace | None: ...


_OutputT = TypeVar("_OutputT", bound=_FinalOutput[Any])


@attrs.frozen(slots=True, eq=False)
class StagedOctree(Generic[_MeshT, _OutputT, _ReportT]):
    """The octree after each stage (``initial``, ``refined``, ``improved``, and the one
    partitioned, ``leaf_mesh.octree``), the final stage's output ``leaf_mesh`` with its
    snapshot ``mesh``, the exact ``conformity`` report, the stage ``seconds`` and, when
    recorded, ``start`` and the ``trace`` that replays ``mesh`` from it."""

    initial: Octree
    refined: Octree
    improved: Octree
    leaf_mesh: _OutputT
    conformity: _ReportT
    seconds: dict[str, float]

    @property
    def mesh(self) -> _MeshT:
        mesh: _MeshT = self.leaf_mesh.mesh  # (the output's mesh type is _MeshT)
        return mesh

    @property
    def octree(self) -> Octree:
        return self.leaf_mesh.octree

    @property
    def start(self) -> _MeshT | None:
        start: _MeshT | None = self.leaf_mesh.start
        return start

    @property
    def trace(self) -> Trace | None:
        return self.leaf_mesh.trace


@attrs.frozen(slots=True, eq=False)
class OctreeMesh(StagedOctree[Mesh3, LeafMesh, ConformityReport]):
    """The result of :func:`generate` (:class:`StagedOctree`), with the exact ``volume``
    and the ``quality`` of its tetrahedra."""

    @property
    def volume(self) -> Rational:
        """The exact volume of the tetrahedra (the domain's when conforming)."""
        lattice = self.leaf_mesh.lattice
        if lattice.octree.planes is not None:
            return total_volume(self.mesh)
        unit = lattice.unit(0) * lattice.unit(1) * lattice.unit(2)
        return self.conformity.volume(unit)

    def quality(self) -> QualitySummary:
        """Dihedral angles and radius-edge ratio (doubles, for display), right for any
        box (:func:`~geomexact.mesh3d.quality.lattice_quality`)."""
        lattice = self.leaf_mesh.lattice
        if lattice.octree.planes is not None:
            points = np.array([[p.fx, p.fy, p.fz] for p in self.mesh.point_list()])
            return quality_summary(points, self.leaf_mesh.tetrahedra)
        units = [lattice.unit(axis) for axis in range(3)]
        return lattice_quality(lattice.vertices, units, self.leaf_mesh.tetrahedra)


def generate(
    domain: Box,
    *,
    initial: Callable[[Box], Octree] = SINGLE_BOX,
    refinement: Callable[[Octree], Octree] = NO_REFINEMENT,
    improvement: Callable[[Octree], Octree] = BALANCE_TWO_TO_ONE,
    final: FinalMesh = PATTERN_PARTITION,
    trace: bool = True,
    on_stage: Callable[[str], None] | None = None,
) -> OctreeMesh:
    """Mesh the box ``domain``: ``initial`` covers it with leaves, ``refinement`` splits
    them, ``improvement`` balances them, ``final`` partitions each leaf into tetrahedra.
    The result is checked exactly (:func:`~geomexact.mesh3d.octree.conformity.
    lattice_conformity`); :class:`InvalidMeshError` if it does not conform (a bug, or a
    user stage that broke the tiling).  With ``trace`` the mesh is built by the reference
    steps and ``replay(result.start, result.trace) == result.mesh``; without, by the
    fast assembly (the same mesh, proven equal in the tests).  ``on_stage`` is told each
    stage's name as it starts (progress)."""
    with collector_paused():
        return _generate(domain, initial, refinement, improvement, final, trace, on_stage)


class _Stages:
    """The stages run one after another, each timed and announced (a transient)."""

    def __init__(self, on_stage: Callable[[str], None] | None) -> None:
        self.on_stage = on_stage
        self.seconds: dict[str, float] = {}

    def run(self, name: str, function: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
        if self.on_stage is not None:
            self.on_stage(name)
        began = time.perf_counter()
        value = function(*args, **kwargs)
        self.seconds[name] = time.perf_counter() - began
        return value

    def octrees(self, domain: Box, initial: Callable[[Box], Octree],
                refinement: Callable[[Octree], Octree],
                improvement: Callable[[Octree], Octree]) -> tuple[Octree, Octree, Octree]:
        first = self.run("initial", initial, domain)
        refined = self.run("refinement", refinement, first)
        return first, refined, self.run("improvement", improvement, refined)


def _generate(domain: Box, initial: Callable[[Box], Octree],
              refinement: Callable[[Octree], Octree], improvement: Callable[[Octree], Octree],
              final: FinalMesh, trace: bool,
              on_stage: Callable[[str], None] | None) -> OctreeMesh:
    stages = _Stages(on_stage)
    first, refined, improved = stages.octrees(domain, initial, refinement, improvement)
    leaf_mesh: LeafMesh = stages.run("final", final, improved, trace=trace)
    lattice = leaf_mesh.lattice
    report = stages.run("conformity", lattice_conformity, lattice.vertices,
                        leaf_mesh.tetrahedra, lattice.size)
    if not report.conforming:
        raise InvalidMeshError([Violation("conformity", problem) for problem in report.problems])
    return OctreeMesh(first, refined, improved, leaf_mesh, report, stages.seconds)


@attrs.frozen(slots=True, eq=False)
class OctreeCellMesh(StagedOctree[MixedMesh3, CellLeafMesh, CellConformity]):
    """The result of :func:`generate_cells` (:class:`StagedOctree`): a mixed-cell
    ``leaf_mesh`` and its exact ``conformity``."""


def generate_cells(
    domain: Box,
    final: CellFinalMesh,
    *,
    initial: Callable[[Box], Octree] = SINGLE_BOX,
    refinement: Callable[[Octree], Octree] = NO_REFINEMENT,
    improvement: Callable[[Octree], Octree] = BALANCE_TWO_TO_ONE,
    trace: bool = True,
    on_stage: Callable[[str], None] | None = None,
) -> OctreeCellMesh:
    """:func:`generate` with a cell final (``final``: mixed or polyhedral cells): the
    result validated exactly (:func:`~geomexact.mesh3d.octree.cell_final.cell_conformity`:
    planar faces, convex cells, matching polygons, the domain's volume);
    :class:`InvalidMeshError` if not."""
    with collector_paused():
        stages = _Stages(on_stage)
        first, refined, improved = stages.octrees(domain, initial, refinement, improvement)
        leaf_mesh: CellLeafMesh = stages.run("final", final, improved, trace=trace)
        report = stages.run("conformity", cell_conformity, leaf_mesh.mesh, domain.volume,
                            leaf_mesh.distinct)
        if not report.conforming:
            raise InvalidMeshError([Violation("conformity", problem)
                                    for problem in report.problems])
        return OctreeCellMesh(first, refined, improved, leaf_mesh, report, stages.seconds)
