"""Lepp refinement of 2D meshes: Lepp-bisection, Lepp-centroid Delaunay, Lepp quasi-Delaunay.

``refine(mesh, criterion, ...)`` refines the triangles of ``region`` that ``criterion``
rates bad, worst first, each by repeating Lepp steps (``geomexact.mesh2d.longest_edge``) until it is
destroyed.  Every change is a step of :mod:`geomexact.mesh2d.ops` (``bisect``, ``flip``,
``insert_centroid``, ``insert_vertex_centroid``) or of :mod:`geomexact.mesh2d.refinement.centroids`
(``insert_in_quadrilateral``) recorded in the returned trace, which replays the input to
the result digest by digest; the input snapshot never changes.

Methods (``specs/refine.md``), for the terminal edge e = {u, v} of the triangles t1 (the
last of the path) and t2 (across e):

* ``"bisection"`` (Rivara): bisect e (one triangle when e is a boundary edge); with
  ``delaunay=True`` followed by Lawson legalization around the midpoint.
* ``"centroid"`` (Rivara & Rodríguez, terminal-triangles centroid): e a constraint edge ->
  bisect e; else when the second-longest edge of t1 (then t2) is a constraint edge ->
  bisect that edge; else insert the centroid of the quadrilateral t1 ∪ t2.  Each insertion
  is followed by legalization when ``delaunay=True``.
* ``"quasi"`` (Mellado, quasi-Delaunay): no legalization; at an unconstrained terminal
  pair that is not locally Delaunay, flip e (when ``delaunay=True``) and search again;
  otherwise insert as the centroid method does.

Two tiers run it (:mod:`geomexact.mesh2d.engine_names`); both record identical traces
(``tests/engines/test_engine_equivalence.py``):

* ``"reference"``: the ops on a :class:`~geomexact.mesh2d.transient.Transient2`, the
  definition (:mod:`geomexact.mesh2d.refinement.engines.reference`); ``"python"`` names
  it too (the pure-Python batch engine it once named was retired: issue 25);
* ``"compiled"``: the compiled kernel (:mod:`geomexact.mesh2d.refinement.engines.compiled`,
  a C extension built at install when a compiler is present, or from a wheel) for every
  method, criterion, rule, region and attribute (only a minimum-angle criterion of another
  type than ``MinAngle`` is outside it); outside it, or not built, it raises
  :class:`~geomexact.errors.PreconditionError`;
* ``"auto"`` (the default): ``"compiled"`` where it applies, else ``"reference"``.

``"fast"`` and ``"transient"`` are the old names of ``"auto"`` and ``"reference"``.

>>> from geomexact.mesh2d.refinement.criteria import MaxArea
>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> result = refine(square, MaxArea("1/8"))
>>> result.status, result.mesh.triangle_count, len(result.trace)
('complete', 8, 5)
"""

from __future__ import annotations

import operator
import time
from collections import Counter
from collections.abc import Callable
from typing import Any, Literal

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2
from geomexact.mesh2d.engine_names import ENGINES, Engine, engine_named
from geomexact.mesh2d.refinement.budget import default_budget
from geomexact.mesh2d.refinement.criteria import Criterion, as_criterion, rate_with_attributes
from geomexact.mesh2d.refinement.driver import (
    TIP_DEPTH,
    LeftReason,
    Method,
    Progress,
    Refinement,
    RunOptions,
    Status,
)
from geomexact.mesh2d.refinement.engines.compiled import run_compiled, unsupported
from geomexact.mesh2d.refinement.engines.reference import ReferenceRefinement
from geomexact.mesh2d.refinement.presets import (
    CENTROIDS,
    CentroidKind,
    FactorStop,
    Order,
    Preset,
    Rules,
    SecondLongestRule,
)
from geomexact.mesh2d.refinement.presets import rules as rules_of
from geomexact.mesh2d.refinement.regions import Region, Whole, as_region
from geomexact.mesh2d.snapshot import Mesh2, Triangle
from geomexact.trace.record import Trace

