"""Persistent tetrahedral meshes: the :class:`Mesh3` snapshot value and its queries.

A :class:`Mesh3` is immutable; its tables are persistent hash maps (``immutables.Map``), so
a step that changes k tetrahedra builds the next snapshot in O(k log n) and shares the
rest.  Vertices are numbered by insertion order.  Adjacency is a *half-face* map, the 3D
analogue of :class:`~geomexact.mesh2d.snapshot.Mesh2`'s half-edges: each positively
oriented tetrahedron (a, b, c, d) contributes its four faces, each oriented so that the
tetrahedron's fourth vertex (the *apex*) lies on its positive side (``orient3d(face,
apex) > 0``), keyed by the face rotated to start at its smallest id.  An interior face
appears twice, with opposite orientations; a boundary face once.
Model, digest and invariants: ``specs/mesh3d.md``.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from itertools import chain
from typing import TYPE_CHECKING, Any, TypeAlias

import attrs
import immutables

from geomexact.kernel import digest as _digest
from geomexact.kernel.derived import Derived
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point3
from geomexact.trace.protocols import kind_of
from geomexact.trace.recording import MAX_VERTICES as MAX_VERTICES
from geomexact.trace.sourced_snapshot import SourcedSnapshot

if TYPE_CHECKING:
    from geomexact.mesh3d.transient import Transient3

Tetrahedron: TypeAlias = tuple[int, int, int, int]
Face: TypeAlias = tuple[int, int, int]
Edge: TypeAlias = tuple[int, int]



def canonical_face(a: int, b: int, c: int) -> Face:
    """The rotation of the oriented face (a, b, c) that starts at its smallest id."""
    if a < b and a < c:
        return a, b, c
    if b < c:
        return b, c, a
    return c, a, b


def canonical_tetrahedron(a: int, b: int, c: int, d: int) -> Tetrahedron:
    """The even permutation of (a, b, c, d) (the same orientation) that starts at its
    smallest id, its other three rotated to start at their smallest."""
    if a < b and a < c and a < d:
        return (a, *canonical_face(b, c, d))
    if b < c and b < d:
        return (b, *canonical_face(a, d, c))  # (b, a, d, c) is even
    if c < d:
        return (c, *canonical_face(d, a, b))  # (c, d, a, b) is even
    return (d, *canonical_face(c, b, a))  # (d, c, b, a) is even


def tetrahedron_faces(a: int, b: int, c: int, d: int) -> tuple[tuple[Face, int], ...]:
    """The four (canonical oriented face, apex) pairs of the positive tetrahedron abcd:
    each face oriented so that its apex is on its positive side (the face seen
    counter-clockwise from inside the tetrahedron)."""
    return (
        (canonical_face(a, b, c), d),
        (canonical_face(a, c, d), b),
        (canonical_face(a, d, b), c),
        (canonical_face(b, d, c), a),
    )


def opposite_face(face: Face) -> Face:
    """The same triangle with the other orientation (canonical)."""
    a, b, c = face
    return canonical_face(a, c, b)


def undirected(u: int, v: int) -> Edge:
    """The edge {u, v} as the pair (min, max)."""
    return (u, v) if u < v else (v, u)


@attrs.frozen(slots=True, eq=False)
class FaceSource:
    """The content of a :class:`Mesh3`'s tables as arrays, as a bulk builder leaves them:
    a snapshot given one builds its persistent tables from it on first use.

    - ``points``: the :class:`Point3` of each vertex id 0..n-1;
    - ``faces``: (F x 3) int64 canonical oriented faces, one per row;
    - ``apexes``: (F,) int64, the apex of each face;
    - ``tetrahedra``: the (T x 4) canonical tetrahedra, sorted and read-only, when the
      builder has them (:meth:`Mesh3.tetrahedron_array`), else None.

    Each vertex's hint is the first face (in row order) that contains it.
    """

    points: Sequence[Point3]
    faces: Any
    apexes: Any
    tetrahedra: Any = None

    def tables(self) -> tuple[immutables.Map[int, Point3], immutables.Map[Face, int],
                              immutables.Map[int, Face]]:
        """(vertices, faces, hints) as persistent maps."""
        import numpy as np

        face_list = list(map(tuple, self.faces.tolist()))
        table: immutables.Map[Face, int] = immutables.Map(
            zip(face_list, self.apexes.tolist(), strict=True))
        used, first = np.unique(self.faces.ravel(), return_index=True)
        hints: immutables.Map[int, Face] = immutables.Map(
            zip(used.tolist(), (face_list[i] for i in (first // 3).tolist()), strict=True))
        return immutables.Map(enumerate(self.points)), table, hints


_Tables3: TypeAlias = tuple[immutables.Map[int, Point3], immutables.Map[Face, int],
                           immutables.Map[int, Face]]


@attrs.frozen(slots=True, eq=False)
class Mesh3(SourcedSnapshot[Point3, _Tables3]):
    """An immutable tetrahedral mesh with exact rational vertices.

    Tables (persistent maps):

    - ``vertices``: id -> :class:`Point3`, ids 0..n-1 in insertion order;
    - ``faces``: canonical oriented face -> apex, four per positive tetrahedron;
    - ``hints``: vertex -> a face key containing it (to walk its star; absent for a vertex
      in no tetrahedron);

    plus ``tetrahedron_count`` and the content ``digest`` (the sum of the vertex hashes and
    the tetrahedra's cell hashes, as in 2D).
    """

    # the three tables are built on first use (kept in ``_derived``) when the snapshot was
    # given a ``source`` (a bulk builder's arrays) instead: an octree run that only writes
    # its mesh never pays for the million-entry face map
    _vertices: immutables.Map[int, Point3] | None
    _faces: immutables.Map[Face, int] | None
    _hints: immutables.Map[int, Face] | None
    tetrahedron_count: int
    digest: int
    _source: FaceSource | None = attrs.field(default=None, kw_only=True, repr=False)
    """The arrays the tables are built from while they are None (:class:`FaceSource`)."""
    _derived: Derived = attrs.field(init=False, factory=Derived, repr=False)
    """The tables built from ``source`` and the read-only arrays derived from them
    (:class:`~geomexact.kernel.derived.Derived`): never content, never compared."""

    # -- tables (``vertices``: :class:`SourcedSnapshot`) ---------------------------------
    @property
    def faces(self) -> immutables.Map[Face, int]:
        """Canonical oriented face -> apex."""
        table = self._faces
        return self._built()[1] if table is None else table

    @property
    def hints(self) -> immutables.Map[int, Face]:
        """Vertex -> a face key containing it."""
        table = self._hints
        return self._built()[2] if table is None else table

    @property
    def source(self) -> FaceSource | None:
        """The arrays this snapshot's tables come from, while they are not built yet."""
        if self._faces is not None or self._derived.known("tables"):
            return None
        return self._source

    # -- sizes and identity (``vertex_count``, ``digest_text``: :class:`SourcedSnapshot`)
    def transient(self, *, batch: bool = False) -> Transient3:
        """A batch builder on this snapshot (the snapshot itself never changes)."""
        transient: Transient3 = kind_of(Mesh3).transient(self, batch=batch)
        return transient

    # -- queries (``point``, ``point_list``: :class:`SourcedSnapshot`) ------------------
    def apex(self, a: int, b: int, c: int) -> int | None:
        """The apex of the tetrahedron on the positive side of the oriented face abc."""
        return self.faces.get(canonical_face(a, b, c))

    def iter_tetrahedra(self) -> Iterator[Tetrahedron]:
        """Every tetrahedron once, canonical, in table order (for sums and checks)."""
        for (a, b, c), d in self.faces.items():
            if d < a and d < b and d < c:  # the face opposite the smallest vertex
                yield canonical_tetrahedron(a, b, c, d)

    def tetrahedra(self) -> list[Tetrahedron]:
        """Every tetrahedron, canonical, sorted."""
        return [tuple(row) for row in self.tetrahedron_array().tolist()]  # type: ignore[misc]

    def cells(self) -> list[Tetrahedron]:
        """The cells (:meth:`tetrahedra`): what the trace tools compare between steps."""
        return self.tetrahedra()

    def tetrahedron_array(self) -> Any:
        """Every tetrahedron, canonical, sorted, as a read-only (T x 4) int64 numpy array
        (one pass over the face table, vectorised; kept once computed)."""
        return self._derived.get("tetrahedra", self._sorted_tetrahedra)

    def _sorted_tetrahedra(self) -> Any:
        import numpy as np

        if self._source is not None and self._source.tetrahedra is not None:
            return self._source.tetrahedra
        faces, apexes = self._face_arrays()
        # the face opposite the smallest vertex: (a, b, c) -> d with d smallest; canonical
        # is (d, *canonical_face(c, b, a)) = (d, a, c, b) since a is the face's smallest
        mask = apexes < faces[:, 0]
        rows = np.column_stack((apexes[mask], faces[mask][:, [0, 2, 1]])).reshape(-1, 4)
        rows = rows[np.lexsort(rows.T[::-1])]
        rows.setflags(write=False)
        return rows

    def _face_arrays(self) -> tuple[Any, Any]:
        """The face table as read-only arrays: (F x 3) canonical faces and their (F,)
        apexes, in no particular order (kept once computed)."""
        arrays: tuple[Any, Any] = self._derived.get("faces", self._face_table_arrays)
        return arrays

    def _face_table_arrays(self) -> tuple[Any, Any]:
        import numpy as np

        source = self.source
        if source is not None:
            return source.faces, source.apexes
        count = len(self.faces)
        faces = np.fromiter(chain.from_iterable(self.faces.keys()), dtype=np.int64,
                            count=3 * count).reshape(-1, 3)
        apexes = np.fromiter(self.faces.values(), dtype=np.int64, count=count)
        faces.setflags(write=False)
        apexes.setflags(write=False)
        return faces, apexes

    def has_tetrahedron(self, tetrahedron: Tetrahedron) -> bool:
        a, b, c, d = tetrahedron
        return self.faces.get(canonical_face(a, b, c)) == d

    def boundary_faces(self) -> list[Face]:
        """The faces with no tetrahedron on their negative side, oriented outward
        (counter-clockwise seen from outside: the reversal of the stored face), sorted."""
        import numpy as np

        faces, _ = self._face_arrays()
        if not len(faces):
            return []
        opposite = faces[:, [0, 2, 1]]  # still canonical: a stays the smallest
        order = np.lexsort(faces.T[::-1])
        known = faces[order]
        at = _row_search(known, opposite)
        found = (at < len(known)) & (known[np.minimum(at, len(known) - 1)] == opposite).all(
            axis=1)
        outward = opposite[~found]
        return [tuple(row) for row in  # type: ignore[misc]
                outward[np.lexsort(outward.T[::-1])].tolist()]

    def interior_faces(self) -> list[Face]:
        """Each face shared by two tetrahedra once, as its sorted vertex triple, sorted
        (one vectorised pass over the face table)."""
        import numpy as np

        faces, _ = self._face_arrays()
        if not len(faces):
            return []
        opposite = faces[:, [0, 2, 1]]  # still canonical: a stays the smallest
        known = faces[np.lexsort(faces.T[::-1])]
        at = _row_search(known, opposite)
        found = (at < len(known)) & (known[np.minimum(at, len(known) - 1)] == opposite).all(
            axis=1)
        # each shared face once: the orientation whose second vertex is the smaller
        shared = np.sort(faces[found & (faces[:, 1] < faces[:, 2])], axis=1)
        return [tuple(row) for row in  # type: ignore[misc]
                shared[np.lexsort(shared.T[::-1])].tolist()]

    def edges(self) -> list[Edge]:
        """Every edge (min, max), sorted (one vectorised pass over the face table)."""
        import numpy as np

        faces, _ = self._face_arrays()
        if not len(faces):
            return []
        pairs = np.concatenate((faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]))
        pairs = np.unique(np.sort(pairs, axis=1), axis=0)
        return [tuple(row) for row in pairs.tolist()]  # type: ignore[misc]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Mesh3):
            return NotImplemented
        return (
            self.digest == other.digest
            and self.tetrahedron_count == other.tetrahedron_count
            and self.vertices == other.vertices
            and self.faces == other.faces
        )

    def __hash__(self) -> int:
        return hash(self.digest)

    def __repr__(self) -> str:
        return (
            f"Mesh3(vertices={self.vertex_count}, tetrahedra={self.tetrahedron_count}, "
            f"digest={self.digest_text})"
        )


