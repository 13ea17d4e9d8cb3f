"""The tetrahedral mesh checker: :func:`validate3` returns every violated invariant of a
:class:`~geomexact.mesh3d.snapshot.Mesh3`, :func:`check3` raises
:class:`~geomexact.errors.InvalidMeshError` carrying them.  Invariants:
``specs/mesh3d.md``."""

from __future__ import annotations

from collections import Counter
from typing import Any

import numpy as np

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.components import component_labels
from geomexact.kernel.numbers import Rational
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.measures import total_volume
from geomexact.mesh3d.snapshot import (
    Mesh3,
    full_digest3,
    opposite_face,
    tetrahedron_faces,
)

__all__ = ["check3", "isolated_vertices3", "manifold_violations", "validate3"]


def validate3(
    mesh: Mesh3, *, volume: Rational | int | None = None, check_digest: bool = True
) -> list[Violation]:
    """Every violation of the 3D invariants, in a deterministic order (empty when valid).

    Checked: vertex ids are 0..n-1; faces refer to existing vertices; each tetrahedron's
    four faces agree (``adjacency``); every tetrahedron is positively oriented (exact
    orient3d); the tetrahedron count; each vertex hint is a face containing it; the
    boundary is closed (every edge of a boundary face is shared by exactly two boundary
    faces, in opposite directions); the mesh is a 3-manifold with boundary around every
    edge and vertex (:func:`manifold_violations`; the boundary check then skips the
    edges it reports); with ``volume``, the volumes sum exactly to it; with
    ``check_digest``, the digest equals a recomputation.  An interior face is shared by
    exactly two tetrahedra with opposite orientations by construction of the face table
    (one entry per oriented face), which ``adjacency`` makes sure of.  Vertices in no
    tetrahedron are legal (:func:`isolated_vertices3` lists them)."""
    found: list[Violation] = []
    count = mesh.vertex_count
    if sorted(mesh.vertices) != list(range(count)):
        found.append(Violation("vertex-ids", "vertex ids are not 0..n-1"))
    faces = mesh.faces
    tetrahedra = []
    for face, apex in sorted(faces.items()):
        corners = (*face, apex)
        if not all(vertex in mesh.vertices for vertex in corners):
            found.append(Violation("missing-vertex", f"face {face} -> {apex} refers to a "
                                   "missing vertex", corners))
            continue
        for other, other_apex in tetrahedron_faces(*corners):
            if faces.get(other) != other_apex:
                found.append(Violation(
                    "adjacency", f"face {face} -> {apex}: face {other} of the same "
                    f"tetrahedron should map to {other_apex}, not {faces.get(other)}", corners))
                break
        else:
            if min(corners) == apex:  # each tetrahedron once
                tetrahedra.append(corners)
    for corners in tetrahedra:
        if orient3d(*(mesh.point(v) for v in corners)) != Orientation.COUNTERCLOCKWISE:
            found.append(Violation("orientation", f"tetrahedron {corners} is not positively "
                                   "oriented", corners))
    if len(tetrahedra) != mesh.tetrahedron_count:
        found.append(Violation("tetrahedron-count", f"tetrahedron_count is "
                               f"{mesh.tetrahedron_count}, but there are {len(tetrahedra)}"))
    for vertex, hint in sorted(mesh.hints.items()):
        if hint not in faces or vertex not in hint:
            found.append(Violation("hint", f"vertex {vertex}: hint {hint} is not a face "
                                   "containing it", (vertex,)))
    manifold = manifold_violations(tetrahedra)
    found.extend(manifold)
    pinched = {v.elements for v in manifold if v.kind == "non-manifold-edge"}
    found.extend(_open_boundary(mesh, pinched))
    if volume is not None and total_volume(mesh) != volume:
        found.append(Violation("volume", f"the tetrahedra's volumes sum to "
                               f"{total_volume(mesh)}, not {volume}"))
    if check_digest and full_digest3(mesh) != mesh.digest:
        found.append(Violation("digest", "digest differs from its recomputation"))
    return found


