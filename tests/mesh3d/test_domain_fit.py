"""The octree's fit to a closed surface (issue 24, item 3): exact sides and cut points,
pieces valid by exact orient3d and by an independent check in plain ``fractions``,
every boundary vertex exactly on the surface, the volume converging to the enclosed
volume, on hand-made surfaces and on the real spot and fandisk."""

from __future__ import annotations

import random
from collections import Counter
from fractions import Fraction

import numpy as np
import pytest
from helpers.paths import SHARED_DATA
from helpers.surface_cases import notched_box, octahedron

from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point3
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.octree.domain_fit import fit_to_surface
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.stages import RefineWhere
from geomexact.mesh3d.surface.queries import INSIDE, ON, OUTSIDE, surface_index
from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface
from geomexact.mesh3d.validation import validate3

SURFACES = SHARED_DATA / "surfaces"


def _domain_box(surface: TriangleSurface) -> Box:
    low, high = surface.bounds()
    side = max(h - lo for lo, h in zip(low, high, strict=True))
    size = mpq(1)
    while size < side * mpq(5, 4):
        size *= 2
    start = tuple(mpq(int((lo + h) / 2 * 16 - size * 8), 16)
                  for lo, h in zip(low, high, strict=True))
    return Box(start, tuple(s + size for s in start))


def fit(surface: TriangleSurface, level: int) -> tuple[object, object]:
    index = surface_index(surface)
    run = generate(_domain_box(surface), trace=False, refinement=RefineWhere(
        level, region=lambda box: index.meets_box(box.low, box.high)))
    return fit_to_surface(run.leaf_mesh.lattice.exact_points(), run.leaf_mesh.tetrahedra,
                          index), index


def _fraction(value: object) -> Fraction:
    return Fraction(int(value.numerator), int(value.denominator))  # type: ignore[attr-defined]


def independent_problems(mesh: object, surface: TriangleSurface) -> list[str]:
    """Plain fractions: every tetrahedron positive; every face in one or two
    tetrahedra, opposite; every boundary face's vertices on a triangle of the surface."""
    points = {v: tuple(_fraction(c) for c in p[:3])
              for v, p in mesh.vertices.items()}  # type: ignore[attr-defined]
    tris = [tuple(tuple(_fraction(c) for c in surface.points[v][:3]) for v in row)
            for row in surface.triangles.tolist()]

    def sub(p: tuple[Fraction, ...], q: tuple[Fraction, ...]) -> tuple[Fraction, ...]:
        return tuple(a - b for a, b in zip(p, q, strict=True))

    def det(a: tuple[Fraction, ...], b: tuple[Fraction, ...], c: tuple[Fraction, ...],
            d: tuple[Fraction, ...]) -> Fraction:
        u, v, w = sub(b, a), sub(c, a), sub(d, a)
        return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))

    def on_surface(p: tuple[Fraction, ...]) -> bool:
        for a, b, c in tris:
            if det(a, b, c, p) != 0:
                continue
            n = [abs(x) for x in (sub(b, a)[1] * sub(c, a)[2] - sub(b, a)[2] * sub(c, a)[1],
                                  sub(b, a)[2] * sub(c, a)[0] - sub(b, a)[0] * sub(c, a)[2],
                                  sub(b, a)[0] * sub(c, a)[1] - sub(b, a)[1] * sub(c, a)[0])]
            k = [i for i in range(3) if i != n.index(max(n))]

            def side(u: tuple[Fraction, ...], v: tuple[Fraction, ...],
                     k: list[int] = k) -> int:
                value = ((v[k[0]] - u[k[0]]) * (p[k[1]] - u[k[1]])
                         - (v[k[1]] - u[k[1]]) * (p[k[0]] - u[k[0]]))
                return (value > 0) - (value < 0)

            if len({side(a, b), side(b, c), side(c, a)} - {0}) <= 1:
                return True
        return False

    problems = []
    faces: Counter[tuple[int, ...]] = Counter()
    for tet in mesh.tetrahedra():  # type: ignore[attr-defined]
        a, b, c, d = (points[v] for v in tet)
        if det(a, b, c, d) <= 0:
            problems.append(f"tetrahedron {tet} not positive")
        for face in ((tet[1], tet[2], tet[3]), (tet[0], tet[3], tet[2]),
                     (tet[0], tet[1], tet[3]), (tet[0], tet[2], tet[1])):
            start = face.index(min(face))
            faces[face[start:] + face[:start]] += 1
    boundary_vertices = set()
    for face, times in faces.items():
        if times > 1:
            problems.append(f"face {face} on one side of two tetrahedra")
        reverse = (face[0], face[2], face[1])
        if reverse not in faces:
            boundary_vertices.update(face)
    problems += [f"boundary vertex {v} is not on the surface"
                 for v in sorted(boundary_vertices) if not on_surface(points[v])]
    return problems


