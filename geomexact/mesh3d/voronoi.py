"""Voronoi control volumes of a Delaunay tetrahedral mesh, for the finite-volume method
(Arancibia 2007, ``Assemble_Voronoi_Surfaces``; Contreras and Hitschfeld-Kahler, IMR23,
2014, on the cells "not adequate for the finite-volume method").

Each tetrahedron is cut into four vertex regions by its circumcentre, the circumcentres of
its faces and the midpoints of its edges: the piece of the dual (Voronoi) face of an edge
``uv`` inside the tetrahedron is the quadrilateral (edge midpoint, circumcentre of one
face through ``uv``, circumcentre of the tetrahedron, circumcentre of the other face).
Summed over the tetrahedra around an edge, these pieces are the edge's Voronoi face, and
around a boundary edge they close on the boundary: the Voronoi cells clipped to the
domain.  Everything is exact:

- the area vector of each Voronoi face (half the sum of cross products of rational
  points), oriented from the edge's smaller vertex to its larger one;
- the coupling ``|A| / |e| = (e . A) / (e . e)`` of each edge (the face is perpendicular
  to its edge, so ``e . A = |e| |A|`` up to its sign);
- each vertex's control volume ``V_u = sum over its edges of (e . A) / 6`` (the pyramids
  from the vertex over its dual faces; the domain's boundary faces through the vertex add
  nothing), and their sum, which equals the mesh's volume exactly.

Only the faces' areas ``|A|`` and the edges' lengths are square roots: given as doubles
(the nearest double of the exact square).  A face whose area vector points against its
edge (``e . A < 0``: circumcentres on the wrong side, the papers' inadequate elements) is
flagged; a face of zero area (co-spherical vertices around the edge) is not.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from types import MappingProxyType

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, mpq, to_float
from geomexact.kernel.points import Point3
from geomexact.mesh3d.measures import is_delaunay3
from geomexact.mesh3d.mixed.conversion import to_tetrahedral
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Edge, Mesh3

__all__ = ["ControlVolumes", "VoronoiFace", "control_volumes", "voronoi_faces"]

Vector = tuple[Rational, Rational, Rational]


@attrs.frozen(slots=True)
class VoronoiFace:
    """The Voronoi face dual to ``edge`` (``u < v``): its exact ``area_vector`` (oriented
    from ``u`` to ``v``) and the exact edge vector ``v - u``."""

    edge: Edge
    area_vector: Vector
    edge_vector: Vector

    @property
    def flux(self) -> Rational:
        """``e . A``, exact: ``|e| |A|`` for a face on the right side, negative for one
        on the wrong side."""
        return _dot(self.edge_vector, self.area_vector)

    @property
    def coupling(self) -> Rational:
        """``(e . A) / (e . e)``, exact: the face's area over the edge's length, the
        weight of the edge in the finite-volume Laplacian."""
        return self.flux / _dot(self.edge_vector, self.edge_vector)  # type: ignore[no-any-return]

    @property
    def area(self) -> float:
        """``|A|``, the nearest double of the square root of the exact ``A . A``."""
        return math.sqrt(to_float(_dot(self.area_vector, self.area_vector)))

    @property
    def adequate(self) -> bool:
        """False when the face points against its edge (``e . A < 0``)."""
        return bool(self.flux >= 0)


@attrs.frozen(slots=True)
class ControlVolumes:
    """A Delaunay mesh's Voronoi control volumes: ``volumes[u]`` the exact volume of
    vertex ``u``'s cell clipped to the domain, ``faces`` the Voronoi face of every edge
    (sorted by edge)."""

    volumes: Mapping[int, Rational]
    faces: tuple[VoronoiFace, ...]

    @property
    def total(self) -> Rational:
        """The sum of the control volumes (exactly the mesh's volume)."""
        total = ZERO
        for volume in self.volumes.values():
            total += volume
        return total

    def inadequate_edges(self) -> list[Edge]:
        """The edges whose Voronoi face points against them, sorted."""
        return [face.edge for face in self.faces if not face.adequate]


def _sub(p: Sequence[Rational], q: Sequence[Rational]) -> Vector:
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def _dot(p: Sequence[Rational], q: Sequence[Rational]) -> Rational:
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]  # type: ignore[no-any-return]


def _cross(p: Sequence[Rational], q: Sequence[Rational]) -> Vector:
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def tetrahedron_circumcentre(a: Point3, b: Point3, c: Point3, d: Point3) -> Vector:
    """The exact centre of the sphere through a, b, c, d (not coplanar)."""
    u, v, w = _sub(b, a), _sub(c, a), _sub(d, a)
    uu, vv, ww = _dot(u, u), _dot(v, v), _dot(w, w)
    vw, wu, uv = _cross(v, w), _cross(w, u), _cross(u, v)
    denominator = 2 * _dot(u, vw)
    return tuple(  # type: ignore[return-value]
        a[k] + (uu * vw[k] + vv * wu[k] + ww * uv[k]) / denominator for k in range(3))