def _open_boundary(mesh: Mesh3, skipped: set[tuple[int, ...]]) -> list[Violation]:
    """Boundary edges not shared by exactly two boundary faces in opposite directions,
    but those ``skipped`` (as sorted pairs: non-manifold edges, reported as such)."""
    directed: Counter[tuple[int, int]] = Counter()
    faces = mesh.faces
    for face in faces:
        if opposite_face(face) not in faces:
            a, b, c = opposite_face(face)  # outward
            directed.update(((a, b), (b, c), (c, a)))
    problems = []
    for (u, v), times in sorted(directed.items()):
        if (min(u, v), max(u, v)) in skipped:
            continue
        if times != 1 or directed.get((v, u), 0) != 1:
            problems.append(Violation(
                "boundary", f"boundary edge ({u}, {v}) is used {times} time(s), its reverse "
                f"{directed.get((v, u), 0)}: the boundary is not a closed surface", (u, v)))
    return problems


_EDGE_CORNERS = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
"""The six edges of a tetrahedron, by the positions of their corners."""

_EDGE_OF = np.full((4, 4), -1, dtype=np.int64)
"""Corner positions (i, j) -> the index of their edge in :data:`_EDGE_CORNERS`."""
_EDGE_OF[tuple(np.array(_EDGE_CORNERS).T)] = np.arange(6)
_EDGE_OF[tuple(np.array(_EDGE_CORNERS).T[::-1])] = np.arange(6)

_OPPOSITE = np.array([[k for k in range(4) if k != i] for i in range(4)], dtype=np.int64)
"""Row i: the corner positions of the face opposite corner i."""


def manifold_violations(tetrahedra: list[tuple[int, int, int, int]]) -> list[Violation]:
    """Where the tetrahedra (each listed once, consistent with a face table: no oriented
    face twice) are not a 3-manifold with boundary, decided combinatorially.

    ``non-manifold-edge``: the tetrahedra around an edge are not one fan, i.e. not
    connected through their faces containing the edge (two tetrahedra sharing only an
    edge).  ``non-manifold-vertex``, at a vertex on no such edge: the tetrahedra around it
    are not connected through their faces containing it (two tetrahedra sharing only a
    vertex), or they are but do not make a ball: the surface of their faces opposite it
    (its link) is then connected and orientable, and it is a sphere (interior vertex) or a
    disk (boundary vertex) exactly when its Euler characteristic is 2 or 1.  Edges first,
    then vertices, each in increasing order.  O(n log n), on arrays."""
    if not tetrahedra:
        return []
    tets = np.array(tetrahedra, dtype=np.int64)
    count = len(tets)
    pairs, face_counts = _shared_faces(tets)
    first, second = pairs[:, 0], pairs[:, 1]  # rows of the 4T (tetrahedron, corner) table
    t1, t2 = first // 4, second // 4
    in_first = _OPPOSITE[first % 4]  # (P x 3) positions of the shared face's corners in t1
    vertices = tets[t1[:, None], in_first]
    in_second = np.argmax(tets[t2][:, None, :] == vertices[:, :, None], axis=2)
    corner_label = component_labels(
        4 * count, (4 * t1[:, None] + in_first).ravel(), (4 * t2[:, None] + in_second).ravel()
    )
    edge_links = [(_EDGE_OF[in_first[:, i], in_first[:, j]], _EDGE_OF[in_second[:, i],
                                                                      in_second[:, j]])
                  for i, j in ((0, 1), (0, 2), (1, 2))]
    edge_label = component_labels(
        6 * count,
        np.concatenate([6 * t1 + e1 for e1, _ in edge_links]),
        np.concatenate([6 * t2 + e2 for _, e2 in edge_links]),
    )
    found: list[Violation] = []
    corners = np.array(_EDGE_CORNERS, dtype=np.int64)
    ends = np.sort(tets[:, corners].reshape(-1, 2), axis=1)  # row 6 t + j: edge j of t
    edge_keys, fans = _groups(ends, edge_label)
    pinched = edge_keys[fans > 1]
    for (u, v), k in zip(pinched.tolist(), fans[fans > 1].tolist(), strict=True):
        found.append(Violation(
            "non-manifold-edge", f"the tetrahedra around edge ({u}, {v}) form {k} fans that "
            "share no face: they meet only along the edge", (u, v)))
    vertex_keys, groups = _groups(tets.reshape(-1, 1), corner_label)
    on_pinched = np.zeros(int(tets.max()) + 1, dtype=bool)
    on_pinched[pinched.ravel()] = True
    euler, closed = _link_euler(tets, ends, face_counts)
    for vertex, k in zip(vertex_keys[:, 0].tolist(), groups.tolist(), strict=True):
        if on_pinched[vertex]:
            continue
        if k > 1:
            found.append(Violation(
                "non-manifold-vertex", f"the tetrahedra around vertex {vertex} form {k} "
                "groups that share no face: they meet only at the vertex", (vertex,)))
        elif euler[vertex] != (2 if closed[vertex] else 1):
            shape = "sphere" if closed[vertex] else "disk"
            found.append(Violation(
                "non-manifold-vertex", f"the tetrahedra around vertex {vertex} do not form a "
                f"ball: their faces opposite it make a surface of Euler characteristic "
                f"{euler[vertex]}, not a {shape}", (vertex,)))
    return found


