"""The reference engine: the refinement loop of
:class:`~geomexact.mesh2d.refinement.driver.Refinement` with every step the op of
:mod:`geomexact.mesh2d.ops` on a :class:`~geomexact.mesh2d.transient.Transient2` and every
Lepp search :func:`geomexact.mesh2d.longest_edge.lepp`."""

from __future__ import annotations

from collections.abc import Callable

from geomexact.kernel.points import Point2
from geomexact.mesh2d.longest_edge import lepp
from geomexact.mesh2d.ops import (
    bisect_in,
    flip_in,
    insert_centroid_in,
    insert_in_quadrilateral_in,
    legalize_in,
)
from geomexact.mesh2d.refinement.centroids import rounded_area_centroid
from geomexact.mesh2d.refinement.driver import (
    Progress,
    Refinement,
    RunOptions,
    StepLimit,
)
from geomexact.mesh2d.snapshot import Attributes, Mesh2, Triangle, canonical_triangle
from geomexact.mesh2d.transient import Transient2
from geomexact.trace.step import Step


class RecordingTransient(Transient2):
    """A transient that lists the triangles it adds and removes, refuses to start a step
    beyond the step limit, and reports each step."""

    __slots__ = ("created", "limit", "removed", "report")

    def __init__(self, mesh: Mesh2, limit: int | None) -> None:
        super().__init__(mesh)
        self.created: list[Triangle] = []
        self.removed: list[Triangle] = []
        self.limit = limit
        self.report: Callable[[Step], None] | None = None

    def _guard(self) -> None:
        # the first edit of each step used here is add_vertex or remove_triangle, and the
        # step count changes only when the step is complete
        if self.limit is not None and len(self.steps) >= self.limit:
            raise StepLimit

    def add_vertex(
        self, point: Point2, marker: int = 0, attributes: Attributes = ()
    ) -> int:
        self._guard()
        return super().add_vertex(point, marker, attributes)

    def add_triangle(
        self, a: int, b: int, c: int, attributes: Attributes | None = None
    ) -> None:
        super().add_triangle(a, b, c, attributes)
        self.created.append(canonical_triangle(a, b, c))

    def remove_triangle(self, a: int, b: int, c: int) -> Attributes | None:
        self._guard()
        attributes = super().remove_triangle(a, b, c)
        self.removed.append(canonical_triangle(a, b, c))
        return attributes

    def record(self, step: Step) -> None:
        super().record(step)
        if self.report is not None:
            self.report(step)


class ReferenceRefinement(Refinement):
    """The refinement loop on a recording transient: the readable reference the other
    engines are tested against, step by step."""

    def __init__(self, mesh: Mesh2, max_steps: int | None, run: RunOptions) -> None:
        super().__init__(mesh, run)
        self.t = t = RecordingTransient(mesh, max_steps)
        t.created = self.created
        t.removed = self.removed
        self.get = lambda edge: t.apex(edge[0], edge[1])
        self.point = t.point
        self.attributed = bool(len(mesh.triangle_attributes))
        if self.on_step is not None:
            t.report = self._report

    def _report(self, step: Step) -> None:
        assert self.on_step is not None
        t = self.t
        self.on_step(
            Progress(len(t.steps), step, t.triangle_count, t.vertex_count, self.queue.size)
        )

    def is_segment(self, u: int, v: int) -> bool:
        return self.t.segment_marker(u, v) is not None

    def attributes(self, triangle: Triangle) -> Attributes | None:
        return self.t.triangle_attributes(triangle)

    def bisect(self, u: int, v: int) -> int:
        return bisect_in(self.t, u, v)

    def flip(self, u: int, v: int) -> None:
        flip_in(self.t, u, v)

    def centroid(self, u: int, v: int) -> int:
        t = self.t
        if self.centroid_kind == "area":
            w, x = t.apex(u, v), t.apex(v, u)
            assert w is not None and x is not None
            point = rounded_area_centroid(t.point(u), t.point(v), t.point(w), t.point(x))
            return insert_in_quadrilateral_in(t, u, v, point)
        kind = "area" if self.centroid_kind == "area-exact" else "vertices"
        return insert_centroid_in(t, u, v, kind=kind)

    def legalize(self, vertex: int) -> None:
        legalize_in(self.t, vertex)

    def terminal(self, a: int, b: int, c: int) -> tuple[int, int, int, int | None, bool]:
        path = lepp(self.t, (a, b, c))
        self.searches += 1
        self.hops += len(path.path)
        u, v = path.terminal_edge
        w = self.t.apex(u, v)
        assert w is not None  # the terminal edge has the path's last triangle on its left
        return u, v, w, self.t.apex(v, u), path.kind != "interior"

    def finish(self, start: Mesh2) -> tuple[Mesh2, list[Step], list[int]]:
        t = self.t
        return t.seal(), t.steps, t.step_digests

