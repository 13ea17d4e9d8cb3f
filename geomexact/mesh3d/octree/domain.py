"""``generate_domain``: the octree mesher of a domain bounded by closed surfaces (issue 24;
``specs/domain.md``).

The surfaces (each closed, 2-manifold, outward, not self-intersecting, checked exactly
by the caller with :func:`~geomexact.mesh3d.surface.checks.check_surface`; no two
meeting) bound the domain: a point is in it when it is inside an odd number of them, so
a surface nested in another is a hole.  Stages: the octree of a dyadic cube around the
surfaces, refined to ``interior_level`` wherever a leaf meets the surfaces' bounding box
and, where a leaf meets a triangle's
bounding box (widened by ``band``), to ``level`` (or while its edges are longer than
``max_edge``); balanced 2:1; each leaf's pattern tetrahedra; then
:func:`~geomexact.mesh3d.octree.domain_fit.fit_to_surface` keeps the domain's part,
exactly, every boundary vertex on a surface.  With ``trace`` the result is also built by
the reference steps of a mixed mesh (from its vertices, one ``add_cell`` per
tetrahedron; a tetra cell hashes as in ``Mesh3``, so the replayed mesh has the result's
digest)."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import Any

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cells import CellKind, standard_cell
from geomexact.mesh3d.mixed.recording import recorded_cells
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.octree.criteria import MaxEdgeLength, RefineToMaxLevel
from geomexact.mesh3d.octree.domain_fit import WARP_FRACTION, SurfaceFit, fit_to_surface
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.refinement import MAX_LEVEL
from geomexact.mesh3d.octree.stages import RefineWhere
from geomexact.mesh3d.octree.tree import Octree
from geomexact.mesh3d.quality_improvement import (
    QualityCriterion,
    QualityImprovement,
    improve_quality,
)
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.surface.queries import INSIDE, SurfaceIndex, surface_index
from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface
from geomexact.trace.record import Trace

__all__ = ["DomainMesh", "domain_box", "enclosed_volume", "generate_domain", "merged_surface"]


@attrs.frozen(slots=True, eq=False)
class DomainMesh:
    """The result of :func:`generate_domain`: the ``surfaces``, the ``box`` meshed, the
    balanced ``octree``, the ``fit``, the exact ``enclosed_volume`` of the domain, the
    stage ``seconds``, the quality ``improvement`` when asked and, when recorded,
    ``start`` and ``trace`` (of the fit from its vertices, or, after an improvement, of
    the improvement from the fitted mesh)."""

    surfaces: tuple[TriangleSurface, ...]
    box: Box
    octree: Octree
    fit: SurfaceFit
    enclosed_volume: Rational
    seconds: dict[str, float]
    start: MixedMesh3 | Mesh3 | None = None
    trace: Trace | None = None
    improvement: QualityImprovement | None = None

    @property
    def mesh(self) -> Mesh3:
        """The fitted mesh, after the quality improvement when one was asked."""
        return self.fit.mesh if self.improvement is None else self.improvement.mesh


def domain_box(surfaces: Sequence[TriangleSurface]) -> Box:
    """The dyadic cube the octree meshes: side the least power of two at least 5/4 of the
    surfaces' largest extent, its corner on the grid of 1/64 of that side, centred on
    them as near as that grid allows (so the surfaces lie strictly inside and the
    lattice's points are exact in doubles when the side is)."""
    lows, highs = zip(*(surface.bounds() for surface in surfaces), strict=True)
    low = [min(box[axis] for box in lows) for axis in range(3)]
    high = [max(box[axis] for box in highs) for axis in range(3)]
    extent = max(h - lo for lo, h in zip(low, high, strict=True))
    if extent <= 0:
        raise PreconditionError("domain_box", "the surfaces have no extent")
    side = mpq(1)
    while side < extent * mpq(5, 4):
        side *= 2
    while side / 2 >= extent * mpq(5, 4):
        side /= 2
    grid = side / 64
    # the margin is at least side / 10 on each side, more than the rounding (side / 64)
    corner = [math.floor(((lo + h) / 2 - side / 2) / grid) * grid
              for lo, h in zip(low, high, strict=True)]
    return Box(tuple(corner), tuple(c + side for c in corner))


def enclosed_volume(surfaces: Sequence[TriangleSurface]) -> Rational:
    """The exact volume of the domain: each surface's enclosed volume, added when it is
    inside an even number of the others, taken away when odd (a hole)."""
    indexes = [surface_index(surface) for surface in surfaces]
    total = ZERO
    for i, surface in enumerate(surfaces):
        first = surface.points[int(surface.triangles[0, 0])]
        depth = sum(1 for j, index in enumerate(indexes)
                    if j != i and index.side(first) == INSIDE)
        total += surface.enclosed_volume() * (-1) ** depth
    return total


def merged_surface(surfaces: Sequence[TriangleSurface]) -> TriangleSurface:
    """The surfaces as one (points and triangles one after another): its inside by parity
    is the domain."""
    if len(surfaces) == 1:
        return surfaces[0]
    points: list[Any] = []
    triangles = []
    for surface in surfaces:
        triangles.append(surface.triangles + len(points))
        points.extend(surface.points)
    return triangle_surface(points, np.concatenate(triangles),
                            " + ".join(surface.name for surface in surfaces))


def _near(index: SurfaceIndex, band: Rational) -> Callable[[Box], bool]:
    def region(box: Box) -> bool:
        return index.meets_box([v - band for v in box.low], [v + band for v in box.high])

    return region


def _normals(surface: TriangleSurface) -> Any:
    """Each triangle's unit normal, in doubles (for the feature criterion only)."""
    xyz = np.array([[p.fx, p.fy, p.fz] for p in surface.points], dtype=np.float64)
    a, b, c = (xyz[surface.triangles[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    lengths = np.linalg.norm(normals, axis=1)
    return normals / np.where(lengths > 0, lengths, 1.0)[:, None]


def _featured(index: SurfaceIndex, feature_angle: float) -> Callable[[Box], bool]:
    """A leaf holds a feature of the surface when the triangles meeting its box have
    normals more than ``feature_angle`` degrees apart: curvature or a crease at the
    leaf's size (the seed's ``Is_fulfilled(mesh, element)`` on the geometry).  Decided in
    doubles: it only chooses where to refine."""
    normals = _normals(index.surface)
    bound = float(np.cos(np.radians(feature_angle)))

    def holds_feature(box: Box) -> bool:
        near = index.near(box.low, box.high)
        if len(near) < 2:
            return False
        found = normals[near]
        return bool((found @ found.T).min() < bound)

    return holds_feature


def generate_domain(
    surfaces: Sequence[TriangleSurface],
    *,
    level: int,
    interior_level: int = 0,
    max_edge: Rational | None = None,
    band: Rational | int = 0,
    feature_angle: float | None = None,
    box: Box | None = None,
    warp: Rational | None = WARP_FRACTION,
    quality: QualityCriterion | None = None,
    trace: bool = False,
    on_stage: Callable[[str], None] | None = None,
) -> DomainMesh:
    """The tetrahedral mesh of the domain the ``surfaces`` bound (module docstring).
    ``box``: the cube to mesh (default :func:`domain_box`), which must hold every surface
    strictly inside.  With ``feature_angle``, a leaf meeting the surface is split past
    ``interior_level`` only while the surface's normals inside it differ by more than
    that many degrees (refinement by the local feature of the surface: curved parts and
    creases get small leaves, flat parts large ones).  With ``quality``, the fitted mesh
    is then improved by exact flips that keep its boundary
    (:func:`~geomexact.mesh3d.quality_improvement.improve_quality`)."""
    if not surfaces:
        raise PreconditionError("generate_domain", "a domain needs one or more surfaces")
    if not 0 <= interior_level <= level <= MAX_LEVEL:
        raise PreconditionError("generate_domain", f"need 0 <= interior level "
                                f"({interior_level}) <= level ({level}) <= {MAX_LEVEL}")
    if band < 0:
        raise PreconditionError("generate_domain", f"the band is not negative, not {band}")
    seconds: dict[str, float] = {}

    def timed(name: str, function: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
        if on_stage is not None:
            on_stage(name)
        began = time.perf_counter()
        value = function(*args, **kwargs)
        seconds[name] = time.perf_counter() - began
        return value

    with collector_paused():
        merged = timed("surfaces", merged_surface, surfaces)
        index = timed("index", surface_index, merged)
        cube = box if box is not None else domain_box(surfaces)
        low, high = merged.bounds()
        if not all(cube.low[a] < low[a] and high[a] < cube.high[a] for a in range(3)):
            raise PreconditionError("generate_domain", f"the box {cube.describe()} does not "
                                    "hold the surfaces strictly inside")
        criterion: Callable[[Box], bool] = (RefineToMaxLevel() if max_edge is None
                                            else MaxEdgeLength(max_edge))
        near = _near(index, mpq(band))
        if feature_angle is not None:
            if not 0 < feature_angle < 180:
                raise PreconditionError("generate_domain", f"the feature angle is between 0 "
                                        f"and 180 degrees, not {feature_angle}")
            featured, plain_near = _featured(index, feature_angle), near

            def near(box: Box) -> bool:
                return plain_near(box) and featured(box)

        def within_bounds(leaf: Box) -> bool:
            return all(leaf.low[a] <= high[a] and low[a] <= leaf.high[a] for a in range(3))

        def refinement(octree: Octree) -> Octree:
            everywhere = RefineWhere(interior_level, region=within_bounds)(octree)
            return RefineWhere(level, criterion=criterion, region=near)(everywhere)

        run = generate(cube, refinement=refinement, trace=False, on_stage=on_stage)
        seconds.update(run.seconds)
        lattice = run.leaf_mesh.lattice
        fit = timed("fit", fit_to_surface, lattice.exact_points(), run.leaf_mesh.tetrahedra,
                    index, warp=warp)
        volume = timed("enclosed volume", enclosed_volume, surfaces)
        start: MixedMesh3 | Mesh3 | None = None
        recorded = None
        improvement = None
        if quality is not None:
            improvement = timed("quality", improve_quality, fit.mesh, quality, trace=trace)
            if trace:
                start, recorded = fit.mesh, improvement.trace
        elif trace:
            mesh = fit.mesh
            cells = [standard_cell(CellKind.TETRA, tetrahedron)
                     for tetrahedron in mesh.tetrahedra()]
            start, _, recorded = timed("trace", recorded_cells, mesh.point_list(),
                                       [((), cells)],
                                       {"algorithm": "octree-domain", "level": level,
                                        "interior_level": interior_level,
                                        "surfaces": [surface.name for surface in surfaces]})
        return DomainMesh(tuple(surfaces), cube, run.octree, fit, volume, seconds, start,
                          recorded, improvement)
