"""The tetrahedral mesh checker: :func:`validate3` returns every violated invariant of a
:class:`~geomexact.mesh3d.snapshot.Mesh3`, :func:`check3` raises
:class:`~geomexact.errors.InvalidMeshError` carrying them.  Invariants:
``specs/mesh3d.md``."""

from __future__ import annotations

from collections import Counter

from geomexact.errors import InvalidMeshError, Violation
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

__all__ = ["check3", "validate3"]


def validate3(
    mesh: Mesh3, *, volume: Rational | int | None = None, check_digest: bool = True
) -> list[Violation]:
    """Every violation of the 3D invariants, in a deterministic order (empty when valid).

    Checked: vertex ids are 0..n-1; faces refer to existing vertices; each tetrahedron's
    four faces agree (``adjacency``); every tetrahedron is positively oriented (exact
    orient3d); the tetrahedron count; each vertex hint is a face containing it; the
    boundary is closed (every edge of a boundary face is shared by exactly two boundary
    faces, in opposite directions); with ``volume``, the volumes sum exactly to it; with
    ``check_digest``, the digest equals a recomputation.  An interior face is shared by
    exactly two tetrahedra with opposite orientations by construction of the face table
    (one entry per oriented face), which ``adjacency`` makes sure of."""
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
    found.extend(_open_boundary(mesh))
    if volume is not None and total_volume(mesh) != volume:
        found.append(Violation("volume", f"the tetrahedra's volumes sum to "
                               f"{total_volume(mesh)}, not {volume}"))
    if check_digest and full_digest3(mesh) != mesh.digest:
        found.append(Violation("digest", "digest differs from its recomputation"))
    return found


def _open_boundary(mesh: Mesh3) -> list[Violation]:
    """Boundary edges not shared by exactly two boundary faces in opposite directions."""
    directed: Counter[tuple[int, int]] = Counter()
    faces = mesh.faces
    for face in faces:
        if opposite_face(face) not in faces:
            a, b, c = opposite_face(face)  # outward
            directed.update(((a, b), (b, c), (c, a)))
    problems = []
    for (u, v), times in sorted(directed.items()):
        if times != 1 or directed.get((v, u), 0) != 1:
            problems.append(Violation(
                "boundary", f"boundary edge ({u}, {v}) is used {times} time(s), its reverse "
                f"{directed.get((v, u), 0)}: the boundary is not a closed surface", (u, v)))
    return problems


def check3(mesh: Mesh3, *, volume: Rational | int | None = None) -> Mesh3:
    """``mesh`` itself when valid, else :class:`InvalidMeshError` listing the violations."""
    violations = validate3(mesh, volume=volume)
    if violations:
        raise InvalidMeshError(violations)
    return mesh
