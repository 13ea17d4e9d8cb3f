"""Polygon meshes (e.g. Polylla output): exact vertices and polygons as counter-clockwise
vertex cycles, optionally with the triangles each polygon was made of."""

from __future__ import annotations

from collections.abc import Iterable

import attrs

from geomexact.errors import PreconditionError
from geomexact.mesh2d import Triangle
from geomexact.points import Point2


# Typed converters: mypy cannot type attrs fields converted by the generic ``tuple``.
def _points(values: Iterable[Point2]) -> tuple[Point2, ...]:
    return tuple(values)


def _polygons(values: Iterable[tuple[int, ...]]) -> tuple[tuple[int, ...], ...]:
    return tuple(values)


def _sources(values: Iterable[tuple[Triangle, ...]]) -> tuple[tuple[Triangle, ...], ...]:
    return tuple(values)


@attrs.frozen(slots=True)
class PolygonMesh:
    """Vertices (ids = positions) and polygons (tuples of at least 3 vertex ids);
    ``sources[i]`` lists the triangles polygon i came from (empty when unknown)."""

    vertices: tuple[Point2, ...] = attrs.field(converter=_points)
    polygons: tuple[tuple[int, ...], ...] = attrs.field(converter=_polygons)
    sources: tuple[tuple[Triangle, ...], ...] = attrs.field(converter=_sources, default=())

    def __attrs_post_init__(self) -> None:
        count = len(self.vertices)
        for index, polygon in enumerate(self.polygons):
            if len(polygon) < 3:
                raise PreconditionError(
                    "PolygonMesh", f"polygon #{index} has {len(polygon)} vertices (< 3)"
                )
            for vertex in polygon:
                if not 0 <= vertex < count:
                    raise PreconditionError(
                        "PolygonMesh", f"polygon #{index} refers to missing vertex {vertex}"
                    )
        if self.sources and len(self.sources) != len(self.polygons):
            raise PreconditionError("PolygonMesh", "one source list per polygon is needed")
