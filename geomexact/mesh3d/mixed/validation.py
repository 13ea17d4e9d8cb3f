"""The mixed-mesh checker: :func:`validate_mixed` returns every violated invariant of a
:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`, exactly; :func:`check_mixed` raises
:class:`~geomexact.errors.InvalidMeshError` carrying them.  Invariants: ``specs/mixed.md``,
"Validation"."""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Mapping, Sequence

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.numbers import ZERO, Rational, sign
from geomexact.kernel.points import Point3
from geomexact.mesh3d.mixed.cell_geometry import (
    Vector,
    cell_problems,
    cell_volume,
    face_normal,
    is_convex_polygon,
    is_planar_polygon,
)
from geomexact.mesh3d.mixed.cells import Cell, Face, cell_hash_of, polygon_key
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, full_mixed_digest
from geomexact.mesh3d.mixed.transient import faces_of

__all__ = ["check_mixed", "validate_mixed"]

Point2D = tuple[Rational, Rational]


def validate_mixed(mesh: MixedMesh3, *, volume: Rational | int | None = None,
                   check_digest: bool = True, cell_geometry: bool = True) -> list[Violation]:
    """Every violation of the mixed-mesh invariants, in a deterministic order (empty when
    valid).

    Checked: vertex ids are 0..n-1 (``vertex-ids``); cells name existing vertices
    (``missing-vertex``); the face table is that of the cells (``adjacency``); each cell
    (sorted order) passes :func:`~geomexact.mesh3d.mixed.cell_geometry.cell_problems`
    (``cell-surface``, ``coincident-vertices``, ``non-planar-face``, ``non-convex-face``,
    ``non-positive-volume``, ``non-convex-cell``); each polygon is a face of one cell or
    of two with opposite orientations (``face-orientation``: two cells on one side;
    ``non-manifold-face``: more than two); a face of one cell that overlaps, in its
    plane, faces of other cells turned the other way is a ``hanging-face`` (a quad
    against two triangles); the remaining faces, the boundary, close up: along every
    line their edges cancel exactly (``open-boundary``) and no directed edge is used
    twice (``non-manifold-edge``); with ``volume``, the cells' volumes sum exactly to it
    (``volume-mismatch``); with ``check_digest``, the digest and each cell's stored hash
    equal a recomputation (``digest``).  Without ``cell_geometry`` each cell is checked
    for its surface and coincident vertices only, not for planar, convex faces, positive
    volume and convexity: for a caller that proved those otherwise (the octree's cell
    finals prove each template once: affine images keep them)."""
    found: list[Violation] = []
    points = mesh.vertices
    if sorted(points) != list(range(mesh.vertex_count)):
        found.append(Violation("vertex-ids", "vertex ids are not 0..n-1"))
    cells = mesh.cell_list()
    present = []
    for cell in cells:
        missing = [v for v in cell.vertices if v not in points]
        if missing:
            found.append(Violation("missing-vertex", f"cell {cell} names missing vertices "
                                   f"{missing}", cell.vertices))
        else:
            present.append(cell)
    table = {face: tuple(sorted(owners)) for face, owners in faces_of(cells).items()}
    if table != dict(mesh.faces.items()):
        found.append(Violation("adjacency", "the face table is not that of the cells"))
    for cell in present:
        found.extend(cell_problems(cell, points, geometry=cell_geometry))
    unmatched = _matched_faces(present, found)
    hanging, boundary = _hanging_faces(unmatched, points)
    found.extend(hanging)
    found.extend(_open_boundary(boundary, points))
    if volume is not None:
        total = sum((cell_volume(cell, points) for cell in present), ZERO)
        if total != volume:
            found.append(Violation("volume-mismatch", f"the cells' volumes sum to {total}, "
                                   f"not {volume}"))
    if check_digest and (full_mixed_digest(mesh) != mesh.digest or any(
            value != cell_hash_of(cell) for cell, value in mesh.cell_hashes.items())):
        found.append(Violation("digest", "digest differs from its recomputation"))
    return found


def _matched_faces(cells: Sequence[Cell], found: list[Violation]) -> list[tuple[Face, Cell]]:
    """Group the cells' faces by polygon; report polygons on one side of two cells or in
    more than two; return the faces not matched by one face turned the other way, each
    as (outward face, cell), in polygon order: the faces of one cell, and every use of a
    reported polygon (they belong to the boundary's chain of faces)."""
    uses: defaultdict[Face, list[tuple[Face, Cell]]] = defaultdict(list)
    for cell in cells:
        for face in cell.faces:
            uses[polygon_key(face)].append((face, cell))
    single = []
    for key in sorted(uses):
        group = uses[key]
        if len(group) == 2 and group[0][0] != group[1][0]:
            continue  # an interior face
        single.extend(group)
        if len(group) == 1:
            continue
        if len(group) > 2:
            found.append(Violation("non-manifold-face", f"face {key} is a face of "
                                   f"{len(group)} cells: {', '.join(str(c) for _, c in group)}",
                                   key))
        elif group[0][0] == group[1][0]:
            found.append(Violation("face-orientation", f"face {key} has the same orientation "
                                   f"in {group[0][1]} and {group[1][1]}: they are on one side "
                                   "of it", key))
    return single


