"""Quality improvement by exact flips (issue 24, item 4; ``specs/quality_improvement.md``).

A :class:`QualityCriterion` says which tetrahedra fail (minimum dihedral angle and/or
radius ratio below a threshold); :func:`improve_quality` removes failing tetrahedra that
meet a region by Joe's transformations (``flip23``, ``flip32``, ``flip44``; ``flip22``
only with ``boundary=True``), each applied by the reference step
:func:`~geomexact.mesh3d.ops.flip_in` (exact orient3d: an invalid flip is never made) and
recorded in the trace, and only when it raises the smallest quality over the tetrahedra it
replaces (hill climbing, Klingner and Shewchuk 2007).  The decision compares qualities in
doubles; the steps, the mesh and its volume are exact.

Order (deterministic, no hash order): each round takes the failing tetrahedra that meet
the region, worst first, ties by their sorted vertex ids; for each one still in the mesh
the candidate flips that remove it are enumerated (its four faces, then the faces around
its edges that have three tetrahedra, each classified exactly; with ``edge_removal``
the removal of each of its interior edges with 4 to 7 tetrahedra around, as the fan from
each ring vertex: flip23s then a flip32, tried on a fresh transient and dropped when a
step is refused), the one whose new
tetrahedra have the largest smallest quality is applied when that beats the replaced
tetrahedra's smallest quality (ties: the first candidate in (op, sorted face) order).
Rounds repeat until one applies no flip or ``max_rounds`` is reached.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from itertools import combinations, pairwise
from typing import Final

import attrs
import numpy as np

from geomexact._version import __version__
from geomexact.errors import PreconditionError
from geomexact.kernel.points import Point3
from geomexact.kernel.vectors import cross3, dot3, sub3
from geomexact.mesh3d.ops import (
    FLIP_NAMES,
    FLIP_OF_KIND,
    FaceConfiguration,
    FaceKind,
    FlipTally,
    classify_face_in,
    flip_in,
    flippable_kinds,
    made_tetrahedra,
    oriented_third,
)
from geomexact.mesh3d.quality import dihedral_angles
from geomexact.mesh3d.snapshot import Face, Mesh3
from geomexact.mesh3d.transient import Transient3
from geomexact.trace.record import Trace
from geomexact.trace.step import Step

__all__ = [
    "FLIP_NAMES",
    "QualityCriterion",
    "QualityImprovement",
    "Region",
    "improve_quality",
    "tetrahedron_measures",
]


Region = Callable[[tuple[Point3, ...]], bool]
"""Whether a tetrahedron (its four points, sorted by vertex id) meets the region."""

Key = tuple[int, int, int, int]
"""A tetrahedron as its sorted vertex ids (the key of the quality cache)."""


@attrs.frozen(slots=True)
class QualityCriterion:
    """A tetrahedron fails when its smallest dihedral angle is below ``min_dihedral``
    (degrees) or its radius ratio (3 inradius / circumradius: 1 for the regular
    tetrahedron, 0 when flat) is below ``min_radius_ratio``; None: not checked.  At least
    one is given."""

    min_dihedral: float | None = None
    min_radius_ratio: float | None = None

    def __attrs_post_init__(self) -> None:
        if self.min_dihedral is None and self.min_radius_ratio is None:
            raise PreconditionError("QualityCriterion", "give min_dihedral and/or "
                                    "min_radius_ratio")
        if self.min_dihedral is not None and not 0 < self.min_dihedral < 70.6:
            raise PreconditionError("QualityCriterion", "min_dihedral is in degrees, "
                                    f"between 0 and 70.5 (regular), not {self.min_dihedral}")
        if self.min_radius_ratio is not None and not 0 < self.min_radius_ratio <= 1:
            raise PreconditionError("QualityCriterion", "min_radius_ratio is in (0, 1], not "
                                    f"{self.min_radius_ratio}")

    def quality(self, min_dihedral: float, radius_ratio: float) -> float:
        """The tetrahedron's quality relative to the criterion: the smallest of each
        measure divided by its threshold (< 1: it fails)."""
        values = []
        if self.min_dihedral is not None:
            values.append(min_dihedral / self.min_dihedral)
        if self.min_radius_ratio is not None:
            values.append(radius_ratio / self.min_radius_ratio)
        return min(values)


@attrs.frozen(slots=True)
class QualityImprovement(FlipTally):
    """What :func:`improve_quality` did: the ``mesh`` after it; the ``trace`` of its steps
    from the input (None when not recorded); the flips applied of each kind (FLIP_NAMES
    order); the rounds run; the smallest dihedral angle (degrees) over the whole mesh and
    the number of failing tetrahedra in the region, before and after; the seconds taken."""

    mesh: Mesh3
    trace: Trace | None
    flips: tuple[int, int, int, int]
    rounds: int
    worst_before: float | None
    worst_after: float | None
    failing_before: int
    failing_after: int
    edge_removals: int
    seconds: float


def tetrahedron_measures(a: Point3, b: Point3, c: Point3, d: Point3) -> tuple[float, float]:
    """(smallest dihedral angle in degrees, radius ratio) of the tetrahedron abcd, in
    doubles from the points' doubles (a fixed order of operations: the same value for the
    same points in any process).  A flat one in doubles gives (0, 0)."""
    p = ((a.fx, a.fy, a.fz), (b.fx, b.fy, b.fz), (c.fx, c.fy, c.fz), (d.fx, d.fy, d.fz))
    # face normals (unnormalised), face k opposite vertex k, pointing outward or inward
    # consistently: the dihedral angle at edge (i, j) is pi minus the angle between the
    # outward normals of the two faces containing it
    normals = []
    areas = []
    for k in range(4):
        i, j, m = (n for n in range(4) if n != k)
        u = sub3(p[j], p[i])
        v = sub3(p[m], p[i])
        normal = cross3(u, v)
        # orient outward: away from vertex k
        if dot3(normal, sub3(p[k], p[i])) > 0:
            normal = (-normal[0], -normal[1], -normal[2])
        length = math.sqrt(dot3(normal, normal))
        normals.append(normal)
        areas.append(length)
    if min(areas) == 0.0:
        return 0.0, 0.0
    largest_cosine = -1.0
    for k, m in combinations(range(4), 2):  # faces k and m share the edge opposite them
        cosine = -dot3(normals[k], normals[m]) / (areas[k] * areas[m])
        largest_cosine = max(largest_cosine, cosine)
    smallest_angle = math.degrees(math.acos(min(1.0, max(-1.0, largest_cosine))))
    b0, c0, d0 = sub3(p[1], p[0]), sub3(p[2], p[0]), sub3(p[3], p[0])
    triple = dot3(b0, cross3(c0, d0))  # 6 volume (signed)
    if triple == 0.0:
        return 0.0, 0.0
    weights = (dot3(b0, b0), dot3(c0, c0), dot3(d0, d0))
    terms = (cross3(c0, d0), cross3(d0, b0), cross3(b0, c0))
    cx, cy, cz = (weights[0] * terms[0][n] + weights[1] * terms[1][n]
                  + weights[2] * terms[2][n] for n in range(3))
    centre = (cx, cy, cz)
    circumradius = math.sqrt(dot3(centre, centre)) / abs(2.0 * triple)
    # inradius = 3 V / total area = (|triple| / 2) / (sum of |normal| / 2)
    inradius = abs(triple) / sum(areas)
    if not 0.0 < circumradius < math.inf:  # flat in doubles: the centre cancels out
        return smallest_angle, 0.0
    return smallest_angle, min(1.0, 3.0 * inradius / circumradius)


class _Qualities:
    """The criterion's quality of tetrahedra, by sorted vertex ids, computed once each."""

    __slots__ = ("_cache", "_criterion", "_mesh")

    def __init__(self, mesh: Mesh3, criterion: QualityCriterion) -> None:
        self._mesh = mesh  # the points: flips add none
        self._criterion = criterion
        self._cache: dict[Key, float] = {}

    def __call__(self, vertices: Iterable[int]) -> float:
        key: Key = tuple(sorted(vertices))  # type: ignore[assignment]
        value = self._cache.get(key)
        if value is None:
            points = [self._mesh.point(vertex) for vertex in key]
            value = self._criterion.quality(*tetrahedron_measures(*points))
            self._cache[key] = value
        return value