def triangle_circumcentre(a: Point3, b: Point3, c: Point3) -> Vector:
    """The exact centre of the circle through a, b, c (not collinear), in their plane."""
    v, w = _sub(b, a), _sub(c, a)
    normal = _cross(v, w)
    numerator = _cross(tuple(_dot(v, v) * w[k] - _dot(w, w) * v[k] for k in range(3)), normal)
    denominator = 2 * _dot(normal, normal)
    return tuple(a[k] + numerator[k] / denominator for k in range(3))  # type: ignore[return-value]


# the edges of a positive tetrahedron (a, b, c, d) as (i, j, k, l): (i, j, k, l) an even
# permutation of (a, b, c, d), so that the quadrilateral (midpoint of ij, c_ijk, c, c_ijl) turns
# positively about the direction from i to j (checked on a regular tetrahedron)
_EDGE_ORDERS = ((0, 1, 2, 3), (0, 2, 3, 1), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 2, 0),
                (2, 3, 0, 1))


def voronoi_faces(mesh: Mesh3) -> dict[Edge, Vector]:
    """The exact area vector of the Voronoi face (clipped to the domain) of every edge
    ``(u, v)``, ``u < v``, oriented from ``u`` to ``v`` (module docstring).  The mesh
    need not be Delaunay here: on a non-Delaunay mesh these are the faces of the
    circumcentric dual, not of a Voronoi diagram."""
    face_centres: dict[tuple[int, int, int], Vector] = {}

    def face_centre(i: int, j: int, k: int) -> Vector:
        key = tuple(sorted((i, j, k)))
        centre = face_centres.get(key)  # type: ignore[arg-type]
        if centre is None:
            centre = triangle_circumcentre(mesh.point(i), mesh.point(j), mesh.point(k))
            face_centres[key] = centre  # type: ignore[index]
        return centre

    half = mpq(1, 2)
    areas: dict[Edge, Vector] = {}
    for tetrahedron in mesh.iter_tetrahedra():
        points = [mesh.point(vertex) for vertex in tetrahedron]
        centre = tetrahedron_circumcentre(*points)
        for order in _EDGE_ORDERS:
            i, j, k, m = (tetrahedron[index] for index in order)
            pi, pj = points[order[0]], points[order[1]]
            middle = tuple((pi[n] + pj[n]) * half for n in range(3))
            piece = _cross(_sub(centre, middle), _sub(face_centre(i, j, m), face_centre(i, j, k)))
            if i > j:
                i, j = j, i
                piece = (-piece[0], -piece[1], -piece[2])
            previous = areas.get((i, j))
            areas[(i, j)] = piece if previous is None else (
                previous[0] + piece[0], previous[1] + piece[1], previous[2] + piece[2])
    return {edge: (a * half, b * half, c * half) for edge, (a, b, c) in sorted(areas.items())}


def control_volumes(mesh: Mesh3 | MixedMesh3, *,
                    require_delaunay: bool = True) -> ControlVolumes:
    """The Voronoi control volumes of ``mesh`` (module docstring).  A mesh that the exact
    check finds not Delaunay is refused (:class:`PreconditionError`) unless
    ``require_delaunay`` is False; the volumes then belong to the circumcentric dual and
    still sum to the mesh's volume.

    A mixed mesh (a polyhedral Delaunay mesh: its cells inscribed in empty spheres) is
    cut into tetrahedra first (:func:`~geomexact.mesh3d.mixed.conversion.to_tetrahedral`:
    any cut of a co-spherical cell is Delaunay, with that cell's circumcentre); the
    faces of the cut's new edges (diagonals of its faces and cells) have zero area and
    are left out, so every face is dual to an edge of ``mesh``."""
    if isinstance(mesh, MixedMesh3):
        return _mixed_control_volumes(mesh, require_delaunay)
    if require_delaunay and not is_delaunay3(mesh):
        raise PreconditionError(
            "control_volumes", "the mesh is not Delaunay (an interior face fails the exact "
            "insphere test): its circumcentric dual is not a Voronoi diagram")
    volumes: dict[int, Rational] = {vertex: ZERO for vertex in sorted(mesh.vertices)}
    sixth = mpq(1, 6)
    faces = []
    for edge, area in voronoi_faces(mesh).items():
        u, v = edge
        face = VoronoiFace(edge, area, _sub(mesh.point(v), mesh.point(u)))
        share = face.flux * sixth
        volumes[u] += share
        volumes[v] += share
        faces.append(face)
    return ControlVolumes(MappingProxyType(volumes), tuple(faces))


def _mixed_control_volumes(mesh: MixedMesh3, require_delaunay: bool) -> ControlVolumes:
    cut = control_volumes(to_tetrahedral(mesh), require_delaunay=require_delaunay)
    edges = {(min(u, v), max(u, v)) for cell in mesh.cell_list() for face in cell.faces
             for u, v in zip(face, (*face[1:], face[0]), strict=True)}
    kept = tuple(face for face in cut.faces if face.edge in edges or any(face.area_vector))
    return ControlVolumes(cut.volumes, kept)