@pytest.mark.parametrize("make", [octahedron, notched_box], ids=["octahedron", "notched"])
def test_the_fit_is_valid_and_its_boundary_is_on_the_surface(make: object) -> None:
    surface = make()  # type: ignore[operator]
    errors = []
    for level in (2, 3, 4):
        result, _ = fit(surface, level)
        mesh = result.mesh  # type: ignore[attr-defined]
        assert result.unfit == () and validate3(mesh) == []  # type: ignore[attr-defined]
        assert independent_problems(mesh, surface) == []
        boundary = {v for face in mesh.boundary_faces() for v in face}
        assert boundary <= set(result.surface_vertices)  # type: ignore[attr-defined]
        errors.append(abs(total_volume(mesh) - surface.enclosed_volume()))
    # a polyhedron's faces are met exactly wherever a piece lies within one face
    assert errors[0] >= errors[1] >= errors[2]


def test_a_convex_surface_is_met_from_inside() -> None:
    """Over a convex surface the chords stay inside: the mesh's volume is at most the
    enclosed volume, and the octahedron's is reached exactly once the lattice holds its
    vertices and edges (its faces are lattice-aligned diagonals)."""
    surface = octahedron(mpq(1, 2), mpq(1, 2))
    for level in (2, 3, 4):
        result, _ = fit(surface, level)
        assert total_volume(result.mesh) <= surface.enclosed_volume()  # type: ignore[attr-defined]


def test_sides_agree_with_brute_force_rays() -> None:
    surface = notched_box()
    result, index = fit(surface, 3)
    rng = random.Random(4)
    brute = {INSIDE: 0, OUTSIDE: 0, ON: 0}
    for _ in range(200):
        p = point3(*(mpq(rng.randint(0, 64), 64) for _ in range(3)))
        brute[index.side(p)] += 1  # type: ignore[attr-defined]
    assert brute[INSIDE] > 0 and brute[OUTSIDE] > 0
    assert set(np.unique(result.sides).tolist()) <= {INSIDE, ON, OUTSIDE}  # type: ignore[attr-defined]


def test_segment_hits_are_exact_points_of_the_surface() -> None:
    index = surface_index(octahedron())
    p, q = point3(mpq(1, 2), mpq(1, 2), mpq(1, 2)), point3(2, mpq(3, 5), mpq(11, 20))
    (hit,) = index.segment_hits(p, q)
    # on the face x + y + z = 3/2 + 7/10: t (3/2 + 1/10 + 1/20) = 7/10
    assert hit.proper and hit.t == mpq(7, 10) / mpq(33, 20)
    at = point3(*(p[i] + hit.t * (q[i] - p[i]) for i in range(3)))
    assert index.on_surface(at) and index.side(at) == ON
    # through a vertex of the octahedron: touching hits, not proper ones
    far = point3(2, mpq(1, 2), mpq(1, 2))
    assert {hit.proper for hit in index.segment_hits(p, far)} == {False}
    # along a face's plane: the first point of the triangle along the segment
    a, b, c = index.surface.triangle(0)
    inside = point3(*((a[i] + b[i] + c[i]) / 3 for i in range(3)))
    assert index.on_surface(inside) and index.side(inside) == ON
    beyond = point3(*(2 * inside[i] - a[i] for i in range(3)))
    hits = index.segment_hits(a, beyond)
    assert hits and hits[0].t == 0 and not hits[0].proper


