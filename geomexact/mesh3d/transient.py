"""The batch builder of :class:`~geomexact.mesh3d.snapshot.Mesh3`: a :class:`Transient3`
opens on a snapshot in O(1), takes any number of edits and steps, and is sealed into the
next snapshot in O(1).  It never escapes the function that made it."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import immutables

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.collector import collector_paused
from geomexact.kernel.points import Point3, point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.snapshot import (
    Face,
    FaceSource,
    Mesh3,
    Tetrahedron,
    canonical_face,
    canonical_tetrahedron,
    empty_mesh3,
    tetrahedron_faces,
)
from geomexact.trace.protocols import kind_of
from geomexact.trace.recording import RecordingTransient
from geomexact.trace.tables import open_table, sealed_table, table_snapshot

__all__ = ["SpaceTransient", "Transient3", "mesh3_from_positive_arrays",
           "mesh3_from_tetrahedra"]


class SpaceTransient(RecordingTransient[Point3]):
    """What the transients of 3D meshes (:class:`Transient3` and the mixed meshes') have
    in common beyond :class:`~geomexact.trace.recording.RecordingTransient`: vertices
    with three coordinates."""

    __slots__ = ()

    def add_vertex(self, point: Point3) -> int:
        """Append a vertex (in no cell yet) and return its id."""
        return self._append_vertex(point, point[:3])


class Transient3(SpaceTransient):
    """Mutable edits on a :class:`Mesh3`, with the digest kept current (O(1) per element)
    and the steps recorded with the digest after each; its steps go through the 3D step
    table (:data:`geomexact.mesh3d.ops.OPERATIONS` and ``insert_cuboid``: the kind's
    table)."""

    __slots__ = ("_faces", "_hints", "_stale", "_tetrahedron_count")

    snapshot_type = Mesh3

    def __init__(self, mesh: Mesh3, *, batch: bool = False) -> None:
        """Open on ``mesh``'s vertices, faces, vertex hints and tetrahedron count
        (``batch``: plain dicts, :meth:`_open_record`)."""
        self._open_record(mesh.vertices, mesh.digest, batch)
        self._faces = open_table(mesh.faces, batch)
        self._hints = open_table(mesh.hints, batch)
        self._tetrahedron_count = mesh.tetrahedron_count
        self._stale: set[int] = set()  # vertices of removed tetrahedra: hints to check

    # -- reads --------------------------------------------------------------------------
    @property
    def tetrahedron_count(self) -> int:
        return self._tetrahedron_count

    def apex(self, a: int, b: int, c: int) -> int | None:
        """The apex of the tetrahedron on the positive side of the oriented face abc."""
        return self._faces.get(canonical_face(a, b, c))

    def has_tetrahedron(self, a: int, b: int, c: int, d: int) -> bool:
        return self._faces.get(canonical_face(a, b, c)) == d

    def star(self, vertex: int) -> list[Tetrahedron]:
        """The tetrahedra containing ``vertex`` (canonical, sorted), found by walking
        across the faces that contain it from its hint."""
        hint = self._hints.get(vertex)
        if hint is None or hint not in self._faces:
            return self._scan_star(vertex)
        first = canonical_tetrahedron(hint[0], hint[1], hint[2], self._faces[hint])
        seen = {first}
        pending = [first]
        faces = self._faces
        while pending:
            a, b, c, d = pending.pop()
            for face, _ in tetrahedron_faces(a, b, c, d):
                if vertex not in face:
                    continue
                x, y, z = face
                neighbour_apex = faces.get(canonical_face(x, z, y))
                if neighbour_apex is None:
                    continue
                neighbour = canonical_tetrahedron(x, z, y, neighbour_apex)
                if neighbour not in seen:
                    seen.add(neighbour)
                    pending.append(neighbour)
        return sorted(seen)

    def faces_snapshot(self) -> immutables.Map[Face, int]:
        """The current face table as an immutable map (to iterate over it).  O(1): the
        mutation is finished and reopened."""
        snapshot, self._faces = table_snapshot(self._faces)
        return snapshot

    def _scan_star(self, vertex: int) -> list[Tetrahedron]:
        return sorted(
            {
                canonical_tetrahedron(a, b, c, apex)
                for (a, b, c), apex in self.faces_snapshot().items()
                if vertex in (a, b, c, apex)
            }
        )

    def around_edge(self, u: int, v: int) -> list[Tetrahedron]:
        """The tetrahedra containing both u and v (canonical, sorted)."""
        return [tetrahedron for tetrahedron in self.star(u) if v in tetrahedron]

    # -- edits --------------------------------------------------------------------------
    def add_tetrahedron(self, a: int, b: int, c: int, d: int) -> None:
        """Add the tetrahedron abcd, which the caller knows to be positively oriented;
        :class:`PreconditionError` when a face of it already has a tetrahedron on that
        side."""
        self._check_open()
        entries = tetrahedron_faces(a, b, c, d)
        faces = self._faces
        for face, _ in entries:
            if face in faces:
                raise PreconditionError(
                    "add_tetrahedron",
                    f"face {face} of tetrahedron {(a, b, c, d)} already has a tetrahedron "
                    "on that side",
                )
        for face, apex in entries:
            faces[face] = apex
        hints = self._hints
        for index, (_, apex) in enumerate(entries):
            hints[apex] = entries[(index + 1) % 4][0]  # every other face contains the apex
        self._tetrahedron_count += 1
        self._digest = _digest.combine(
            self._digest, _digest.cell_hash(canonical_tetrahedron(a, b, c, d))
        )

    def remove_tetrahedron(self, a: int, b: int, c: int, d: int) -> None:
        """Remove the tetrahedron abcd (any even permutation)."""
        self._check_open()
        entries = tetrahedron_faces(a, b, c, d)
        faces = self._faces
        for face, apex in entries:
            if faces.get(face) != apex:
                raise PreconditionError(
                    "remove_tetrahedron", f"{(a, b, c, d)} is not a tetrahedron of the mesh"
                )
        for face, _ in entries:
            del faces[face]
        self._stale.update((a, b, c, d))
        self._tetrahedron_count -= 1
        self._digest = _digest.remove(
            self._digest, _digest.cell_hash(canonical_tetrahedron(a, b, c, d))
        )

    # -- steps and sealing --------------------------------------------------------------
    def _repair_hints(self) -> None:
        faces, hints = self._faces, self._hints
        stale = sorted(
            vertex for vertex in self._stale
            if (hint := hints.get(vertex)) is not None and hint not in faces
        )
        self._stale.clear()
        if not stale:
            return
        # rare (tetrahedra removed without replacement): one scan
        table = self.faces_snapshot()
        wanted = set(stale)
        best: dict[int, Face] = {}
        for face in table:  # one scan; the smallest face, so the table order cannot matter
            for vertex in face:
                if vertex in wanted and (vertex not in best or face < best[vertex]):
                    best[vertex] = face
        for vertex in stale:
            if vertex in best:
                hints[vertex] = best[vertex]
            else:
                del hints[vertex]

    def seal(self) -> Mesh3:
        """Finish the edits and return the new snapshot; the transient is then unusable."""
        self._check_open()
        self._repair_hints()
        self._sealed = True
        return Mesh3(
            vertices=sealed_table(self._vertices),
            faces=sealed_table(self._faces),
            hints=sealed_table(self._hints),
            tetrahedron_count=self._tetrahedron_count,
            digest=self._digest,
        )


def mesh3_from_tetrahedra(
    points: Sequence[Point3 | tuple[object, object, object]],
    tetrahedra: Iterable[Sequence[int]],
    *,
    orient: bool = False,
) -> Mesh3:
    """Build a snapshot from vertex and tetrahedron tables.

    ``points`` are :class:`Point3` or coordinate triples (converted exactly); tetrahedra
    are vertex-index quadruples, positively oriented unless ``orient=True`` (then each
    negative one is reversed).  :class:`PreconditionError` for an index out of range, a
    flat tetrahedron, a negative one when ``orient`` is false, or two tetrahedra on the
    same side of a face.
    """
    transient = Transient3(empty_mesh3())
    for raw in points:
        transient.add_vertex(raw if isinstance(raw, Point3) else point3(*raw))
    count = transient.vertex_count
    for index, raw_tetrahedron in enumerate(tetrahedra):
        a, b, c, d = (int(i) for i in raw_tetrahedron)
        if not all(0 <= vertex < count for vertex in (a, b, c, d)) or len({a, b, c, d}) < 4:
            raise PreconditionError(
                "mesh3_from_tetrahedra",
                f"tetrahedron #{index} {(a, b, c, d)} has a vertex out of range 0..{count - 1} "
                "or a repeated one",
            )
        orientation = orient3d(*(transient.point(v) for v in (a, b, c, d)))
        if orientation == Orientation.COLLINEAR:
            raise PreconditionError(
                "mesh3_from_tetrahedra", f"tetrahedron #{index} {(a, b, c, d)} is flat"
            )
        if orientation == Orientation.CLOCKWISE:
            if not orient:
                raise PreconditionError(
                    "mesh3_from_tetrahedra",
                    f"tetrahedron #{index} {(a, b, c, d)} is negatively oriented",
                )
            a, b = b, a
        transient.add_tetrahedron(a, b, c, d)
    return transient.seal()


def mesh3_from_positive_arrays(points: Sequence[Point3], tetrahedra: Any) -> Mesh3:
    """The snapshot of ``points`` and the (T x 4) integer array ``tetrahedra``, each known
    positive by construction (an octree's partition): the same value as
    :func:`mesh3_from_tetrahedra`, built in bulk without the per-tetrahedron orient3d.
    :class:`PreconditionError` when two tetrahedra are on the same side of a face or a
    vertex id is out of range."""
    with collector_paused():
        return _from_positive_arrays(points, tetrahedra)


def _from_positive_arrays(points: Sequence[Point3], tetrahedra: Any) -> Mesh3:
    import numpy as np

    array = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    count = len(points)
    if array.size and (array.min() < 0 or array.max() >= count):
        raise PreconditionError("mesh3_from_positive_arrays",
                                f"a tetrahedron has a vertex outside 0..{count - 1}")
    a, b, c, d = array.T
    faces = _rotate_to_smallest(np.concatenate(
        [np.stack(f, axis=1) for f in ((a, b, c), (a, c, d), (a, d, b), (b, d, c))]))
    apexes = np.concatenate((d, b, c, a))
    if len(faces) > 1 and _repeats_a_row(faces, count):
        raise PreconditionError("mesh3_from_positive_arrays",
                                "two tetrahedra are on the same side of a face")
    canonical = _canonical_rows(array)
    total = _bulk_digest(points, canonical)
    canonical = canonical[np.lexsort(canonical.T[::-1])]
    for derived in (faces, apexes, canonical):
        derived.setflags(write=False)
    # the persistent tables are built from these arrays on first use (FaceSource)
    return Mesh3(
        vertices=None,
        faces=None,
        hints=None,
        tetrahedron_count=int(array.shape[0]),
        digest=total,
        source=FaceSource(list(points), faces, apexes, canonical),
    )


def _bulk_digest(points: Sequence[Point3], rows: Any) -> int:
    """The digest of the mesh of ``points`` and the canonical tetrahedra ``rows``: by the
    kind's acceleration where it is built (the cuboid kernel: the same hashes in C, tested
    equal), else by :func:`~geomexact.kernel.digest.vertex_hash` and
    :func:`~geomexact.kernel.digest.cell_hash`."""
    accelerated = kind_of(Mesh3).bulk_digest
    value = None if accelerated is None else accelerated(points, rows)
    return reference_bulk_digest(points, rows) if value is None else value


def reference_bulk_digest(points: Sequence[Point3], rows: Any) -> int:
    """:func:`_bulk_digest` by the definition (the Python hashes)."""
    total = 0
    for vertex, point in enumerate(points):
        total += _digest.vertex_hash(vertex, point[:3])
    if len(rows):
        _digest.vertex_key(int(rows.max()))  # the keys of every id, cached
        cell_hash = _digest.cell_hash
        for tetrahedron in rows.tolist():
            total += cell_hash(tetrahedron)
    return total & (_digest.MODULUS - 1)


def _rotate_to_smallest(faces: Any) -> Any:
    """Each row (a, b, c) rotated to start at its smallest id (``canonical_face``)."""
    import numpy as np

    x, y, z = faces[:, 0], faces[:, 1], faces[:, 2]
    # the rotation is chosen column by column (cheaper than gathering whole rows)
    first, second = (x <= y) & (x <= z), (y < x) & (y <= z)
    rotated = np.empty_like(faces)
    rotated[:, 0] = np.where(first, x, np.where(second, y, z))
    rotated[:, 1] = np.where(first, y, np.where(second, z, x))
    rotated[:, 2] = np.where(first, z, np.where(second, x, y))
    return rotated


def _repeats_a_row(rows: Any, count: int) -> bool:
    """Whether two rows of the (n x 3) id array ``rows`` (ids below ``count``) are equal:
    one int64 key per row sorted where the ids fit in 21 bits, else a sort of the rows."""
    import numpy as np

    if count <= 1 << 21:
        keys = np.sort((rows[:, 0] << 42) | (rows[:, 1] << 21) | rows[:, 2])
        return bool(np.any(keys[1:] == keys[:-1]))
    ordered = rows[np.lexsort(rows.T[::-1])]
    return bool(np.any((ordered[1:] == ordered[:-1]).all(axis=1)))


def _canonical_rows(tetrahedra: Any) -> Any:
    """Each row as ``canonical_tetrahedron``: the even permutation starting at its smallest
    id, the other three rotated to start at their smallest."""
    import numpy as np

    smallest = np.argmin(tetrahedra, axis=1)
    # the even permutation that brings position p first: (a b c d), (b a d c), (c d a b),
    # (d c b a)
    evens = np.array([[0, 1, 2, 3], [1, 0, 3, 2], [2, 3, 0, 1], [3, 2, 1, 0]])
    moved = np.take_along_axis(tetrahedra, evens[smallest], axis=1)
    rest = _rotate_to_smallest(moved[:, 1:])
    return np.concatenate((moved[:, :1], rest), axis=1)