__all__ = [
    "CENTROIDS",
    "ENGINES",
    "METHODS",
    "Progress",
    "RefineStats",
    "Result",
    "refine",
]

METHODS: tuple[str, ...] = ("bisection", "centroid", "quasi")


@attrs.frozen(slots=True)
class RefineStats:
    """Counts of a run.

    ``status``: ``"complete"`` (every triangle of the region meets the
    criterion or is listed in ``left``; for an average-area criterion, the mean is reached)
    or ``"step-limit"`` (stopped by ``max_steps``) or ``"budget"`` (stopped by the default
    budget, :func:`~geomexact.mesh2d.refinement.budget.default_budget`); ``steps``: trace
    length; ``bisections``: edge midpoints inserted; ``centroids``: quadrilateral centroids
    inserted; ``flips``: legalization and quasi-Delaunay flips; ``targets``: bad triangles
    taken from the queue; ``lepp_searches`` / ``lepp_triangles``: Lepp paths computed and
    their total length in triangles; ``left``: bad triangles of the final mesh left alone at
    input angles below the minimum angle (sorted, canonical), and ``left_reasons`` why, one
    per triangle of ``left`` (:data:`~geomexact.mesh2d.refinement.driver.LeftReason`):
    ``"sharp-corner"`` — an angle below it inside such an input angle — or
    ``"protected-tip"`` — its Lepp step would split a constraint edge of such an input angle
    shorter than 2^-TIP_DEPTH of its input length; ``waiting``: after a step limit, the bad
    triangles of the region not refined yet (sorted; none for a region-wide criterion or a
    complete run); ``seconds``: wall time."""

    status: Status
    steps: int
    bisections: int
    centroids: int
    flips: int
    targets: int
    lepp_searches: int
    lepp_triangles: int
    left: tuple[Triangle, ...]
    seconds: float
    left_reasons: tuple[LeftReason, ...] = ()
    waiting: tuple[Triangle, ...] = ()

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready counts (``left`` as a count, with ``left_reasons`` counted by
        reason; ``waiting`` as a count)."""
        return {
            "status": self.status,
            "steps": self.steps,
            "bisections": self.bisections,
            "centroids": self.centroids,
            "flips": self.flips,
            "targets": self.targets,
            "lepp_searches": self.lepp_searches,
            "lepp_triangles": self.lepp_triangles,
            "left": len(self.left),
            "left_reasons": dict(sorted(Counter(self.left_reasons).items())),
            "waiting": len(self.waiting),
            "seconds": self.seconds,
        }

    def left_summary(self) -> str | None:
        """One sentence on the triangles the run did not make good, each group with its
        reason (None when there are none)."""
        parts = []
        reasons = Counter(self.left_reasons)
        if reasons["sharp-corner"]:
            parts.append(
                f"{reasons['sharp-corner']} at a sharp input corner (their small angle lies "
                "in an input angle below the minimum, which no triangulation improves)"
            )
        if reasons["protected-tip"]:
            parts.append(
                f"{reasons['protected-tip']} whose refinement would split a protected tip "
                f"(a segment of such a corner shorter than 2^-{TIP_DEPTH} of its input "
                "length)"
            )
        if self.waiting:
            limit = "default step budget" if self.status == "budget" else "step limit"
            parts.append(
                f"{len(self.waiting)} not refined yet: the run stopped at the {limit} "
                f"({self.steps} steps)"
            )
        if not parts:
            return None
        count = len(self.left) + len(self.waiting)
        return f"{count} triangle(s) do not meet the criterion: " + "; ".join(parts)


@attrs.frozen(slots=True)
class Result:
    """A refinement run: the input (``start``), the result (``mesh``), the trace replaying
    ``start`` to ``mesh``, and the run's :class:`RefineStats`."""

    start: Mesh2
    mesh: Mesh2
    trace: Trace
    stats: RefineStats

    @property
    def status(self) -> Status:
        """``"complete"``, ``"step-limit"`` or ``"budget"``."""
        return self.stats.status


