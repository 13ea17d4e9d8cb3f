"""Regions of the plane that restrict a refinement to part of a mesh.

A :class:`Region` answers one exact question, ``contains(point)``; points on the region's
border count as inside.  A triangle is *in* a region when at least one of its vertices is
(``specs/refine.md``), so a region smaller than a triangle that holds none of its vertices
selects nothing.  Regions are frozen values; ``parameters()`` describes one as JSON for a
trace header.

>>> from geomexact.kernel.points import point2
>>> Circle(0, 0, 1).contains(point2("0.6", "0.8"))  # on the circle: inside
True
>>> Rectangle(0, 0, 2, 1).contains(point2(3, 0))
False
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any, Protocol, runtime_checkable

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, format_rational, to_rational
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.segments import within_box

__all__ = [
    "CallableRegion",
    "Circle",
    "Polygon",
    "Rectangle",
    "Region",
    "Whole",
    "as_region",
]


@runtime_checkable
class Region(Protocol):
    """A part of the plane: ``contains`` is exact and counts the border as inside."""

    def contains(self, point: Point2, /) -> bool:
        """True when ``point`` is inside the region or on its border."""
        ...

    def parameters(self) -> dict[str, Any]:
        """A JSON description (kind and exact parameters as text)."""
        ...


@attrs.frozen(slots=True)
class Whole:
    """The whole plane: every triangle is in it."""

    def contains(self, point: Point2, /) -> bool:
        """Always True."""
        return True

    def parameters(self) -> dict[str, Any]:
        """``{"kind": "whole"}``."""
        return {"kind": "whole"}


def _rational(value: object) -> Rational:
    return to_rational(value)


@attrs.frozen(slots=True)
class Circle:
    """The closed disk of ``radius`` (> 0) around (``center_x``, ``center_y``); values
    are read exactly (``"0.1"`` is 1/10)."""

    center_x: Rational = attrs.field(converter=_rational)
    center_y: Rational = attrs.field(converter=_rational)
    radius: Rational = attrs.field(converter=_rational)
    _radius_squared: Rational = attrs.field(init=False, repr=False, eq=False)

    def __attrs_post_init__(self) -> None:
        if not self.radius > 0:
            raise PreconditionError(
                "Circle", f"the radius must be positive, not {format_rational(self.radius)}"
            )
        object.__setattr__(self, "_radius_squared", self.radius * self.radius)

    def contains(self, point: Point2, /) -> bool:
        """(x - cx)² + (y - cy)² <= r², exactly."""
        dx = point[0] - self.center_x
        dy = point[1] - self.center_y
        return bool(dx * dx + dy * dy <= self._radius_squared)

    def parameters(self) -> dict[str, Any]:
        """Kind, centre and radius (exact text)."""
        return {
            "kind": "circle",
            "center": [format_rational(self.center_x), format_rational(self.center_y)],
            "radius": format_rational(self.radius),
        }


@attrs.frozen(slots=True)
class Rectangle:
    """The closed axis-parallel rectangle [x, x + width] × [y, y + height] (width and
    height > 0)."""

    x: Rational = attrs.field(converter=_rational)
    y: Rational = attrs.field(converter=_rational)
    width: Rational = attrs.field(converter=_rational)
    height: Rational = attrs.field(converter=_rational)

    def __attrs_post_init__(self) -> None:
        if not (self.width > 0 and self.height > 0):
            raise PreconditionError(
                "Rectangle",
                f"width and height must be positive, not {format_rational(self.width)} and "
                f"{format_rational(self.height)}",
            )

    def contains(self, point: Point2, /) -> bool:
        """x <= px <= x + width and y <= py <= y + height, exactly."""
        px, py = point[0], point[1]
        return bool(
            self.x <= px <= self.x + self.width and self.y <= py <= self.y + self.height
        )

    def parameters(self) -> dict[str, Any]:
        """Kind, corner, width and height (exact text)."""
        return {
            "kind": "rectangle",
            "corner": [format_rational(self.x), format_rational(self.y)],
            "width": format_rational(self.width),
            "height": format_rational(self.height),
        }


def _polygon_points(values: Iterable[Point2 | Sequence[object]]) -> tuple[Point2, ...]:
    return tuple(v if isinstance(v, Point2) else point2(v[0], v[1]) for v in values)


@attrs.frozen(slots=True)
class Polygon:
    """The closed region bounded by the polygon through ``vertices`` (points or
    coordinate pairs, in either orientation; the last vertex joins the first).

    Membership follows the even-odd rule (a simple polygon's interior; for a
    self-intersecting one, the points enclosed an odd number of times), and every point on
    an edge is inside.  Exact: orientation tests only, no division.  O(n) per point.
    """

    vertices: tuple[Point2, ...] = attrs.field(converter=_polygon_points)
    _box: tuple[Rational, Rational, Rational, Rational] = attrs.field(
        init=False, repr=False, eq=False
    )

    def __attrs_post_init__(self) -> None:
        distinct = set(self.vertices)
        if len(distinct) < 3:
            raise PreconditionError(
                "Polygon", f"a polygon needs at least 3 distinct vertices, got {len(distinct)}"
            )
        first = self.vertices[0]
        if all(
            orient2d(first, p, q) == Orientation.COLLINEAR
            for p, q in zip(self.vertices[1:], self.vertices[2:], strict=False)
        ):
            raise PreconditionError("Polygon", "the polygon's vertices are all collinear")
        xs = [p.x for p in self.vertices]
        ys = [p.y for p in self.vertices]
        object.__setattr__(self, "_box", (min(xs), min(ys), max(xs), max(ys)))

    def contains(self, point: Point2, /) -> bool:
        """True inside (even-odd rule) or on an edge."""
        x_min, y_min, x_max, y_max = self._box
        px, py = point[0], point[1]
        if px < x_min or px > x_max or py < y_min or py > y_max:
            return False
        vertices = self.vertices
        inside = False
        previous = vertices[-1]
        for current in vertices:
            side = orient2d(previous, current, point)
            if side == Orientation.COLLINEAR and within_box(point, previous, current):
                return True
            upward = current[1] > py
            if (previous[1] > py) != upward and (side == Orientation.COUNTERCLOCKWISE) == (
                current[1] > previous[1]
            ):
                # the edge crosses the horizontal line through the point, right of it
                inside = not inside
            previous = current
        return inside

    def parameters(self) -> dict[str, Any]:
        """Kind and vertices (exact text)."""
        return {
            "kind": "polygon",
            "vertices": [[format_rational(p.x), format_rational(p.y)] for p in self.vertices],
        }


@attrs.frozen(slots=True)
class CallableRegion:
    """A region given by a function ``contains(point) -> bool`` (it should be exact and
    deterministic: it decides what is refined)."""

    function: Callable[[Point2], object]
    name: str = ""

    def contains(self, point: Point2, /) -> bool:
        """``bool(function(point))``."""
        return bool(self.function(point))

    def parameters(self) -> dict[str, Any]:
        """Kind and the function's name."""
        name = self.name or getattr(self.function, "__qualname__", repr(self.function))
        return {"kind": "callable", "name": name}


def as_region(value: Region | Callable[[Point2], object] | None) -> Region:
    """``None`` -> :class:`Whole`; a :class:`Region` as is; another callable ->
    :class:`CallableRegion`."""
    if value is None:
        return Whole()
    if isinstance(value, Region):
        return value
    if callable(value):
        return CallableRegion(value)
    raise TypeError(f"a region must be a Region or a callable, not {type(value).__name__}")