def _replaced_and_made(t: Transient3, configuration: FaceConfiguration
                       ) -> tuple[list[Key], list[Key]]:
    """The tetrahedra a flip of ``configuration`` removes and those it makes (sorted
    vertex ids), as :func:`~geomexact.mesh3d.ops.flip_in` would."""
    a, b, c = configuration.face
    d, e = configuration.d, configuration.e
    kind = configuration.kind

    def key(*vertices: int) -> Key:
        return tuple(sorted(vertices))  # type: ignore[return-value]

    made = [key(*tetrahedron) for tetrahedron in made_tetrahedra(configuration)]
    if kind == FaceKind.T23:
        return [key(a, b, c, d), key(a, b, c, e)], made
    assert configuration.edge is not None
    u, v = configuration.edge
    if kind == FaceKind.T32:
        return [key(a, b, c, d), key(a, b, c, e), key(u, v, d, e)], made
    return _around(t, u, v, oriented_third((a, b, c), u, v)), made


def _exists(t: Transient3, key: Key) -> bool:
    a, b, c, d = key
    return t.apex(a, b, c) == d or t.apex(a, c, b) == d


def _interior(t: Transient3, face: Face) -> bool:
    a, b, c = face
    return t.apex(a, b, c) is not None and t.apex(a, c, b) is not None


