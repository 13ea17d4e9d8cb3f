"""The 3-manifold checks of ``validate3`` (issue 27, item 4): two tetrahedra sharing only a
vertex or only an edge, a vertex whose tetrahedra make a ring (its link an annulus), and
unused vertices (legal, listed by ``isolated_vertices3``); and a property test of
``manifold_violations`` against its definition on random subsets of valid meshes."""

from __future__ import annotations

from itertools import combinations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import Violation
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra
from geomexact.mesh3d.validation import isolated_vertices3, manifold_violations, validate3

Corner = tuple[int, int, int]


def _positive(points: list[Corner], tetrahedra: list[list[int]]) -> list[list[int]]:
    """Each tetrahedron with its first two corners swapped when it is negative."""
    result = []
    for a, b, c, d in tetrahedra:
        volume = np.linalg.det(np.subtract([points[b], points[c], points[d]], points[a]))
        result.append([a, b, c, d] if volume > 0 else [b, a, c, d])
    return result


def _mesh(points: list[Corner], tetrahedra: list[list[int]]) -> Mesh3:
    return mesh3_from_tetrahedra(points, _positive(points, tetrahedra))


AT_A_VERTEX = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, -1, 0),
                (0, 0, -1)], [[0, 1, 2, 3], [0, 4, 5, 6]])
ALONG_AN_EDGE = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, -1, 0)],
                 [[0, 1, 2, 3], [0, 3, 4, 5]])


def test_two_tetrahedra_sharing_only_a_vertex() -> None:
    mesh = _mesh(*AT_A_VERTEX)
    assert validate3(mesh) == [Violation(
        "non-manifold-vertex", "the tetrahedra around vertex 0 form 2 groups that share no "
        "face: they meet only at the vertex", (0,))]


def test_two_tetrahedra_sharing_only_an_edge() -> None:
    """One violation: the edge (its ends are not reported again, nor the boundary's four
    uses of the edge)."""
    mesh = _mesh(*ALONG_AN_EDGE)
    assert validate3(mesh) == [Violation(
        "non-manifold-edge", "the tetrahedra around edge (0, 3) form 2 fans that share no "
        "face: they meet only along the edge", (0, 3))]


def test_a_ring_of_tetrahedra_around_a_vertex() -> None:
    """Vertex 0 inside a square tube of 8 triangles: its tetrahedra are connected through
    faces and every edge is one fan, but the boundary is two cones touching at vertex 0
    (its link is an annulus, Euler characteristic 0)."""
    square = [(2, 0), (0, 2), (-2, 0), (0, -2)]
    points = [(0, 0, 0)] + [(x, y, -1) for x, y in square] + [(x, y, 1) for x, y in square]
    low, high = [1, 2, 3, 4], [5, 6, 7, 8]
    tetrahedra = []
    for i in range(4):
        j = (i + 1) % 4
        tetrahedra += [[0, low[i], low[j], high[j]], [0, low[i], high[j], high[i]]]
    mesh = _mesh(points, tetrahedra)
    assert validate3(mesh) == [Violation(
        "non-manifold-vertex", "the tetrahedra around vertex 0 do not form a ball: their "
        "faces opposite it make a surface of Euler characteristic 0, not a disk", (0,))]
    # closing the tube at both ends makes vertex 0 interior: a ball, valid
    closed = _mesh(points + [(0, 0, -2), (0, 0, 2)], tetrahedra + [
        [0, low[i], low[(i + 1) % 4], 9] for i in range(4)] + [
        [0, high[i], high[(i + 1) % 4], 10] for i in range(4)])
    assert validate3(closed) == []


def test_unused_vertices_are_legal_and_listed() -> None:
    points = [(0, 0, 0), (1, 0, 0), (5, 5, 5), (0, 1, 0), (0, 0, 1), (7, 7, 7)]
    mesh = _mesh(points, [[0, 1, 3, 4]])
    assert validate3(mesh) == []
    assert isolated_vertices3(mesh) == [
        Violation("isolated-vertex", "vertex 2 is in no tetrahedron", (2,)),
        Violation("isolated-vertex", "vertex 5 is in no tetrahedron", (5,)),
    ]
    assert isolated_vertices3(_mesh(*AT_A_VERTEX)) == []


# -- against the definition ---------------------------------------------------------------
def _fans(group: list[frozenset[int]]) -> int:
    """The number of classes of ``group`` joined by shared faces (three common vertices)."""
    seen: set[frozenset[int]] = set()
    classes = 0
    for start in group:
        if start in seen:
            continue
        classes += 1
        stack = [start]
        seen.add(start)
        while stack:
            current = stack.pop()
            for other in group:
                if other not in seen and len(current & other) == 3:
                    seen.add(other)
                    stack.append(other)
    return classes


def _reference(tetrahedra: list[tuple[int, int, int, int]]) -> list[tuple[str, tuple[int, ...]]]:
    """``manifold_violations``' kinds and elements, from their definitions on sets."""
    cells = [frozenset(t) for t in tetrahedra]
    found: list[tuple[str, tuple[int, ...]]] = []
    edges = sorted({pair for cell in cells for pair in combinations(sorted(cell), 2)})
    pinched = set()
    for u, v in edges:
        if _fans([cell for cell in cells if {u, v} <= cell]) > 1:
            found.append(("non-manifold-edge", (u, v)))
            pinched |= {u, v}
    for vertex in sorted({v for cell in cells for v in cell} - pinched):
        star = [cell for cell in cells if vertex in cell]
        faces = [frozenset(face) for cell in star for face in combinations(cell, 3)
                 if vertex in face]
        links = {frozenset(face) for face in faces}
        neighbours = {v for cell in star for v in cell} - {vertex}
        closed = all(faces.count(face) == 2 for face in links)
        euler = len(neighbours) - len(links) + len(star)
        if _fans(star) > 1 or euler != (2 if closed else 1):
            found.append(("non-manifold-vertex", (vertex,)))
    return found


FULL = partition_cuboid(2**18 - 1).mesh  # 40 tetrahedra, 26 vertices (one inside)


@settings(max_examples=150, deadline=None)
@given(st.sets(st.integers(0, FULL.tetrahedron_count - 1), min_size=1))
def test_manifold_violations_follow_their_definition(chosen: set[int]) -> None:
    """Any subset of a valid mesh's tetrahedra is a mesh (a face table); its pinched edges
    and vertices are those of the definitions, in the same order."""
    all_tetrahedra = FULL.tetrahedra()
    subset = [all_tetrahedra[k] for k in sorted(chosen)]
    found = manifold_violations(subset)
    assert [(v.kind, v.elements) for v in found] == _reference(subset)
    mesh = mesh3_from_tetrahedra(FULL.point_list(), subset)
    assert [v for v in validate3(mesh) if v.kind.startswith("non-manifold")] == found
    if len(chosen) == FULL.tetrahedron_count:
        assert found == []
