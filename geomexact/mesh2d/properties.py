"""Properties of a triangle mesh as yes/no predicates, each decided exactly: the checks
``geomexact trace bisect --fails`` searches a trace for (with
:func:`~geomexact.mesh2d.delaunay.triangulation.is_delaunay`).

>>> from geomexact.mesh2d.transient import mesh_from_triangles
>>> square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
>>> is_valid(square), has_min_angle(square, 45), has_min_angle(square, "45.5")
(True, True, False)
>>> has_area(square, 1)
True
"""

from __future__ import annotations

from geomexact.kernel.numbers import Rational
from geomexact.mesh2d.measures import total_area
from geomexact.mesh2d.refinement.criteria import MinAngle
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.validation import validate

__all__ = ["has_area", "has_min_angle", "is_valid"]


def is_valid(mesh: Mesh2) -> bool:
    """True when :func:`~geomexact.mesh2d.validation.validate` finds no violation.
    O(n)."""
    return len(validate(mesh)) == 0


def has_min_angle(mesh: Mesh2, degrees: Rational | int | str) -> bool:
    """True when every triangle's smallest angle is at least ``degrees`` (0 < θ < 60),
    decided as :class:`~geomexact.mesh2d.refinement.criteria.MinAngle` decides it: exactly
    for 30° and 45°, else against a rational bound that never accepts an angle below θ.
    O(n)."""
    criterion = MinAngle(degrees)
    point = mesh.point
    return all(criterion.rate(point(a), point(b), point(c)) is None
               for a, b, c in mesh.iter_triangles())


def has_area(mesh: Mesh2, area: Rational) -> bool:
    """True when the triangles' areas sum exactly to ``area``.  O(n)."""
    return bool(total_area(mesh) == area)