@pytest.mark.skipif(not SURFACES.is_dir(), reason="../shared/data/surfaces is absent")
@pytest.mark.parametrize("name", ["spot", "fandisk"])
def test_real_surfaces_fit_with_falling_volume_error(name: str) -> None:
    from fractions import Fraction as F

    points, triangles = [], []
    for line in (SURFACES / f"{name}.obj").read_text().splitlines():
        if line.startswith("v "):
            points.append(tuple(F(x) for x in line.split()[1:4]))
        elif line.startswith("f "):
            triangles.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    surface = triangle_surface(points, triangles, name)
    enclosed = surface.enclosed_volume()
    errors = []
    for level in (3, 4, 5):
        result, index = fit(surface, level)
        mesh = result.mesh  # type: ignore[attr-defined]
        assert result.unfit == () and validate3(mesh) == []  # type: ignore[attr-defined]
        on = result.surface_vertices  # type: ignore[attr-defined]
        assert all(index.on_surface(mesh.point(v)) for v in on)  # type: ignore[attr-defined]
        assert {v for face in mesh.boundary_faces() for v in face} <= set(on)
        errors.append(abs(float((total_volume(mesh) - enclosed) / enclosed)))
    assert errors[0] > errors[1] > errors[2] and errors[2] < 0.1


@pytest.mark.skipif(not SURFACES.is_dir(), reason="../shared/data/surfaces is absent")
def test_warping_removes_the_slivers_of_cut_points_next_to_vertices() -> None:
    from fractions import Fraction as F

    from geomexact.mesh3d.quality import quality_summary

    points, triangles = [], []
    for line in (SURFACES / "spot.obj").read_text().splitlines():
        if line.startswith("v "):
            points.append(tuple(F(x) for x in line.split()[1:4]))
        elif line.startswith("f "):
            triangles.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    surface = triangle_surface(points, triangles, "spot")
    index = surface_index(surface)
    run = generate(_domain_box(surface), trace=False, refinement=RefineWhere(
        5, region=lambda box: index.meets_box(box.low, box.high)))
    lattice_points = run.leaf_mesh.lattice.exact_points()

    def angles(result: object) -> float:
        mesh = result.mesh  # type: ignore[attr-defined]
        xyz = np.array([[p.fx, p.fy, p.fz] for p in mesh.point_list()])
        return float(quality_summary(xyz, np.array(mesh.tetrahedra())).min_dihedral)

    plain = fit_to_surface(lattice_points, run.leaf_mesh.tetrahedra, index, warp=None)
    warped = fit_to_surface(lattice_points, run.leaf_mesh.tetrahedra, index)
    assert plain.warped == 0 and warped.warped > 0 and warped.pinches == ()
    assert validate3(warped.mesh) == []
    assert angles(plain) < 1 < 10 < angles(warped)
    on = set(warped.surface_vertices)
    assert all(index.on_surface(warped.mesh.point(v)) for v in on)


@pytest.mark.skipif(not SURFACES.is_dir(), reason="../shared/data/surfaces is absent")
def test_refinement_by_the_local_feature_of_the_surface() -> None:
    """Leaves where the surface is flat stay coarse: fewer leaves for about the same
    volume error (fandisk: 14,554 leaves at level 6, 8,590 with a 20° feature angle)."""
    from geomexact.io.surface_files import read_surface
    from geomexact.mesh3d.octree.domain import generate_domain
    from geomexact.mesh3d.surface.checks import oriented_outward

    fandisk = oriented_outward(read_surface(SURFACES / "fandisk.obj"))[0]
    everywhere = generate_domain([fandisk], level=5, interior_level=2)
    featured = generate_domain([fandisk], level=5, interior_level=2, feature_angle=20.0)
    assert featured.octree.leaf_count < 0.9 * everywhere.octree.leaf_count  # 2,528 of 3,109
    assert validate3(featured.mesh) == []
    error = abs(total_volume(featured.mesh) - featured.enclosed_volume)
    assert error < 2 * abs(total_volume(everywhere.mesh) - everywhere.enclosed_volume)
