"""Exact measures of tetrahedral meshes: volumes, and the Delaunay test of every interior
face (exact insphere)."""

from __future__ import annotations

from collections.abc import Iterator

from geomexact.kernel.numbers import ZERO, Rational
from geomexact.kernel.predicate_results import SphereLocation
from geomexact.kernel.predicates3d import insphere
from geomexact.mesh3d.snapshot import Face, Mesh3, Tetrahedron, opposite_face, signed_volume6

__all__ = ["interior_face_spheres", "is_delaunay3", "locally_non_delaunay_faces",
           "tetrahedron_volume", "total_volume"]


def tetrahedron_volume(mesh: Mesh3, tetrahedron: Tetrahedron) -> Rational:
    """The exact volume of a (positive) tetrahedron of ``mesh``."""
    return signed_volume6(*(mesh.point(v) for v in tetrahedron)) / 6


def total_volume(mesh: Mesh3) -> Rational:
    """The exact sum of the tetrahedra's volumes."""
    total = ZERO
    for tetrahedron in mesh.iter_tetrahedra():
        total += signed_volume6(*(mesh.point(v) for v in tetrahedron))
    return total / 6  # type: ignore[no-any-return]


def locally_non_delaunay_faces(mesh: Mesh3) -> list[Face]:
    """The interior faces (sorted vertex triples, sorted) whose opposite vertex lies
    strictly inside the circumsphere of the tetrahedron on the other side; cospherical
    ties are Delaunay."""
    bad: list[Face] = [
        tuple(sorted(face))  # type: ignore[misc]
        for face, _, _, location in interior_face_spheres(mesh)
        if location == SphereLocation.INSIDE
    ]
    return sorted(bad)


def interior_face_spheres(mesh: Mesh3) -> Iterator[tuple[Face, int, int, SphereLocation]]:
    """Each interior face of ``mesh`` once (as the smaller of its two orientations), as
    ``(face, apex, other, location)``: the apex of the tetrahedron on its positive side,
    the apex of the one across it, and where ``other`` lies with respect to the sphere
    through the face and ``apex`` (exact insphere)."""
    faces = mesh.faces
    for face, apex in faces.items():
        other = faces.get(opposite_face(face))
        if other is None or face > opposite_face(face):
            continue
        a, b, c = face
        yield face, apex, other, insphere(*(mesh.point(v) for v in (a, b, c, apex, other)))


def is_delaunay3(mesh: Mesh3) -> bool:
    """True when no interior face is locally non-Delaunay (exact)."""
    return not locally_non_delaunay_faces(mesh)