def _row_search(sorted_rows: Any, rows: Any) -> Any:
    """For each of ``rows`` (N x 3), the index where it would be inserted into the
    lexicographically sorted ``sorted_rows`` (M x 3) to keep them sorted."""
    import numpy as np

    top = int(max(sorted_rows.max(initial=0), rows.max(initial=0))) + 1
    if top < 1 << 21:  # three ids in one int64, in the same order
        def key(array: Any) -> Any:
            return (array[:, 0] * top + array[:, 1]) * top + array[:, 2]

        return np.searchsorted(key(sorted_rows), key(rows))
    # a row's three ids as one structured value compare lexicographically
    kind = np.dtype([("a", np.int64), ("b", np.int64), ("c", np.int64)])
    table = np.ascontiguousarray(sorted_rows).view(kind).ravel()
    wanted = np.ascontiguousarray(rows).view(kind).ravel()
    return np.searchsorted(table, wanted)


def empty_mesh3() -> Mesh3:
    """The mesh with no vertices and no tetrahedra."""
    return Mesh3(
        vertices=immutables.Map(),
        faces=immutables.Map(),
        hints=immutables.Map(),
        tetrahedron_count=0,
        digest=0,
    )


def full_digest3(mesh: Mesh3) -> int:
    """The digest recomputed from the content (``validate`` compares it with ``digest``)."""
    total = 0
    for vertex, point in mesh.vertices.items():
        total = _digest.combine(total, _digest.vertex_hash(vertex, point[:3]))
    for tetrahedron in mesh.iter_tetrahedra():
        total = _digest.combine(total, _digest.cell_hash(tetrahedron))
    return total


def signed_volume6(a: Point3, b: Point3, c: Point3, d: Point3) -> Rational:
    """Six times the signed volume of abcd, exactly: ``det[b - a, c - a, d - a]``
    (positive for a positively oriented tetrahedron, as ``orient3d``)."""
    bx, by, bz = b.x - a.x, b.y - a.y, b.z - a.z
    cx, cy, cz = c.x - a.x, c.y - a.y, c.z - a.z
    dx, dy, dz = d.x - a.x, d.y - a.y, d.z - a.z
    return (  # type: ignore[no-any-return]
        bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx)
    )
