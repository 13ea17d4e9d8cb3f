"""Actions on an uploaded mesh (run in the job's process): :data:`ACTIONS` by name, each
turning the read value and the form's text fields into an :class:`Outcome`, or raising
:class:`~geomexact.server.bounded.JobFailed` for bad input."""

from __future__ import annotations

from collections.abc import Callable
from http import HTTPStatus
from typing import Any

import attrs

from geomexact.server.bounded import JobFailed


@attrs.frozen
class Outcome:
    """What an action made: the trace's start (a mesh, or a PSLG for a triangulation
    trace), the trace, the final mesh and report lines for the page."""

    start: Any
    trace: Any
    result: Any
    report: tuple[str, ...]


@attrs.frozen
class Action:
    """An upload action: a label for the form, whether it is usable here, and the
    function ``run(value, form) -> Outcome`` (``form``: the form's text fields)."""

    label: str
    available: Callable[[], bool]
    run: Callable[[Any, dict[str, str]], Outcome]


def _triangulate(value: Any, form: dict[str, str]) -> Outcome:
    from geomexact.mesh2d.delaunay.triangulation import make_delaunay, triangulate
    from geomexact.mesh2d.pslg import PSLG
    from geomexact.mesh2d.snapshot import Mesh2

    if isinstance(value, Mesh2):
        mesh, trace = make_delaunay(value)
        return Outcome(value, trace, mesh, (f"Lawson flips: {len(trace)} steps",))
    if isinstance(value, PSLG):
        construction = triangulate(
            value,
            keep_convex_hull=form.get("keep_convex_hull") == "on",
            split_segments=form.get("split_segments") == "on",
            merge_duplicates=form.get("merge_duplicates") == "on",
        )
        kind = "constrained Delaunay" if value.segments else "Delaunay"
        return Outcome(value, construction.trace, construction.mesh,
                       (f"{kind} triangulation: {len(construction.trace)} steps",))
    raise JobFailed(HTTPStatus.BAD_REQUEST, "a polygon mesh cannot be triangulated")


CRITERIA = ("max_area", "min_angle", "average_area_factor", "max_edge_length")
MAX_STEPS_LIMIT = 5_000_000


def _refine_available() -> bool:
    import importlib.util

    return importlib.util.find_spec("geomexact.mesh2d.refinement.api") is not None


def _refine(value: Any, form: dict[str, str]) -> Outcome:
    from geomexact.errors import GeomexactError
    from geomexact.mesh2d.delaunay.triangulation import triangulate
    from geomexact.mesh2d.pslg import PSLG
    from geomexact.mesh2d.refinement import criteria
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.snapshot import Mesh2

    report: list[str] = []
    if isinstance(value, PSLG):
        construction = triangulate(value)
        mesh = construction.mesh
        report.append(f"constrained Delaunay triangulation first: {mesh.triangle_count} "
                      "triangles")
    elif isinstance(value, Mesh2):
        mesh = value
    else:
        raise JobFailed(HTTPStatus.BAD_REQUEST, "a polygon mesh cannot be refined")
    kind = form.get("criterion", "max_area")
    text = form.get("value", "").strip()
    if kind not in CRITERIA:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"unknown criterion {kind!r}")
    if not text:
        raise JobFailed(HTTPStatus.BAD_REQUEST, "give the criterion a value")
    makers = {
        "max_area": criteria.MaxArea,
        "min_angle": criteria.MinAngle,
        "average_area_factor": criteria.AverageAreaFactor,
        "max_edge_length": criteria.MaxEdgeLength,
    }
    try:
        criterion = makers[kind](text)
    except (GeomexactError, ValueError, TypeError) as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, f"{kind.replace('_', ' ')}: {error}") from None
    steps_text = form.get("max_steps", "").strip()
    max_steps = None
    if steps_text:
        if not steps_text.isdigit() or int(steps_text) > MAX_STEPS_LIMIT:
            raise JobFailed(HTTPStatus.BAD_REQUEST,
                            f"max steps must be an integer from 0 to {MAX_STEPS_LIMIT}")
        max_steps = int(steps_text)
    method = form.get("method", "centroid")
    try:
        result = refine(mesh, criterion, method=method, max_steps=max_steps)  # type: ignore[arg-type]
    except GeomexactError as error:
        raise JobFailed(HTTPStatus.BAD_REQUEST, str(error)) from None
    report.append(f"Lepp-{method} refinement ({kind.replace('_', ' ')} {text}): "
                  f"{len(result.trace)} steps, {result.status}")
    return Outcome(mesh, result.trace, result.mesh, tuple(report))


ACTIONS: dict[str, Action] = {
    "refine": Action("refine (Lepp)", _refine_available, _refine),
    "triangulate": Action("triangulate (constrained Delaunay / Lawson flips)",
                          lambda: True, _triangulate),
}
"""Upload actions by name; the first available one is the form's default."""


def available_actions() -> list[str]:
    """Names of the actions usable in this installation."""
    return [name for name, action in ACTIONS.items() if action.available()]