def _plane_of(face: Face, points: Mapping[int, Point3]) -> tuple[tuple[object, ...], int,
                                                                 Vector] | None:
    """(the face's plane without orientation, +1 or -1: its orientation, its normal), or
    None for a face that is not a planar convex polygon (reported with its cell)."""
    corners = [points[v] for v in face]
    if not is_planar_polygon(corners) or not is_convex_polygon(corners):
        return None
    normal = face_normal(corners)
    assert normal is not None
    k = next(i for i in range(3) if normal[i] != 0)
    unit = tuple(c / normal[k] for c in normal)
    offset = sum((u * c for u, c in zip(unit, corners[0][:3], strict=True)), ZERO)
    return (k, *unit, offset), sign(normal[k]), normal


def _projected(face: Face, points: Mapping[int, Point3], axis: int) -> list[Point2D]:
    kept = [i for i in range(3) if i != axis]
    return [(points[v][kept[0]], points[v][kept[1]]) for v in face]


def _cross2(a: Point2D, b: Point2D, c: Point2D) -> int:
    return sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def _area_sign(polygon: list[Point2D]) -> int:
    return sign(sum((polygon[i - 1][0] * p[1] - p[0] * polygon[i - 1][1]
                     for i, p in enumerate(polygon)), ZERO))


def _separates(polygon: list[Point2D], other: list[Point2D]) -> bool:
    """True when a side of the convex ``polygon`` has all of ``other`` on or beyond it."""
    turn = _area_sign(polygon)
    return any(all(turn * _cross2(polygon[i - 1], p, q) <= 0 for q in other)
               for i, p in enumerate(polygon))


def _overlap(first: list[Point2D], second: list[Point2D]) -> bool:
    """True when two convex polygons of one plane share interior points (no side of
    either separates them)."""
    return not _separates(first, second) and not _separates(second, first)


def _hanging_faces(unmatched: list[tuple[Face, Cell]], points: Mapping[int, Point3]
                   ) -> tuple[list[Violation], list[tuple[Face, Cell]]]:
    """The hanging faces (faces of one cell overlapping, in their common plane, faces of
    one cell turned the other way; one violation per connected group) and the remaining
    faces (the boundary)."""
    planes: defaultdict[tuple[object, ...], list[int]] = defaultdict(list)
    orientation: dict[int, int] = {}
    for index, (face, _) in enumerate(unmatched):
        plane = _plane_of(face, points)
        if plane is not None:
            planes[plane[0]].append(index)
            orientation[index] = plane[1]
    parent = list(range(len(unmatched)))

    def root(n: int) -> int:
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    involved: set[int] = set()
    for key, members in planes.items():
        axis = int(key[0])  # type: ignore[call-overload]
        shapes = {m: _projected(unmatched[m][0], points, axis) for m in members}
        ups = [m for m in members if orientation[m] > 0]
        downs = [m for m in members if orientation[m] < 0]
        for up in ups:
            for down in downs:
                if _overlap(shapes[up], shapes[down]):
                    involved.update((up, down))
                    low, high = sorted((root(up), root(down)))
                    parent[high] = low
    groups: defaultdict[int, list[int]] = defaultdict(list)
    for index in sorted(involved):
        groups[root(index)].append(index)
    found = []
    for _, members in sorted(groups.items()):
        faces = [unmatched[m][0] for m in members]
        cells = sorted({unmatched[m][1] for m in members})
        found.append(Violation(
            "hanging-face", f"faces {faces} of cells {', '.join(map(str, cells))} overlap "
            "in one plane but are not the same polygons: a hanging face",
            tuple(sorted({v for face in faces for v in face}))))
    boundary = [entry for index, entry in enumerate(unmatched) if index not in involved]
    return found, boundary


def _open_boundary(boundary: list[tuple[Face, Cell]], points: Mapping[int, Point3]
                   ) -> list[Violation]:
    """Where the boundary faces do not close up: a directed edge used twice, or a line
    along which their edges do not cancel (as segments: an edge ab cancels am and mb)."""
    directed: Counter[tuple[int, int]] = Counter()
    for face, _ in boundary:
        for i, vertex in enumerate(face):
            directed[(vertex, face[(i + 1) % len(face)])] += 1
    found = []
    for (u, v), times in sorted(directed.items()):
        if times > 1:
            found.append(Violation("non-manifold-edge", f"boundary edge ({u}, {v}) is used "
                                   f"{times} times that way: the boundary touches itself",
                                   (u, v)))
    lines: dict[tuple[object, ...], defaultdict[Rational, int]] = {}
    first_edge: dict[tuple[object, ...], tuple[int, int]] = {}
    for (u, v), times in sorted(directed.items()):
        a, b = points[u], points[v]
        direction = (b.x - a.x, b.y - a.y, b.z - a.z)
        if not any(direction):
            continue  # coincident vertices, reported with their cell
        k = next(i for i in range(3) if direction[i] != 0)
        unit = tuple(c / direction[k] for c in direction)
        base = tuple(a[i] - a[k] * unit[i] for i in range(3))
        key = (k, *unit, *base)
        start, end = a[k], b[k]
        weight = times if start < end else -times
        low, high = min(start, end), max(start, end)
        events = lines.setdefault(key, defaultdict(int))
        first_edge.setdefault(key, (u, v))
        events[low] += weight
        events[high] -= weight
    for key, events in lines.items():
        if any(events.values()):
            u, v = first_edge[key]
            found.append(Violation("open-boundary", f"the boundary is open along the line of "
                                   f"edge ({u}, {v}): its edges there do not cancel",
                                   (u, v)))
    return found


def check_mixed(mesh: MixedMesh3, *, volume: Rational | int | None = None) -> MixedMesh3:
    """``mesh`` itself when valid, else :class:`InvalidMeshError` listing the
    violations."""
    violations = validate_mixed(mesh, volume=volume)
    if violations:
        raise InvalidMeshError(violations)
    return mesh