def _shared_faces(tets: Any) -> tuple[Any, Any]:
    """The interior faces as pairs of rows of the (tetrahedron, opposite corner) table
    (row 4 t + i: the face of t opposite its corner i), and every face as its sorted
    vertices with its number of tetrahedra (1 or 2)."""
    keys = np.sort(tets[:, _OPPOSITE].reshape(-1, 3), axis=1)
    order = np.lexsort(keys.T[::-1])
    ordered = keys[order]
    same = np.all(ordered[1:] == ordered[:-1], axis=1)
    pairs = np.stack([order[:-1][same], order[1:][same]], axis=1)
    return pairs, _counted_rows(ordered)


def _counted_rows(ordered: Any) -> tuple[Any, Any]:
    """The distinct rows of the lexicographically sorted ``ordered`` and how many times
    each occurs (``np.unique(axis=0)``, without its slow sort of whole rows)."""
    starts = np.flatnonzero(np.concatenate(
        [[True], np.any(ordered[1:] != ordered[:-1], axis=1)]))
    return ordered[starts], np.diff(np.append(starts, len(ordered)))


def _distinct_rows(rows: Any) -> tuple[Any, Any]:
    """:func:`_counted_rows` of ``rows`` in any order."""
    return _counted_rows(rows[np.lexsort(rows.T[::-1])])


def _groups(keys: Any, labels: Any) -> tuple[Any, Any]:
    """The distinct rows of ``keys``, sorted, and how many distinct ``labels`` each has."""
    distinct, _ = _distinct_rows(np.column_stack([keys, labels]))
    return _counted_rows(distinct[:, :-1])


def _link_euler(tets: Any, ends: Any, faces: tuple[Any, Any]) -> tuple[Any, Any]:
    """Per vertex: the Euler characteristic of its link (edges - faces + tetrahedra
    through it: the link's vertices, edges and triangles) and whether the link is closed
    (no boundary face through the vertex)."""
    size = int(tets.max()) + 1
    keys, counts = faces
    edges, _ = _distinct_rows(ends)
    euler = (np.bincount(edges.ravel(), minlength=size)
             - np.bincount(keys.ravel(), minlength=size)
             + np.bincount(tets.ravel(), minlength=size))
    on_boundary = np.bincount(keys[counts == 1].ravel(), minlength=size)
    return euler, on_boundary == 0


def isolated_vertices3(mesh: Mesh3) -> list[Violation]:
    """An ``isolated-vertex`` violation for each vertex in no tetrahedron (legal in a
    :class:`Mesh3`, reported by ``geomexact check --strict``), in id order.  O(n)."""
    used = np.zeros(mesh.vertex_count, dtype=bool)
    tets = mesh.tetrahedron_array()
    used[tets.ravel()] = True
    return [Violation("isolated-vertex", f"vertex {vertex} is in no tetrahedron", (vertex,))
            for vertex in np.flatnonzero(~used).tolist()]


def check3(mesh: Mesh3, *, volume: Rational | int | None = None) -> Mesh3:
    """``mesh`` itself when valid, else :class:`InvalidMeshError` listing the violations."""
    violations = validate3(mesh, volume=volume)
    if violations:
        raise InvalidMeshError(violations)
    return mesh
