"""Polyhedral Delaunay cells: the tetrahedra of a Delaunay tetrahedralization grouped by
their common empty sphere, decided exactly (Contreras and Hitschfeld-Kahler, "Generation
of polyhedral Delaunay meshes", IMR23, Procedia Engineering 82, 2014, who decided
co-sphericity in floating point).

Two tetrahedra sharing a face belong to one cell when the vertex of either opposite the
face lies exactly on the other's circumsphere (``insphere`` is zero); the cells are the
connected groups of that relation.  In a Delaunay tetrahedralization each group is the
set of tetrahedra of one Delaunay cell, the convex hull of co-spherical points (the
whole cube when its eight corners are its only points), so the cells do not depend on
how the tetrahedralization cut the co-spherical groups."""

from __future__ import annotations

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.components import component_labels
from geomexact.kernel.predicate_results import SphereLocation
from geomexact.mesh3d.measures import interior_face_spheres
from geomexact.mesh3d.snapshot import Mesh3, Tetrahedron, canonical_tetrahedron

__all__ = ["PolyhedralCell", "polyhedral_cells"]


@attrs.frozen(slots=True)
class PolyhedralCell:
    """One polyhedral Delaunay cell: its ``vertices`` (sorted ids) and the
    ``tetrahedra`` of the tetrahedralization that it groups (sorted)."""

    vertices: tuple[int, ...]
    tetrahedra: tuple[Tetrahedron, ...]

    @property
    def is_tetrahedron(self) -> bool:
        return len(self.tetrahedra) == 1


def polyhedral_cells(mesh: Mesh3) -> tuple[PolyhedralCell, ...]:
    """The polyhedral Delaunay cells of ``mesh`` (module docstring), sorted by their
    first tetrahedron; :class:`PreconditionError` when the exact check finds the mesh
    not Delaunay (its co-spherical groups would not be cells)."""
    tetrahedra = sorted(mesh.iter_tetrahedra())
    index = {tetrahedron: n for n, tetrahedron in enumerate(tetrahedra)}
    first: list[int] = []
    second: list[int] = []
    # one insphere per interior face: Delaunay and groups
    for (a, b, c), apex, other, location in interior_face_spheres(mesh):
        if location == SphereLocation.INSIDE:
            raise PreconditionError("polyhedral_cells", "the mesh is not Delaunay: group "
                                    "its co-spherical tetrahedra after making it Delaunay")
        if location == SphereLocation.COSPHERICAL:
            first.append(index[canonical_tetrahedron(a, b, c, apex)])
            second.append(index[canonical_tetrahedron(a, c, b, other)])
    labels = component_labels(len(tetrahedra), np.array(first, dtype=np.int64),
                              np.array(second, dtype=np.int64)).tolist()
    groups: dict[int, list[Tetrahedron]] = {}
    for label, tetrahedron in zip(labels, tetrahedra, strict=True):
        groups.setdefault(label, []).append(tetrahedron)
    return tuple(
        PolyhedralCell(tuple(sorted({v for t in members for v in t})), tuple(members))
        for _, members in sorted(groups.items()))

