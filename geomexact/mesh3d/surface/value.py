"""The triangulated surface value: exact points and triangles (vertex ids), immutable.

A surface bounds a domain when it is closed, 2-manifold, consistently oriented with its
normals pointing out (``a, b, c`` counter-clockwise seen from outside), free of
degenerate triangles and of self-intersections; the checks live in
:mod:`geomexact.mesh3d.surface.checks`.  This value holds any triangle soup: a reader
builds it, the checks judge it."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.digest import cell_hash, combine, digest_text, vertex_hash
from geomexact.kernel.numbers import ZERO, Rational
from geomexact.kernel.points import Point3, point3

__all__ = ["TriangleSurface", "triangle_surface"]


@attrs.frozen(slots=True, eq=False)
class TriangleSurface:
    """``points`` (exact, by id) and ``triangles`` (an (n, 3) read-only int64 array of
    vertex ids, each row's order its orientation); ``name``: where it came from (a file
    name, or empty)."""

    points: tuple[Point3, ...]
    triangles: Any
    name: str = ""

    @property
    def vertex_count(self) -> int:
        return len(self.points)

    @property
    def triangle_count(self) -> int:
        return int(self.triangles.shape[0])

    def triangle(self, index: int) -> tuple[Point3, Point3, Point3]:
        """The three points of triangle ``index``."""
        a, b, c = self.triangles[index].tolist()
        return self.points[a], self.points[b], self.points[c]

    def enclosed_volume(self) -> Rational:
        """The signed volume the triangles enclose, exactly: the sum over triangles of
        ``det(a, b, c) / 6`` (positive for a closed surface oriented outward)."""
        total = ZERO
        for a, b, c in self.triangles.tolist():
            p, q, r = self.points[a], self.points[b], self.points[c]
            total += (p.x * (q.y * r.z - q.z * r.y) - p.y * (q.x * r.z - q.z * r.x)
                      + p.z * (q.x * r.y - q.y * r.x))
        return total / 6  # type: ignore[no-any-return]

    def bounds(self) -> tuple[tuple[Rational, Rational, Rational],
                              tuple[Rational, Rational, Rational]]:
        """The exact bounding box of the points used by triangles: (low, high)."""
        used = np.unique(self.triangles).tolist()
        if not used:
            raise PreconditionError("bounds", f"the surface {self.name!r} has no triangle")
        low = [min(self.points[v][axis] for v in used) for axis in range(3)]
        high = [max(self.points[v][axis] for v in used) for axis in range(3)]
        return (low[0], low[1], low[2]), (high[0], high[1], high[2])

    def reversed(self) -> TriangleSurface:
        """The same surface with every triangle's orientation flipped."""
        flipped = np.ascontiguousarray(self.triangles[:, [0, 2, 1]])
        flipped.setflags(write=False)
        return TriangleSurface(self.points, flipped, self.name)

    @property
    def digest(self) -> int:
        """A content hash of the points and triangles (order of triangles ignored)."""
        value = 0
        for vertex, point in enumerate(self.points):
            value = combine(value, vertex_hash(vertex, point[:3]))
        for triangle in self.triangles.tolist():
            value = combine(value, cell_hash(triangle))
        return value

    @property
    def digest_text(self) -> str:
        return digest_text(self.digest)


def triangle_surface(points: Sequence[Point3 | Sequence[object]],
                     triangles: Any, name: str = "") -> TriangleSurface:
    """The surface of ``points`` (:class:`Point3` or coordinate triples, converted
    exactly) and ``triangles`` ((n, 3) vertex ids); :class:`PreconditionError` for an id
    out of range or a row that is not three ids."""
    exact = tuple(p if isinstance(p, Point3) else point3(*p) for p in points)
    array = np.array(triangles, dtype=np.int64).reshape(-1, 3) if len(triangles) else (
        np.zeros((0, 3), dtype=np.int64))
    if array.size and (array.min() < 0 or array.max() >= len(exact)):
        raise PreconditionError("triangle_surface", f"a triangle names a vertex outside "
                                f"0..{len(exact) - 1}")
    array.setflags(write=False)
    return TriangleSurface(exact, array, name)
