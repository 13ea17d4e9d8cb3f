"""Building a mixed mesh by the reference steps, recording its trace: the start is the
given points and no cell; then, group by group, an ``add_vertex`` for each new point and
an ``add_cell`` for each cell (the octree's and the cuboid's cell finals)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from geomexact._version import __version__
from geomexact.kernel.points import Point3
from geomexact.mesh3d.mixed.cells import Cell
from geomexact.mesh3d.mixed.ops import add_cell_in, add_vertex_in
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import MixedTransient3, mixed_mesh_from_cells
from geomexact.trace.record import Trace

__all__ = ["recorded_cells"]


def recorded_cells(points: Sequence[Point3],
                   groups: Iterable[tuple[Sequence[Point3], Sequence[Cell]]],
                   parameters: Mapping[str, Any]) -> tuple[MixedMesh3, MixedMesh3, Trace]:
    """(start, mesh, trace): from the start (``points``, no cell), each group's new
    points (ids following on) and cells added by the reference steps; ``replay(start,
    trace) == mesh``."""
    start = mixed_mesh_from_cells(points, ())
    t = MixedTransient3(start)
    for new_points, cells in groups:
        for point in new_points:
            add_vertex_in(t, point.x, point.y, point.z)
        for cell in cells:
            add_cell_in(t, cell)
    trace = Trace(start.digest, t.steps, t.step_digests, dict(parameters), __version__)
    return start, t.seal(), trace
