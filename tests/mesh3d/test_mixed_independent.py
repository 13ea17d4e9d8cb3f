"""An independent check of ``validate_mixed``: planarity, face and cell convexity, cell
volumes, face matching and the total volume recomputed with ``fractions.Fraction`` only
(no geomexact geometry), on a few hundred random meshes (box grids, random splits and
merges, then sometimes a moved vertex, an inverted cell or a dropped cell), agreeing with
the checker cell by cell."""

from __future__ import annotations

import random
from collections import Counter
from fractions import Fraction

import pytest
from helpers.mixed_cases import random_grid, random_walk

from geomexact.mesh3d.mixed.cells import cell_of_faces
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed

Vec = tuple[Fraction, Fraction, Fraction]
CELL_KINDS = ("cell-surface", "coincident-vertices", "non-planar-face", "non-convex-face",
              "non-positive-volume", "non-convex-cell")


def sub(a: Vec, b: Vec) -> Vec:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(u: Vec, v: Vec) -> Vec:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def dot(u: Vec, v: Vec) -> Fraction:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def newell(poly: list[Vec]) -> Vec:
    """Twice the vector area of a polygon (exact, Newell's sums)."""
    total = (Fraction(0), Fraction(0), Fraction(0))
    for i, p in enumerate(poly):
        q = poly[(i + 1) % len(poly)]
        c = cross(p, q)
        total = (total[0] + c[0], total[1] + c[1], total[2] + c[2])
    return total


def first_problem(faces: tuple[tuple[int, ...], ...], points: dict[int, Vec]) -> set[str]:
    """The first failed cell check (for faces: every face's), in validate_mixed's order,
    recomputed independently."""
    edges = Counter((f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f)))
    vertices = {v for f in faces for v in f}
    if any(n != 1 or edges[(v, u)] != 1 for (u, v), n in edges.items()) or \
            len(vertices) - len(edges) // 2 + len(faces) != 2:
        return {"cell-surface"}
    if len({points[v] for v in vertices}) != len(vertices):
        return {"coincident-vertices"}
    problems = set()
    for face in faces:
        poly = [points[v] for v in face]
        normal = newell(poly)
        # planar: every vertex at the same height along any normal of three of them
        triples = [cross(sub(poly[j], poly[0]), sub(poly[k], poly[0]))
                   for j in range(1, len(poly)) for k in range(j + 1, len(poly))]
        some = next((t for t in triples if any(t)), None)
        if some is not None and any(dot(some, sub(p, poly[0])) != 0 for p in poly):
            problems.add("non-planar-face")
            continue
        turns = [dot(cross(sub(poly[(i + 1) % len(poly)], poly[i]), sub(p, poly[i])), normal)
                 for i in range(len(poly)) for p in poly]
        if not any(normal) or any(t < 0 for t in turns):
            problems.add("non-convex-face")
    if problems:
        return problems
    if volume(faces, points) <= 0:
        return {"non-positive-volume"}
    for face in faces:
        poly = [points[v] for v in face]
        normal = newell(poly)
        if any(dot(normal, sub(points[v], poly[0])) > 0 for v in vertices):
            return {"non-convex-cell"}
    return set()


def volume(faces: tuple[tuple[int, ...], ...], points: dict[int, Vec]) -> Fraction:
    """The divergence theorem: the sum over faces of (a point of it . its vector area)/3."""
    return sum((dot(points[f[0]], newell([points[v] for v in f])) for f in faces),
               Fraction(0)) / 6


def independent_view(mesh: MixedMesh3) -> tuple[dict[tuple[int, ...], set[str]], Fraction,
                                                  int, int]:
    points = {v: tuple(Fraction(int(c.numerator), int(c.denominator)) for c in p[:3])
              for v, p in mesh.vertices.items()}
    problems = {}
    total = Fraction(0)
    polygons: Counter[frozenset[int]] = Counter()
    directed: Counter[tuple[int, ...]] = Counter()
    for cell in mesh.cell_list():
        problems[cell.vertices] = first_problem(cell.faces, points)  # type: ignore[arg-type]
        total += volume(cell.faces, points)  # type: ignore[arg-type]
        for face in cell.faces:
            start = face.index(min(face))
            directed[face[start:] + face[:start]] += 1
    for face, times in directed.items():
        back = tuple(reversed(face))
        start = back.index(min(back))
        if directed.get(back[start:] + back[:start]) == 1 and times == 1:
            polygons[frozenset(face)] += 1
    same_side = sum(1 for times in directed.values() if times > 1)
    return problems, total, len(polygons), same_side


def corrupt(mesh: MixedMesh3, rng: random.Random) -> MixedMesh3:
    choice = rng.randrange(4)
    cells = mesh.cell_list()
    points = [mesh.point(v) for v in range(mesh.vertex_count)]
    if choice == 1:
        v = rng.randrange(len(points))
        p = points[v]
        points[v] = (p.x + Fraction(rng.randint(-2, 2), rng.randint(1, 5)), p.y,  # type: ignore[assignment]
                     p.z + Fraction(rng.randint(-1, 1), 3))
    elif choice == 2:
        k = rng.randrange(len(cells))
        cells[k] = cell_of_faces([tuple(reversed(f)) for f in cells[k].faces])
    elif choice == 3 and len(cells) > 1:
        cells.pop(rng.randrange(len(cells)))
    return mixed_mesh_from_cells(points, cells)


@pytest.mark.parametrize("seed", range(300))
def test_validate_mixed_agrees_with_an_independent_fraction_check(seed: int) -> None:
    rng = random.Random(seed)
    box, start = random_grid(rng, largest=2)
    transient = start.transient()
    random_walk(transient, rng, rng.randint(0, 6))
    mesh = corrupt(transient.seal(), rng)
    found = validate_mixed(mesh, volume=box.volume)
    problems, total, _, same_side = independent_view(mesh)
    reported: dict[tuple[int, ...], set[str]] = {}
    for violation in found:
        if violation.kind in CELL_KINDS:
            reported.setdefault(violation.elements, set()).add(violation.kind)
    for vertices, kinds in problems.items():
        assert reported.get(vertices, set()) == kinds, (vertices, kinds)
    assert ("volume-mismatch" in {v.kind for v in found}) == (total != box.volume)
    assert ("face-orientation" in {v.kind for v in found}) == (same_side > 0)
    if not any(problems.values()) and total == box.volume and same_side == 0:
        # nothing changed, or a moved vertex kept every cell convex: still valid
        assert found == []
