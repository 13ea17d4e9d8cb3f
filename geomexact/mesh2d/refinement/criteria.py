"""Refinement criteria: what makes a triangle *bad* and how bad it is.

A :class:`Criterion` rates a counter-clockwise triangle from its three exact points:
``rate(a, b, c)`` is ``None`` for an acceptable triangle, else a *priority key* — an exact
value (``mpq``) or a tuple of them; the smallest key is refined first ("worst first"), and
equal keys are ordered by the triangle's vertex ids (``specs/refine.md``).  Every decision
is exact: areas and lengths in rationals, angles against an
:class:`~geomexact.kernel.angles.AngleThreshold`.

>>> from geomexact.kernel.points import point2
>>> a, b, c = point2(0, 0), point2(1, 0), point2(0, 1)
>>> MaxArea("0.5").rate(a, b, c) is None        # area 1/2 is allowed
True
>>> MaxArea("0.25").rate(a, b, c)               # too large: key = -(doubled area)
mpq(-1,1)
>>> MinAngle(30).rate(a, b, c) is None          # 45°, 45°, 90°
True
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any, ClassVar, Protocol, runtime_checkable

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.angles import AngleThreshold, compare_angle
from geomexact.kernel.comparisons import compare_squared_lengths
from geomexact.kernel.numbers import Rational, format_rational, mpq, to_rational
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Comparison
from geomexact.mesh2d.pslg import PSLG

__all__ = [
    "AnyOf",
    "AverageAreaFactor",
    "CallableCriterion",
    "Criterion",
    "MaxArea",
    "MaxEdgeLength",
    "MinAngle",
    "RegionAreas",
    "as_criterion",
    "doubled_area",
    "rate_with_attributes",
    "region_areas_of",
    "smallest_angle_cos2",
]

_LESS = Comparison.LESS
_GREATER = Comparison.GREATER


@runtime_checkable
class Criterion(Protocol):
    """The refinement goal.

    ``rate(a, b, c)``: None when the counter-clockwise triangle abc is acceptable, else its
    priority key (smaller = refined first); it must depend only on the three points.
    ``angle_threshold``: the minimum angle the criterion asks for, or None (refinement uses
    it to leave triangles whose small angle lies between input constraints).
    ``target_mean_area(total, count)``: for a criterion on the region as a whole, the mean
    triangle area at which refinement stops, given the region's initial total area and
    triangle count; None for a criterion on each triangle.
    ``parameters()``: a JSON description for trace headers.
    """

    @property
    def angle_threshold(self) -> AngleThreshold | None:
        """The minimum angle asked for, or None."""
        ...

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Any | None:
        """None when acceptable, else the priority key."""
        ...

    def target_mean_area(self, total: Rational, count: int, /) -> Rational | None:
        """The stopping mean area for a region-wide criterion, else None."""
        ...

    def parameters(self) -> dict[str, Any]:
        """JSON description."""
        ...


def doubled_area(a: Point2, b: Point2, c: Point2) -> Rational:
    """Twice the signed area of triangle abc (positive when counter-clockwise), exact."""
    ax, ay = a[0], a[1]
    return (b[0] - ax) * (c[1] - ay) - (b[1] - ay) * (c[0] - ax)


def _positive(name: str, value: object) -> Rational:
    number = to_rational(value)
    if not number > 0:
        raise PreconditionError(name, f"the value must be positive, not {format_rational(number)}")
    return number


def _positive_area(value: object) -> Rational:
    return _positive("MaxArea", value)


def _positive_factor(value: object) -> Rational:
    return _positive("AverageAreaFactor", value)


def _positive_length(value: object) -> Rational:
    return _positive("MaxEdgeLength", value)


class _Local:
    """Shared defaults of criteria on single triangles."""

    __slots__ = ()

    @property
    def angle_threshold(self) -> AngleThreshold | None:
        return None

    def target_mean_area(self, total: Rational, count: int, /) -> Rational | None:
        return None


@attrs.frozen(slots=True)
class MaxArea(_Local):
    """Bad when the triangle's area exceeds ``area`` (> 0).  Key: −(doubled area), so the
    largest triangle is refined first."""

    area: Rational = attrs.field(converter=_positive_area)
    _doubled: Rational = attrs.field(init=False, repr=False, eq=False)

    def __attrs_post_init__(self) -> None:
        object.__setattr__(self, "_doubled", 2 * self.area)

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Rational | None:
        ax, ay = a[0], a[1]
        twice = (b[0] - ax) * (c[1] - ay) - (b[1] - ay) * (c[0] - ax)
        return -twice if twice > self._doubled else None

    def parameters(self) -> dict[str, Any]:
        return {"kind": "max_area", "area": format_rational(self.area)}


@attrs.frozen(slots=True)
class AverageAreaFactor:
    """Refine the largest triangles of the region, largest first, until the mean area of
    the region's triangles is at most ``factor`` (> 0) times its initial mean.  Every
    triangle of the region is a candidate (key: −(doubled area))."""

    factor: Rational = attrs.field(converter=_positive_factor)

    @property
    def angle_threshold(self) -> AngleThreshold | None:
        return None

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Rational:
        return -doubled_area(a, b, c)

    def target_mean_area(self, total: Rational, count: int, /) -> Rational | None:
        """``factor × total / count`` (0 for an empty region: nothing to refine)."""
        return self.factor * total / count if count else mpq(0)

    def parameters(self) -> dict[str, Any]:
        return {"kind": "average_area_factor", "factor": format_rational(self.factor)}


def smallest_angle_cos2(a: Point2, b: Point2, c: Point2) -> Rational:
    """cos² of the smallest angle of triangle abc, exact (the smallest angle is opposite
    the shortest edge and is at most 60°, so a larger cos² means a smaller angle)."""
    if compare_squared_lengths(a, b, b, c) != _GREATER:  # ab is not longer than bc
        p, q, r = (c, a, b) if compare_squared_lengths(a, b, c, a) != _GREATER else (b, c, a)
    else:
        p, q, r = (a, b, c) if compare_squared_lengths(b, c, c, a) != _GREATER else (b, c, a)
    # p is opposite the shortest edge qr; angle at p between q - p and r - p
    ux, uy = q[0] - p[0], q[1] - p[1]
    vx, vy = r[0] - p[0], r[1] - p[1]
    dot = ux * vx + uy * vy
    result: Rational = dot * dot / ((ux * ux + uy * uy) * (vx * vx + vy * vy))
    return result


@attrs.frozen(slots=True)
class MinAngle:
    """Bad when the triangle's smallest angle is below ``degrees`` (0 < θ < 60).

    The comparison is exact against cos²θ when it is rational (θ = 30° or 45°), else against
    a rational bound that never accepts an angle below θ (see
    :class:`~geomexact.kernel.angles.AngleThreshold`).  Key: −cos²(smallest angle), exact, so
    the sharpest triangle is refined first.
    """

    degrees: Rational = attrs.field(converter=to_rational)
    threshold: AngleThreshold = attrs.field(init=False, repr=False, eq=False)

    def __attrs_post_init__(self) -> None:
        if not 0 < self.degrees < 60:
            raise PreconditionError(
                "MinAngle",
                f"the angle must be strictly between 0 and 60 degrees (a triangle's smallest "
                f"angle is at most 60°), not {format_rational(self.degrees)}",
            )
        object.__setattr__(self, "threshold", AngleThreshold.from_degrees(self.degrees))

    @property
    def angle_threshold(self) -> AngleThreshold | None:
        return self.threshold

    def is_small(self, p: Point2, apex: Point2, q: Point2) -> bool:
        """True when the angle at ``apex`` between p and q is below the threshold."""
        return compare_angle(p, apex, q, self.threshold) == _LESS

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Rational | None:
        # the smallest angle is opposite the shortest edge: find that corner first
        if compare_squared_lengths(a, b, b, c) != _GREATER:
            if compare_squared_lengths(a, b, c, a) != _GREATER:
                small = compare_angle(b, c, a, self.threshold) == _LESS  # shortest ab, at c
            else:
                small = compare_angle(a, b, c, self.threshold) == _LESS  # shortest ca, at b
        elif compare_squared_lengths(b, c, c, a) != _GREATER:
            small = compare_angle(c, a, b, self.threshold) == _LESS  # shortest bc, at a
        else:
            small = compare_angle(a, b, c, self.threshold) == _LESS  # shortest ca, at b
        return -smallest_angle_cos2(a, b, c) if small else None

    def target_mean_area(self, total: Rational, count: int, /) -> Rational | None:
        return None

    def parameters(self) -> dict[str, Any]:
        return {"kind": "min_angle", "degrees": format_rational(self.degrees)}


@attrs.frozen(slots=True)
class MaxEdgeLength(_Local):
    """Bad when some edge is longer than ``length`` (> 0).  Key: −(longest squared edge
    length)."""

    length: Rational = attrs.field(converter=_positive_length)
    _squared: Rational = attrs.field(init=False, repr=False, eq=False)

    def __attrs_post_init__(self) -> None:
        object.__setattr__(self, "_squared", self.length * self.length)

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Rational | None:
        longest = max(_squared_length(a, b), _squared_length(b, c), _squared_length(c, a))
        return -longest if longest > self._squared else None

    def parameters(self) -> dict[str, Any]:
        return {"kind": "max_edge_length", "length": format_rational(self.length)}


def _squared_length(p: Point2, q: Point2) -> Rational:
    dx, dy = q[0] - p[0], q[1] - p[1]
    result: Rational = dx * dx + dy * dy
    return result


@attrs.frozen(slots=True)
class CallableCriterion(_Local):
    """Bad when ``test(a, b, c)`` is true (it should be exact and deterministic).  Key:
    ``priority(a, b, c)`` when given (smaller first; values must be mutually comparable),
    else −(doubled area), largest first."""

    test: Callable[[Point2, Point2, Point2], object]
    priority: Callable[[Point2, Point2, Point2], Any] | None = None
    name: str = ""

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Any | None:
        if not self.test(a, b, c):
            return None
        if self.priority is not None:
            return self.priority(a, b, c)
        return -doubled_area(a, b, c)

    def parameters(self) -> dict[str, Any]:
        name = self.name or getattr(self.test, "__qualname__", repr(self.test))
        return {"kind": "callable", "name": name}


def _members(value: Sequence[Criterion]) -> tuple[Criterion, ...]:
    members = tuple(as_criterion(member) for member in value)
    if len(members) < 2:
        raise PreconditionError("AnyOf", f"combine two or more criteria, not {len(members)}")
    if any(member.target_mean_area(mpq(1), 1) is not None for member in members):
        raise PreconditionError("AnyOf", "a region-wide criterion (an average-area factor) "
                                "stops the whole run: it does not combine with others")
    if sum(member.angle_threshold is not None for member in members) > 1:
        raise PreconditionError("AnyOf", "combine at most one minimum angle")
    return members


@attrs.frozen(slots=True)
class AnyOf:
    """Bad while the triangle fails any of ``criteria`` (on single triangles; at most one
    minimum angle): Triangle's ``-q`` with ``-a``.  Key: (the position of the first
    criterion it fails, that criterion's key), so the triangles failing an earlier
    criterion are refined first, each group in its own order."""

    criteria: tuple[Criterion, ...] = attrs.field(converter=_members)

    @property
    def needs_attributes(self) -> bool:
        return any(getattr(member, "needs_attributes", False) for member in self.criteria)

    def rate_attributed(self, a: Point2, b: Point2, c: Point2,
                        attributes: tuple[Rational, ...] | None, /) -> tuple[int, Any] | None:
        for position, member in enumerate(self.criteria):
            key = rate_with_attributes(member, a, b, c, attributes)
            if key is not None:
                return (position, key)
        return None

    @property
    def angle_threshold(self) -> AngleThreshold | None:
        for member in self.criteria:
            if member.angle_threshold is not None:
                return member.angle_threshold
        return None

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> tuple[int, Any] | None:
        for position, member in enumerate(self.criteria):
            key = member.rate(a, b, c)
            if key is not None:
                return (position, key)
        return None

    def rate_beyond_angle(self, a: Point2, b: Point2, c: Point2,
                          attributes: tuple[Rational, ...] | None = None, /
                          ) -> tuple[int, Any] | None:
        """:meth:`rate` over the criteria other than the minimum angle: what still asks
        for a triangle whose small angle cannot be improved (it lies in a sharp input
        corner)."""
        for position, member in enumerate(self.criteria):
            if member.angle_threshold is None:
                key = rate_with_attributes(member, a, b, c, attributes)
                if key is not None:
                    return (position, key)
        return None

    def target_mean_area(self, total: Rational, count: int, /) -> Rational | None:
        return None

    def parameters(self) -> dict[str, Any]:
        return {"kind": "any_of", "criteria": [member.parameters() for member in self.criteria]}


def _areas(value: Iterable[tuple[Rational, Rational]]) -> tuple[tuple[Rational, Rational], ...]:
    found: dict[Rational, Rational] = {}
    for attribute, area in value:
        attribute, area = to_rational(attribute), _positive_area(area)
        if found.get(attribute, area) != area:
            raise PreconditionError("RegionAreas", f"two regions with attribute "
                                    f"{format_rational(attribute)} ask for different "
                                    "maximum areas: give each region its own attribute")
        found[attribute] = area
    if not found:
        raise PreconditionError("RegionAreas", "no region has a maximum area")
    return tuple(sorted(found.items()))


@attrs.frozen(slots=True)
class RegionAreas(_Local):
    """Bad when the triangle is larger than the maximum area of its region: Triangle's
    ``-a`` without a number, the areas of a ``.poly`` region list.  A triangle's region is
    its first attribute (set by the region seeds when the PSLG is triangulated, inherited
    by the triangles refinement makes); a triangle of no listed region is never bad.  Key:
    −(doubled area).  Rated with the triangle's attributes
    (:meth:`rate_attributed`): ``rate`` alone cannot tell the region and accepts."""

    areas: tuple[tuple[Rational, Rational], ...] = attrs.field(converter=_areas)
    needs_attributes: ClassVar[bool] = True

    def rate(self, a: Point2, b: Point2, c: Point2, /) -> Rational | None:
        return None

    def rate_attributed(self, a: Point2, b: Point2, c: Point2,
                        attributes: tuple[Rational, ...] | None, /) -> Rational | None:
        if not attributes:
            return None
        area = dict(self.areas).get(attributes[0])
        if area is None:
            return None
        twice = doubled_area(a, b, c)
        return -twice if twice > 2 * area else None

    def parameters(self) -> dict[str, Any]:
        return {"kind": "region_areas",
                "areas": {format_rational(k): format_rational(v) for k, v in self.areas}}


def region_areas_of(pslg: PSLG) -> RegionAreas:
    """The maximum areas of ``pslg``'s region seeds (by regional attribute)."""
    return RegionAreas(tuple((seed.attribute, seed.max_area) for seed in pslg.regions
                             if seed.max_area is not None))


def rate_with_attributes(criterion: Criterion, a: Point2, b: Point2, c: Point2,
                         attributes: tuple[Rational, ...] | None) -> Any | None:
    """``criterion``'s key of the triangle abc with these attributes (a criterion that
    needs attributes reads them; the others rate the points)."""
    if getattr(criterion, "needs_attributes", False):
        return criterion.rate_attributed(a, b, c, attributes)  # type: ignore[attr-defined]
    return criterion.rate(a, b, c)


def as_criterion(value: Criterion | Callable[[Point2, Point2, Point2], object]) -> Criterion:
    """A :class:`Criterion` as is; another callable ``test(a, b, c) -> bool`` as a
    :class:`CallableCriterion`."""
    if isinstance(value, Criterion):
        return value
    if callable(value):
        return CallableCriterion(value)
    raise TypeError(f"a criterion must be a Criterion or a callable, not {type(value).__name__}")
