"""Planar straight-line graphs (PSLGs): the input of (constrained) Delaunay triangulation.

A :class:`PSLG` is an immutable value: exact vertices, segments between them (with boundary
markers), hole seed points and regional-attribute seed points, as in Triangle's ``.poly``
files.  A point set is a PSLG without segments.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2


@attrs.frozen(slots=True)
class RegionSeed:
    """A point inside a region, the regional attribute to give its triangles, and an
    optional maximum triangle area for that region (None: no constraint)."""

    point: Point2
    attribute: Rational
    max_area: Rational | None = None


# Typed converters: mypy cannot type attrs fields converted by the generic ``tuple``.
def _points(values: Iterable[Point2]) -> tuple[Point2, ...]:
    return tuple(values)


def _segments(values: Iterable[tuple[int, int, int]]) -> tuple[tuple[int, int, int], ...]:
    return tuple(values)


def _regions(values: Iterable[RegionSeed]) -> tuple[RegionSeed, ...]:
    return tuple(values)


def _markers(values: Iterable[int]) -> tuple[int, ...]:
    return tuple(values)


def _attributes(
    values: Iterable[tuple[Rational, ...]],
) -> tuple[tuple[Rational, ...], ...]:
    return tuple(values)


@attrs.frozen(slots=True)
class PSLG:
    """Vertices (ids = positions), segments ``(u, v, marker)`` with u != v, holes (seed
    points), regions (:class:`RegionSeed`), and per-vertex boundary markers and attribute
    tuples (empty tuples when the input has none)."""

    vertices: tuple[Point2, ...] = attrs.field(converter=_points)
    segments: tuple[tuple[int, int, int], ...] = attrs.field(converter=_segments, default=())
    holes: tuple[Point2, ...] = attrs.field(converter=_points, default=())
    regions: tuple[RegionSeed, ...] = attrs.field(converter=_regions, default=())
    vertex_markers: tuple[int, ...] = attrs.field(converter=_markers, default=())
    vertex_attributes: tuple[tuple[Rational, ...], ...] = attrs.field(
        converter=_attributes, default=()
    )

    def __attrs_post_init__(self) -> None:
        count = len(self.vertices)
        for index, (u, v, _) in enumerate(self.segments):
            if not (0 <= u < count and 0 <= v < count):
                raise PreconditionError(
                    "PSLG", f"segment #{index} ({u}, {v}) refers to a missing vertex"
                )
            if u == v:
                raise PreconditionError("PSLG", f"segment #{index} ({u}, {v}) has equal ends")
        for name, table in (
            ("vertex_markers", self.vertex_markers),
            ("vertex_attributes", self.vertex_attributes),
        ):
            if table and len(table) != count:
                raise PreconditionError(
                    "PSLG", f"{name} has {len(table)} entries for {count} vertices"
                )

    def marker(self, vertex: int) -> int:
        """Boundary marker of ``vertex`` (0 when the input has none)."""
        return self.vertex_markers[vertex] if self.vertex_markers else 0


def point_set(points: Sequence[Point2]) -> PSLG:
    """The PSLG of a bare point set."""
    return PSLG(vertices=tuple(points))