def _ring(t: Transient3, u: int, v: int, w: int) -> tuple[list[int], bool]:
    """The vertices around the edge uv, in order from the third vertex ``w`` of a
    tetrahedron on it, and whether they close a ring (an interior edge) — walked across
    the faces u v x of the face table (cheaper than a vertex's star)."""
    ring = [w]
    x = t.apex(u, v, w)
    while x is not None and x != w:
        ring.append(x)
        x = t.apex(u, v, x)
    if x == w:
        return ring, True
    x = t.apex(u, w, v)  # open: walk the other way from w
    while x is not None:
        ring.insert(0, x)
        x = t.apex(u, x, v)
    return ring, False


def _around(t: Transient3, u: int, v: int, w: int) -> list[Key]:
    """The tetrahedra on the edge uv (sorted vertex ids), from the third vertex ``w``."""
    ring, closed = _ring(t, u, v, w)
    pairs = list(pairwise(ring))
    if closed:
        pairs.append((ring[-1], ring[0]))
    return [tuple(sorted((u, v, x, y))) for x, y in pairs]  # type: ignore[misc]


def _candidate_faces(t: Transient3, tetrahedron: Key) -> list[Face]:
    """The interior faces whose flip could remove ``tetrahedron``: its own four, then the
    faces around each of its edges with exactly three tetrahedra in a closed ring; sorted,
    once each."""
    faces: set[Face] = set()
    for face in combinations(tetrahedron, 3):
        if _interior(t, face):  # type: ignore[arg-type]
            faces.add(face)  # type: ignore[arg-type]
    for u, v in combinations(tetrahedron, 2):
        w = next(x for x in tetrahedron if x != u and x != v)
        ring, closed = _ring(t, u, v, w)
        if closed and len(ring) == 3:
            faces.update(tuple(sorted((u, v, x))) for x in ring)  # type: ignore[misc]
    return sorted(faces)


Move = tuple[float, tuple[tuple[str, Face], ...], list[Key]]
"""A candidate: the smallest quality of the tetrahedra it makes, its flip steps (op,
sorted face) and the tetrahedra it removes."""

MAX_RING: Final = 7
"""Edge removal is tried on interior edges with 4 to this many tetrahedra around."""


def _fan(u: int, v: int, ring: list[int], apex: int) -> tuple[tuple[tuple[str, Face], ...],
                                                               list[Key]]:
    """Edge removal of the interior edge uv whose closed ``ring`` is ring, replaced by the
    fan of triangles from ``ring[apex]``: the flip23 steps across u v p1 … u v p(n-3) then
    the flip32 at u v p0 (ring rotated to start at the apex), and the tetrahedra made."""
    p = ring[apex:] + ring[:apex]
    steps: list[tuple[str, Face]] = [
        ("flip23", _sorted3(u, v, p[j])) for j in range(1, len(p) - 2)]
    steps.append(("flip32", _sorted3(u, v, p[0])))
    made = [tuple(sorted((p[0], p[j], p[j + 1], w)))
            for j in range(1, len(p) - 1) for w in (u, v)]
    return tuple(steps), made  # type: ignore[return-value]


def _sorted3(a: int, b: int, c: int) -> Face:
    x, y, z = sorted((a, b, c))
    return x, y, z


def _moves(t: Transient3, tetrahedron: Key, quality: _Qualities,
           allowed: frozenset[FaceKind], edge_removal: bool) -> list[Move]:
    """The moves that remove ``tetrahedron`` and raise the smallest quality of the
    tetrahedra they replace (module docstring), best first (ties: in the order found)."""
    found: list[Move] = []
    seen: set[tuple[Key, ...]] = set()
    for face in _candidate_faces(t, tetrahedron):
        configuration = classify_face_in(t, face)
        if configuration.kind not in allowed:
            continue
        removed, made = _replaced_and_made(t, configuration)
        if tetrahedron not in removed:
            continue
        identity = tuple(sorted(made))
        if identity in seen:  # the same flip seen from another face
            continue
        seen.add(identity)
        before = min(quality(k) for k in removed)
        after = min(quality(k) for k in made)
        if after > before:
            found.append((after, ((FLIP_OF_KIND[configuration.kind], face),), removed))
    if edge_removal:
        for u, v in combinations(tetrahedron, 2):
            w = next(x for x in tetrahedron if x != u and x != v)
            ring, closed = _ring(t, u, v, w)
            if not closed or not 4 <= len(ring) <= MAX_RING:
                continue
            removed = _around(t, u, v, w)
            before = min(quality(k) for k in removed)
            for apex in range(len(ring)):
                steps, made = _fan(u, v, ring, apex)
                identity = tuple(sorted(made))
                if identity in seen:
                    continue
                seen.add(identity)
                after = min(quality(k) for k in made)
                if after > before:
                    found.append((after, steps, removed))
    order = sorted(range(len(found)), key=lambda index: (-found[index][0], index))
    return [found[index] for index in order]


