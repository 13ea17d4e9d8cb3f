"""The default step budget of a refinement: every run ends, or says why not.

``refine(..., max_steps="auto")`` (the default) stops a run after :func:`default_budget`
steps with status ``"budget"`` instead of letting it grow without bound.  The budget is a
generous multiple of what the input and the criterion let us estimate
(``specs/refine.md``, "The default budget"):

    budget = 100 × (T + E) + 10,000 steps

where T is the input's triangle count and E the criterion's estimate of the triangles it
needs:

* ``MaxArea(A)``: ⌈2·|Ω| / A⌉, with |Ω| the mesh's area;
* ``MaxEdgeLength(L)``: ⌈4·|Ω| / L²⌉;
* ``RegionAreas``: the sum over its regions of ⌈2·|Ωᵢ| / Aᵢ⌉, |Ωᵢ| the area of the
  triangles of region i (their first attribute);
* ``AverageAreaFactor(f)``: ⌈T / f⌉;
* ``MinAngle`` and callables: 0 (the size is set by the input's features, which T counts).

The terminating runs measured for the termination suite (``tests/mesh2d/refinement/
test_refine_termination.py``) use under a tenth of it.

>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> from geomexact.mesh2d.refinement.criteria import MaxArea, MinAngle
>>> square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> default_budget(square, MinAngle(30))
10200
>>> default_budget(square, MaxArea("1/100"))
30200
"""

from __future__ import annotations

from geomexact.kernel.numbers import Rational, mpq
from geomexact.mesh2d.refinement.criteria import (
    AnyOf,
    AverageAreaFactor,
    Criterion,
    MaxArea,
    MaxEdgeLength,
    RegionAreas,
    doubled_area,
)
from geomexact.mesh2d.snapshot import Mesh2

__all__ = ["BUDGET_BASE", "BUDGET_FACTOR", "budget_of", "default_budget", "estimated_triangles"]

BUDGET_FACTOR = 100
"""Steps allowed per triangle of the input and of the criterion's estimate."""

BUDGET_BASE = 10_000
"""Steps allowed to every run on top of the per-triangle allowance."""


def _ceiling(value: Rational) -> int:
    return int(-((-value.numerator) // value.denominator))


_RECENT: dict[tuple[int, Criterion], int] = {}
"""The last few estimates by (mesh digest, criterion): a command computes E for its memory
budget and ``refine()`` again for the step budget, and an O(T) exact sum is paid once."""


def estimated_triangles(mesh: Mesh2, criterion: Criterion) -> int:
    """The criterion's rough estimate E of the triangles a refinement of ``mesh`` needs
    (module docstring); 0 when the criterion gives no size."""
    key = (mesh.digest, criterion)
    try:
        return _RECENT[key]
    except (KeyError, TypeError):  # not seen, or a criterion that does not hash
        pass
    estimate = _estimated(mesh, criterion)
    try:
        if len(_RECENT) >= 8:
            del _RECENT[next(iter(_RECENT))]
        _RECENT[key] = estimate
    except TypeError:
        pass
    return estimate


def _estimated(mesh: Mesh2, criterion: Criterion) -> int:
    if isinstance(criterion, AverageAreaFactor):
        return _ceiling(mpq(mesh.triangle_count) / criterion.factor)
    if isinstance(criterion, AnyOf):
        return max(_estimated(mesh, member) for member in criterion.criteria)
    if isinstance(criterion, RegionAreas):
        areas = dict(criterion.areas)
        region_area2: dict[Rational, Rational] = {}
        points = mesh.point_list()
        for a, b, c in mesh.iter_triangles():
            attributes = mesh.triangle_attributes.get((a, b, c))
            if attributes and attributes[0] in areas:
                region_area2[attributes[0]] = (region_area2.get(attributes[0], mpq(0))
                                               + doubled_area(points[a], points[b], points[c]))
        return sum(_ceiling(area2 / areas[key]) for key, area2 in region_area2.items())
    if not isinstance(criterion, (MaxArea, MaxEdgeLength)):
        return 0
    # the point list and the triangles come from a kernel's arrays when the mesh has them
    # (reading them builds no persistent table)
    points = mesh.point_list()
    area2 = mpq(0)
    for a, b, c in mesh.iter_triangles():
        area2 += doubled_area(points[a], points[b], points[c])
    if isinstance(criterion, MaxArea):
        return _ceiling(area2 / criterion.area)  # 2·|Ω| / A
    return _ceiling(2 * area2 / (criterion.length * criterion.length))  # 4·|Ω| / L²


def budget_of(triangles: int, estimate: int) -> int:
    """``100 × (T + E) + 10,000`` for ``triangles`` T and the criterion's ``estimate`` E
    (:func:`estimated_triangles`), for a caller that has E already."""
    return BUDGET_FACTOR * (triangles + estimate) + BUDGET_BASE


def default_budget(mesh: Mesh2, criterion: Criterion) -> int:
    """``100 × (T + E) + 10,000``: the steps a run may take unless ``max_steps`` says
    otherwise.  O(T) exact additions (for an area or length criterion)."""
    return budget_of(mesh.triangle_count, estimated_triangles(mesh, criterion))
