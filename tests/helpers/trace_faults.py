"""Traces with a planted fault: a step that breaks a property at a known place."""

from __future__ import annotations

from typing import Any

from geomexact.errors import PreconditionError
from geomexact.mesh2d import ops
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.trace.record import Trace, trace_of


def planted_trace(run: Any, at: int) -> tuple[Mesh2, Trace, int]:
    """``run``'s first ``at`` steps, a flip that breaks the Delaunay property, then the
    later steps that leave the flipped quadrilateral alone (so it stays broken).  When no
    flip after step ``at`` breaks it (cocircular quadrilaterals everywhere, as in a
    refined square), the fault goes after the first later step where one does: the
    planted flip is step ``prefix + 1``, where ``prefix`` (returned third) is ``at`` or
    that later step."""
    t = run.start.transient()
    for step in run.trace.steps[:at]:
        t.apply(step)
    mesh = t.seal()
    while (edge := next((e for e in mesh.edges() if _breaks_delaunay(mesh, e)), None)) is None:
        t = mesh.transient()
        t.apply(run.trace.steps[at])
        mesh, at = t.seal(), at + 1
    u, v = edge
    t = mesh.transient()
    w, x = ops.flip_in(t, u, v)
    quadrilateral = {u, v, w, x}
    for step in run.trace.steps[at:]:
        if quadrilateral.isdisjoint(a for a in step.args if isinstance(a, int)):
            try:
                t.apply(step)
            except PreconditionError:
                continue
    rest = trace_of(mesh, t)
    planted = Trace(run.trace.input_digest, [*run.trace.steps[:at], *rest.steps],
                    [*run.trace.digests[:at], *rest.digests])
    return run.start, planted, at


def _breaks_delaunay(mesh: Mesh2, edge: tuple[int, int]) -> bool:
    try:
        return not is_delaunay(ops.flip(mesh, edge))
    except PreconditionError:  # a boundary edge or a non-convex quadrilateral
        return False
