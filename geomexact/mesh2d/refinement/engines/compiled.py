"""The compiled Lepp engine: glue between :func:`geomexact.mesh2d.refinement.api.refine` and
the typed kernel :mod:`geomexact.mesh2d.refinement.engines.lepp_kernel` (a Cython
extension, optional).

``run_compiled(mesh, max_steps, run)`` takes the arguments of
``geomexact.mesh2d.refinement.engines.reference.ReferenceRefinement`` (a
:class:`~geomexact.mesh2d.refinement.driver.RunOptions`) and returns a
:class:`CompiledRun` — the same steps, digests, final mesh, status and counters as the
reference engine — or None when the kernel is not built or the run is outside its subset
(:func:`unsupported` says why):

* method ``"bisection"``, with or without Delaunay legalization; methods ``"centroid"``
  and ``"quasi"`` with every centroid kind (``"area"``: the rounded area centroid,
  computed by :func:`geomexact.mesh2d.refinement.centroids.rounded_area_centroid` and
  recorded as ``insert_in_quadrilateral``; ``"vertices"``, ``"area-exact"``: the exact
  centroids, ``insert_vertex_centroid``/``insert_centroid``; ``"midpoint"``), with or
  without ``delaunay``;
* every rule of the presets (:mod:`geomexact.mesh2d.refinement.presets`): both orders,
  the three second-longest rules and both factor stops;
* a criterion on single triangles: ``MinAngle`` (the exact type), rated in C (the angle
  opposite the shortest edge against the threshold by ``compare_angle``'s float filter,
  the key −cos² exact), with the small-angle rules of ``Refinement`` (sharp corners left,
  protected tips; ``left`` and ``left_reasons`` as the reference engine's); another criterion
  with no ``angle_threshold``, rated through its ``rate`` (``MaxArea`` in C on dyadic
  triangles; an ``AnyOf`` of such criteria too); ``AnyOf((MinAngle, X, ...))`` with
  such criteria after the angle (``--min-angle`` with ``--max-area`` and/or
  ``--max-edge``: the angle's entries first); or ``AverageAreaFactor`` (the exact type;
  no other region-wide target), the region's mean area tracked exactly as
  ``Refinement.account``; criteria that read triangle attributes (``RegionAreas``) get
  them;
* any region; triangle attributes (borders between them constrain as segments do, new
  triangles keep their parent's) and vertex attributes (interpolated at new vertices);
  any ``max_steps`` and ``on_step``.

``refine(..., engine="auto")`` (the default) uses it whenever it applies, and the reference
engine otherwise; ``engine="compiled"`` uses it or raises
:class:`~geomexact.errors.PreconditionError` with that reason; ``engine="reference"`` (or
``"python"``) never uses it (``tests/engines`` compares the two step by step).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Literal

import attrs

from geomexact.kernel.numbers import mpq
from geomexact.mesh2d.engine_names import compiled_kernel
from geomexact.mesh2d.refinement.criteria import (
    AnyOf,
    AverageAreaFactor,
    MaxArea,
    MinAngle,
    RegionAreas,
)
from geomexact.mesh2d.refinement.driver import LeftReason, Progress, RunOptions
from geomexact.mesh2d.refinement.regions import Whole
from geomexact.mesh2d.snapshot import Mesh2, Triangle
from geomexact.trace.deferred import deferred_trace
from geomexact.trace.step import Step

_lepp_kernel: Any = compiled_kernel("geomexact.mesh2d.refinement.engines.lepp_kernel")

__all__ = ["AVAILABLE", "REPLAYED_OPS", "CompiledRun", "replay_compiled", "run_compiled",
           "supports", "unsupported"]

AVAILABLE: bool = _lepp_kernel is not None
"""True when the extension is built and importable."""

@attrs.frozen(slots=True)
class CompiledRun:
    """What ``refine()`` needs from a run: the final snapshot, the trace (steps and the
    digest after each), the status and the counters of
    :class:`~geomexact.mesh2d.refinement.api.RefineStats` (``left`` and ``left_reasons``
    as ``Refinement.left_triangles`` and ``left_reasons``)."""

    mesh: Mesh2
    steps: Sequence[Step]
    digests: Sequence[int]
    status: Literal["complete", "step-limit"]
    left: tuple[Triangle, ...]
    targets: int
    searches: int
    hops: int
    left_reasons: tuple[LeftReason, ...] = ()
    op_counts: dict[str, int] = attrs.field(factory=dict)
    """How many steps of each op (counted by the kernel off its records)."""


@attrs.frozen(slots=True)
class KernelRun:
    """What one run of the Lepp kernel does (the kernel's constructor reads it; its
    docstring says what each field means): the criterion in the region, how it is rated
    in C, the method and the rules, the step limit and the progress callback."""

    criterion: Any
    region: Any
    delaunay: bool = True
    max_steps: int | None = None
    on_step: Callable[[Any], None] | None = None
    progress: Any = Progress
    max_area_doubled: Any = None
    average: bool = False
    method: str = "bisection"
    constraint_midpoints: bool = True
    threshold: Any = None
    area_rate: Callable[..., Any] | None = None
    grouped: bool = False
    centroid_kind: str = "area"
    order: str = "worst-first"
    second_longest_rule: str | None = None
    factor_stop: str = "action"
    rate_attributes: bool = False
    region_doubled: dict[Any, Any] | None = None

    @property
    def whole(self) -> bool:
        """The region is the whole mesh (no vertex test)."""
        return isinstance(self.region, Whole)


def unsupported(mesh: Mesh2, run: RunOptions) -> str | None:
    """Why the kernel cannot run this refinement exactly (not built, or outside its
    subset), or None when it can."""
    if not AVAILABLE:
        return "the compiled Lepp kernel is not built (no C compiler at install)"
    criterion = run.criterion
    if run.method not in ("bisection", "centroid", "quasi"):
        return f"it runs no method {run.method!r}"
    if isinstance(criterion, AnyOf):
        if criterion.angle_threshold is not None and not _angle_then_sizes(criterion):
            return ("a combination with a minimum angle it runs is AnyOf((MinAngle, ...)), "
                    "the angle first and then criteria on single triangles")
    elif criterion.angle_threshold is not None and type(criterion) is not MinAngle:
        return "the only minimum-angle criterion it runs is MinAngle"
    if type(criterion) is not AverageAreaFactor and (
        criterion.target_mean_area(mpq(1), 1) is not None
    ):
        return "the only region-wide criterion it runs is AverageAreaFactor"
    return None


def _angle_then_sizes(criterion: AnyOf) -> bool:
    """True for ``AnyOf((MinAngle(θ), X, ...))`` with each X on single triangles, no
    angle (``refine --min-angle`` with ``--max-area`` and/or ``--max-edge``)."""
    first, *rest = criterion.criteria
    return type(first) is MinAngle and all(
        member.angle_threshold is None and member.target_mean_area(mpq(1), 1) is None
        for member in rest)


def _needs_attributes(criterion: object) -> bool:
    """The criterion rates a triangle with its attributes (a region's maximum area)."""
    return bool(getattr(criterion, "needs_attributes", False))


def _region_doubled(criterion: object) -> dict[Any, Any] | None:
    """A ``RegionAreas``'s doubled maximum areas by region (rated in C on the grid),
    else None."""
    if type(criterion) is not RegionAreas:
        return None
    return {region: 2 * area for region, area in criterion.areas}  # type: ignore[attr-defined]


def supports(mesh: Mesh2, run: RunOptions) -> bool:
    """True when the kernel is available and implements this run exactly."""
    return unsupported(mesh, run) is None


def run_compiled(mesh: Mesh2, max_steps: int | None, run: RunOptions) -> CompiledRun | None:
    """Run Lepp refinement in the kernel, or return None (not built, or outside the
    subset): the run ``refine()`` gives ``ReferenceRefinement``."""
    if not supports(mesh, run):
        return None
    criterion, region = run.criterion, run.region
    on_step: Callable[[Any], None] | None = run.on_step
    doubled = 2 * criterion.area if type(criterion) is MaxArea else None
    angle: Any = criterion if type(criterion) is MinAngle else None
    area_rate = None
    grouped = False
    sized: object = criterion  # the size criterion the kernel rates in group 1
    if isinstance(criterion, AnyOf) and criterion.angle_threshold is not None:
        angle, *rest = criterion.criteria  # AnyOf((MinAngle, X, ...)): checked above
        if len(rest) == 1:  # X's own key, in group 1 (a MaxArea rated in C on the grid)
            sized = rest[0]
            area_rate = (rest[0].rate_attributed  # type: ignore[attr-defined]
                         if _needs_attributes(rest[0]) else rest[0].rate)
            doubled = 2 * rest[0].area if type(rest[0]) is MaxArea else None  # type: ignore[attr-defined]
        else:  # (position, key) of the first size the triangle fails
            area_rate, grouped = criterion.rate_beyond_angle, True
    # the kernel counts steps in int64: a larger limit is never reached anyway
    limit = None if max_steps is None or max_steps >= 1 << 62 else max_steps
    assert _lepp_kernel is not None
    kernel = _lepp_kernel.Kernel(mesh, KernelRun(
        criterion, region, delaunay=run.delaunay, max_steps=limit, on_step=on_step,
        max_area_doubled=doubled, average=type(criterion) is AverageAreaFactor,
        method=run.method, constraint_midpoints=run.constraint_midpoints,
        threshold=None if angle is None else angle.threshold, area_rate=area_rate,
        grouped=grouped, centroid_kind=run.rules.centroid, order=run.rules.order,
        second_longest_rule=run.rules.second_longest_rule,
        factor_stop=run.rules.factor_stop, rate_attributes=_needs_attributes(criterion),
        region_doubled=_region_doubled(sized)))
    status = kernel.run()
    result, made = kernel.finish(mesh)
    steps, digests = deferred_trace(kernel)  # made from its records when first read
    return CompiledRun(
        mesh=result,
        steps=made if made is not None else steps,  # (on_step made them already)
        digests=digests,
        status=status,
        left=kernel.left_triangles(),
        targets=kernel.targets,
        searches=kernel.searches,
        hops=kernel.hops,
        left_reasons=kernel.left_reasons(),
        op_counts=kernel.op_counts(),
    )


REPLAYED_OPS = frozenset({"bisect", "flip", "insert_in_quadrilateral",
                          "insert_vertex_centroid", "insert_centroid"})
"""The steps the kernel replays: those it records."""


def replay_compiled(start: Mesh2, steps: Sequence[Step], digests: Sequence[int]
                    ) -> Mesh2 | None:
    """The mesh after ``steps`` replayed on ``start`` by the kernel, each step's
    preconditions checked (those of its reference op) and each digest compared with
    ``digests``; None when the kernel cannot replay them all (not built, a
    step it does not record) or when a step fails or diverges -- the caller then replays
    with the reference ops, which name the step and the reason."""
    if not AVAILABLE or not {step.op for step in steps} <= REPLAYED_OPS:
        return None
    assert _lepp_kernel is not None
    # a criterion nothing fails: the kernel's queue stays empty
    nothing = MaxArea(mpq(2) ** 200)
    kernel = _lepp_kernel.Kernel(start, KernelRun(nothing, Whole(), delaunay=False,
                                                  max_area_doubled=2 * nothing.area))
    if kernel.replay(list(steps), list(digests), len(steps)) != len(steps):
        return None
    mesh: Mesh2 = kernel.finish(start)[0]
    return mesh