def _all_tetrahedra(t: Transient3) -> list[Key]:
    """Every tetrahedron of the transient, as sorted vertex ids, sorted."""
    found = []
    for (a, b, c), d in t.faces_snapshot().items():
        if d < a and d < b and d < c:
            found.append(tuple(sorted((a, b, c, d))))
    return sorted(found)  # type: ignore[arg-type]


def _worst_dihedral(mesh: Mesh3) -> float | None:
    if mesh.tetrahedron_count == 0:
        return None
    xyz = np.array([(p.fx, p.fy, p.fz) for p in mesh.point_list()], dtype=np.float64)
    return float(dihedral_angles(xyz, mesh.tetrahedron_array()).min())


def improve_quality(
    mesh: Mesh3,
    criterion: QualityCriterion,
    *,
    region: Region | None = None,
    max_rounds: int = 10,
    boundary: bool = False,
    edge_removal: bool = True,
    trace: bool = True,
) -> QualityImprovement:
    """Flip failing tetrahedra of ``mesh`` that meet ``region`` (all when None) away
    while that raises the quality of the tetrahedra replaced (module docstring), for at
    most ``max_rounds`` rounds.  ``boundary=False`` (default) keeps every boundary face:
    only flip23, flip32 and flip44 (which change no boundary face) are made; True also
    allows flip22 (two coplanar boundary faces re-triangulated: the boundary as a point set
    and its vertices are kept).  ``mesh`` is unchanged; the result's trace replays on it."""
    if max_rounds < 0:
        raise PreconditionError("improve_quality", f"max_rounds >= 0, not {max_rounds}")
    began = time.perf_counter()
    kinds = flippable_kinds(boundary)
    t = Transient3(mesh)
    steps: list[Step] = []
    digests: list[int] = []
    quality = _Qualities(mesh, criterion)

    def meets(key: Key) -> bool:
        return region is None or bool(region(tuple(mesh.point(v) for v in key)))

    def failing() -> list[Key]:
        found = [(quality(key), key) for key in _all_tetrahedra(t)
                 if quality(key) < 1.0 and meets(key)]
        return [key for _, key in sorted(found)]

    def attempt(move: Move) -> bool:
        """Make the move's steps; a sequence whose intermediate flip is refused (its face
        not of that kind) is given up, the mesh as before."""
        nonlocal t
        moves = move[1]
        if len(moves) == 1:
            op, face = moves[0]
            flip_in(t, op, face)  # classified just before: it applies
            return True
        base = t.seal()
        steps.extend(t.steps)
        digests.extend(t.step_digests)
        trial = Transient3(base)
        try:
            for op, face in moves:
                flip_in(trial, op, face)
        except PreconditionError:
            t = Transient3(base)
            return False
        t = trial
        return True

    counts = dict.fromkeys(FLIP_NAMES, 0)
    removals = 0
    worst_before = _worst_dihedral(mesh)
    queue = failing()
    failing_before = len(queue)
    rounds = 0
    while queue and rounds < max_rounds:
        rounds += 1
        changed = 0
        for key in queue:
            if not _exists(t, key):
                continue  # flipped away this round
            for move in _moves(t, key, quality, kinds, edge_removal):
                if attempt(move):
                    for op, _ in move[1]:
                        counts[op] += 1
                    removals += len(move[1]) > 1
                    changed += 1
                    break
        if not changed:
            break
        queue = failing()
    failing_after = len(queue)  # the list after the last round (current)
    steps.extend(t.steps)
    digests.extend(t.step_digests)
    recorded = Trace(mesh.digest, steps, digests, {
        "operation": "improve_quality", "min_dihedral": criterion.min_dihedral,
        "min_radius_ratio": criterion.min_radius_ratio, "boundary": boundary,
        "edge_removal": edge_removal, "max_rounds": max_rounds}, __version__,
    ) if trace else None
    result = t.seal()
    return QualityImprovement(
        mesh=result,
        trace=recorded,
        flips=(counts["flip23"], counts["flip32"], counts["flip22"], counts["flip44"]),
        rounds=rounds,
        worst_before=worst_before,
        worst_after=_worst_dihedral(result),
        failing_before=failing_before,
        failing_after=failing_after,
        edge_removals=removals,
        seconds=time.perf_counter() - began,
    )
