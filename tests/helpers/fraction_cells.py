"""Cell geometry with ``fractions.Fraction`` only (no geomexact code): the independent
checks of mixed meshes (``test_mixed_independent``, ``test_octree_cells``)."""

from __future__ import annotations

from collections import Counter
from fractions import Fraction

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
