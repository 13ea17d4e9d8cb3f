"""Joe's local transformations applied toward Delaunay (``specs/cuboid.md``, "Improvement").

Every interior face is queued (sorted vertex triples, sorted; first in, first out; a face
already waiting is not queued twice).  A face taken from the queue that is still an
interior face, whose configuration is T23, T32, T44 (or T22 with
``allow_boundary_flips``) and whose far apex is strictly inside the circumsphere (exact
insphere; ties never flip) is transformed by ``flip_in`` (so it is recorded), and the faces
of the new tetrahedra (sorted) join the queue.  When the queue is empty the interior faces
are scanned: the transformable ones that still fail their test (a flip elsewhere can make
an N32 or N44 face transformable) start the next round, in sorted order.  The queue
empties after finitely many flips (``specs/flips3d.md``: the lifted triangulation moves
strictly down).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable
from itertools import combinations
from typing import Final

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.predicate_results import SphereLocation
from geomexact.kernel.predicates3d import insphere
from geomexact.mesh3d.ops import (
    FLIP_NAMES,
    FLIP_OF_KIND,
    FaceConfiguration,
    FlipTally,
    classify_face_in,
    flip_in,
    flippable_kinds,
    made_tetrahedra,
)
from geomexact.mesh3d.snapshot import Face, Mesh3
from geomexact.mesh3d.transient import Transient3

__all__ = ["FLIP_NAMES", "ImprovementReport", "failing_faces_in", "improve", "improve_in",
           "interior_faces_in", "is_failing_in"]

MAX_FLIPS: Final = 1_000_000
"""A guard only: the flips terminate (the lifted argument); this many means a bug."""


@attrs.frozen(slots=True)
class ImprovementReport(FlipTally):
    """What an improvement did: the flips applied of each kind (``flips[name]`` in
    FLIP_NAMES order), the number of rounds (1 when the first queue sufficed) and the
    configuration kinds of the faces that still fail their sphere test, sorted by name
    (empty: the mesh is Delaunay)."""

    flips: tuple[int, int, int, int]
    rounds: int
    failing_kinds: tuple[str, ...]


def interior_faces_in(t: Transient3) -> list[Face]:
    """The interior faces of the transient's mesh: sorted vertex triples, sorted."""
    faces = t.faces_snapshot()
    return sorted(
        (a, b, c) for (a, b, c) in faces
        if a < b < c and (a, c, b) in faces
    )


def is_failing_in(t: Transient3, face: Face) -> bool:
    """True when the interior face ``face`` (a sorted triple) is locally non-Delaunay:
    with abcd and acbe its tetrahedra, e strictly inside the sphere of abcd."""
    a, b, c = face
    d, e = t.apex(a, b, c), t.apex(a, c, b)
    if d is None or e is None:
        raise PreconditionError("improve", f"{face} is not an interior face")
    points = (t.point(a), t.point(b), t.point(c), t.point(d), t.point(e))
    return insphere(*points) == SphereLocation.INSIDE


def failing_faces_in(t: Transient3) -> list[FaceConfiguration]:
    """The configuration of every locally non-Delaunay interior face, by sorted face."""
    return [classify_face_in(t, face) for face in interior_faces_in(t) if is_failing_in(t, face)]


def _faces_of(tetrahedra: Iterable[tuple[int, ...]]) -> list[Face]:
    found = {tuple(sorted(face)) for tetrahedron in tetrahedra
             for face in combinations(tetrahedron, 3)}
    return sorted(found)  # type: ignore[arg-type]


def improve_in(t: Transient3, *, allow_boundary_flips: bool = False) -> ImprovementReport:
    """Apply Joe's transformations to ``t`` until no transformable face fails its sphere
    test (T22, which changes the box's boundary, only with ``allow_boundary_flips``);
    every flip is recorded on ``t``.  The order is fixed (module docstring)."""
    flippable = flippable_kinds(allow_boundary_flips)
    counts = dict.fromkeys(FLIP_NAMES, 0)
    queue: deque[Face] = deque(interior_faces_in(t))
    pending = set(queue)
    rounds = 1
    while True:
        while queue:
            face = queue.popleft()
            pending.discard(face)
            a, b, c = face
            if t.apex(a, b, c) is None or t.apex(a, c, b) is None:
                continue  # flipped away
            if not is_failing_in(t, face):
                continue
            configuration = classify_face_in(t, face)
            if configuration.kind not in flippable:
                continue
            op = FLIP_OF_KIND[configuration.kind]
            flip_in(t, op, face)
            counts[op] += 1
            if sum(counts.values()) > MAX_FLIPS:  # pragma: no cover - a guard
                raise PreconditionError("improve", f"more than {MAX_FLIPS} flips")
            for new in _faces_of(made_tetrahedra(configuration)):
                if new not in pending:
                    pending.add(new)
                    queue.append(new)
        failing = failing_faces_in(t)
        again = [c.face for c in failing if c.kind in flippable]
        if not again:
            break
        rounds += 1
        queue.extend(again)
        pending.update(again)
    kinds = tuple(sorted({c.kind.value for c in failing}))
    return ImprovementReport(
        (counts["flip23"], counts["flip32"], counts["flip22"], counts["flip44"]),
        rounds, kinds,
    )


def improve(mesh: Mesh3, *, allow_boundary_flips: bool = False) -> tuple[Mesh3,
                                                                          ImprovementReport]:
    """The improved mesh (see :func:`improve_in`) and the report; ``mesh`` is unchanged."""
    t = mesh.transient()
    report = improve_in(t, allow_boundary_flips=allow_boundary_flips)
    return t.seal(), report