_OP = operator.attrgetter("op")


def refine(
    mesh: Mesh2,
    criterion: Criterion | Callable[[Point2, Point2, Point2], object],
    *,
    region: Region | Callable[[Point2], object] | None = None,
    method: Method = "bisection",
    delaunay: bool = True,
    centroid: CentroidKind | None = None,
    constraint_midpoints: bool | None = None,
    max_steps: int | Literal["auto"] | None = "auto",
    step_cap: int | None = None,
    on_step: Callable[[Progress], None] | None = None,
    engine: Engine = "auto",
    preset: Preset | None = None,
    order: Order | None = None,
    second_longest_rule: SecondLongestRule | None = None,
    factor_stop: FactorStop | None = None,
    rules: Rules | None = None,
) -> Result:
    """Refine the triangles of ``region`` that ``criterion`` rates bad, by Lepp steps.

    Parameters
    ----------
    mesh:
        The input snapshot (never changed).  For a Delaunay method it should be (constrained)
        Delaunay; then the result is too.
    criterion:
        A :class:`~geomexact.mesh2d.refinement.criteria.Criterion` (``MaxArea``,
        ``AverageAreaFactor``,
        ``MinAngle``, ``MaxEdgeLength``, ``CallableCriterion``) or a callable
        ``test(a, b, c) -> bool``.
    region:
        A :class:`~geomexact.mesh2d.refinement.regions.Region` or a callable ``contains(point) ->
        bool``
        (default: the whole mesh).  A triangle is in the region when one of its vertices is.
    method:
        ``"bisection"``, ``"centroid"`` or ``"quasi"`` (module docstring).
    delaunay:
        Legalize after each insertion (bisection, centroid) or flip non-Delaunay terminal
        pairs (quasi).  ``False`` never flips.
    centroid:
        (Default ``"area"``, or the preset's.)  The point inserted into a terminal
        quadrilateral: ``"area"`` (its area centroid rounded to 24 bits below its shortest
        side, step ``insert_in_quadrilateral``; see
        :mod:`geomexact.mesh2d.refinement.centroids`), ``"area-exact"`` (the exact area
        centroid, step ``insert_centroid``: coordinate sizes grow geometrically, for small
        runs only), ``"vertices"`` (the mean of its four vertices, exact, step
        ``insert_vertex_centroid``) or ``"midpoint"`` (no centroid: the terminal edge is
        bisected, Mellado's ``centroid=false`` variant; with ``method="quasi"`` it is
        Lepp-bisection with quasi-Delaunay flips).
    constraint_midpoints:
        Deprecated (a :class:`~geomexact.errors.GeomexactDeprecationWarning`): the older
        name of ``second_longest_rule``: True is ``"bisect-second"`` (when a
        terminal triangle's second-longest edge is a constraint edge, insert that edge's
        midpoint instead of the centroid: Rivara & Rodríguez's rule for convergence near
        constraints), False ``"centroid"`` (always the centroid, as QLepp2D does).
    max_steps:
        Stop before the step that would exceed it, with status ``"step-limit"`` (a run may
        stop inside a legalization: the mesh is valid but need not be Delaunay).  Required
        with a minimum-angle criterion for Lepp-bisection and for ``delaunay=False``, which
        cannot meet it in general.  ``"auto"`` (the default) is the budget
        :func:`~geomexact.mesh2d.refinement.budget.default_budget` derived from the input
        and the criterion; a run it stops has status ``"budget"``.  ``None`` runs without
        any limit.
    step_cap:
        A further limit set from outside the refinement (a command's memory budget), or
        None: when it is below ``max_steps`` it acts as a budget (a run it stops has
        status ``"budget"`` and records it as ``step_budget``); a run it does not stop is
        the same run, trace and all, as without it.
    on_step:
        Called with a :class:`Progress` after every step.
    engine:
        ``"auto"`` (the compiled kernel where it applies, else ``"reference"``),
        ``"compiled"`` (the kernel, or :class:`~geomexact.errors.PreconditionError` when it
        is not built or does not implement this run) or ``"reference"`` (the ops on a
        transient, pure Python; ``"python"`` names it too).  All record the same trace.
        ``"fast"`` and ``"transient"`` are old names of ``"auto"`` and ``"reference"``
        (deprecated).
    preset:
        ``"pineda"`` or ``"mellado"``: the rules of that paper's program
        (:mod:`geomexact.mesh2d.refinement.presets`, ``specs/refine.md``), each of which
        the options below (and ``centroid``) override one by one.  None: geomexact's rules.
    order:
        ``"worst-first"`` (default: a priority queue, worst key first) or ``"passes"``
        (the bad triangles in passes, each pass in vertex-id order, until none is left).
    second_longest_rule:
        What a terminal pair whose triangle has a constraint second-longest edge gets:
        ``"bisect-second"`` (default: that edge's midpoint), ``"centroid"`` (ignored: the
        centroid) or ``"bisect-longest"`` (the midpoint of the terminal edge).
    factor_stop:
        ``"action"`` (default: an average-area factor is checked after every action) or
        ``"target"`` (after each refined target).
    rules:
        All of the above at once, as one
        :class:`~geomexact.mesh2d.refinement.presets.Rules` record (made by
        :func:`~geomexact.mesh2d.refinement.presets.rules`, which checks them, from a
        preset and overrides); then none of ``preset``, ``centroid``, ``order``,
        ``second_longest_rule``, ``factor_stop`` and ``constraint_midpoints`` is given.

    Raises :class:`~geomexact.errors.PreconditionError` for an unknown method, centroid or
    engine, engine ``"compiled"`` where the kernel cannot run, a negative ``max_steps``,
    or a minimum angle with bisection or without Delaunay flips and no step limit.

    Every decision is exact and every tie is broken by vertex ids (``specs/refine.md``),
    so the trace is the same on every machine.  Cost: O(steps × Lepp length) exact
    predicates.  The cyclic garbage collector is paused during the run
    (:func:`geomexact.kernel.collector.collector_paused`: afterwards every tracked object is in
    the oldest generation, so the new mesh is not scanned by young collections).
    """
    rule = as_criterion(criterion)
    area = as_region(region)
    if method not in METHODS:
        raise PreconditionError("refine", f"unknown method {method!r}; choose from {METHODS}")
    if rules is None:  # (a deprecated constraint_midpoints warns at the caller's line)
        chosen = rules_of(preset, centroid=centroid, order=order,
                          second_longest_rule=second_longest_rule, factor_stop=factor_stop,
                          constraint_midpoints=constraint_midpoints, stacklevel=3)
    elif any(value is not None for value in (preset, centroid, order, second_longest_rule,
                                              factor_stop, constraint_midpoints)):
        raise PreconditionError(
            "refine", "give the rules once: rules=Rules(...) or the preset and the rules "
            "one by one, not both")
    else:
        chosen = rules
    centroid = chosen.centroid
    constraint_midpoints = chosen.second_longest_rule == "bisect-second"
    name = engine_named("refine", engine)
    if max_steps is not None and max_steps != "auto" and (
        isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 0
    ):
        raise PreconditionError("refine", f"max_steps must be an integer >= 0, not {max_steps!r}")
    if rule.angle_threshold is not None and (max_steps is None or max_steps == "auto"):
        if method == "bisection":
            raise PreconditionError(
                "refine",
                "Lepp-bisection does not raise angles (each bisection keeps or halves the "
                "angles at the split), so a minimum-angle criterion may never be met; pass "
                "method='centroid' or method='quasi', or give a step limit max_steps=N to "
                "bisect anyway",
            )
        if not delaunay:
            raise PreconditionError(
                "refine",
                "without Delaunay flips no angle at an existing vertex ever grows (insertions "
                "only split angles), so a minimum-angle criterion may never be met; pass "
                "delaunay=True to allow flips, or give a step limit max_steps=N",
            )
    budget = default_budget(mesh, rule) if max_steps == "auto" else None
    limit = budget if max_steps == "auto" else max_steps
    if step_cap is not None and (limit is None or step_cap < limit):
        if step_cap < 0:
            raise PreconditionError("refine", f"step_cap must be >= 0, not {step_cap!r}")
        limit = budget = step_cap
    began = time.perf_counter()
    run_options = RunOptions(rule, area, method, delaunay, chosen, on_step)
    if name == "compiled":
        reason = unsupported(mesh, run_options)
        if reason is not None:
            raise PreconditionError(
                "refine", f"engine 'compiled' cannot run this refinement: {reason} "
                "(engine 'auto' runs the reference engine where the kernel does not apply)"
            )
    with collector_paused():  # a large run makes millions of small tuples
        compiled = (
            run_compiled(mesh, limit, run_options) if name in ("auto", "compiled") else None
        )
        status: Status
        if compiled is not None:
            status, result, steps, digests = (
                compiled.status, compiled.mesh, compiled.steps, compiled.digests
            )
            left, targets, searches, hops = (
                compiled.left, compiled.targets, compiled.searches, compiled.hops
            )
            reasons: tuple[LeftReason, ...] = compiled.left_reasons
            ops = Counter(compiled.op_counts)
        else:
            # the reference ops: the engine of every run the kernel does not take, and of
            # "python" (its pure-Python batch engine was retired: issue 25)
            run: Refinement = ReferenceRefinement(mesh, limit, run_options)
            run.start_queue(sorted(mesh.iter_triangles()))
            status = run.run()
            result, steps, digests = run.finish(mesh)
            left, reasons = run.left_triangles(), run.left_reasons()
            targets, searches, hops = run.targets, run.searches, run.hops
            ops = Counter(map(_OP, steps))
            del run  # its work tables go now, before the collector would scan them
    if budget is not None and status == "step-limit":
        status = "budget"
    from geomexact._version import __version__

    parameters: dict[str, Any] = {
        "algorithm": "lepp",
        "method": method,
        "delaunay": delaunay,
        "centroid": centroid,
        "constraint_midpoints": constraint_midpoints,
        "criterion": rule.parameters(),
        "region": area.parameters(),
        "max_steps": None if max_steps == "auto" else max_steps,
    }
    if status == "budget":  # a run the budget did not stop never depended on it
        parameters["step_budget"] = budget
    if chosen.preset is not None:
        parameters["preset"] = chosen.preset
    parameters.update({name: value for name, value in chosen.changed().items()
                       if name != "centroid"})
    trace = Trace(mesh.digest, steps, digests, parameters, __version__)
    stats = RefineStats(
        status=status,
        steps=len(steps),
        bisections=ops["bisect"],
        centroids=ops["insert_in_quadrilateral"] + ops["insert_centroid"]
        + ops["insert_vertex_centroid"],
        flips=ops["flip"],
        targets=targets,
        lepp_searches=searches,
        lepp_triangles=hops,
        left=left,
        seconds=time.perf_counter() - began,
        left_reasons=reasons,
        waiting=_waiting(result, rule, area, left) if status != "complete" else (),
    )
    return Result(mesh, result, trace, stats)


def _waiting(
    mesh: Mesh2, criterion: Criterion, region: Region, left: tuple[Triangle, ...]
) -> tuple[Triangle, ...]:
    """The triangles of ``region`` that ``criterion`` rates bad and that are not left:
    what a stopped run had not refined yet (none for a region-wide criterion)."""
    if criterion.target_mean_area(mpq(1), 1) is not None:
        return ()
    whole = isinstance(region, Whole)
    skip = set(left)
    found = []
    for triangle in sorted(mesh.iter_triangles()):
        corners = [mesh.point(vertex) for vertex in triangle]
        if triangle in skip or not (whole or any(region.contains(p) for p in corners)):
            continue
        if rate_with_attributes(criterion, corners[0], corners[1], corners[2],
                                mesh.triangle_attributes.get(triangle)) is not None:
            found.append(triangle)
    return tuple(found)

