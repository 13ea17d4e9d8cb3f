"""THE reference implementation of every 3D step: ``split_tetra`` and Joe's local
transformations ``flip23``, ``flip32``, ``flip22``, ``flip44``, with exact preconditions,
and the classification of an interior face that decides which one applies.

Each ``*_in`` function edits a :class:`~geomexact.mesh3d.transient.Transient3` and
records its :class:`~geomexact.trace.step.Step`; the pure functions (``split_tetra``,
``flip``) return a new :class:`~geomexact.mesh3d.snapshot.Mesh3`.  Definitions, tie rules
and the termination argument: ``specs/mesh3d.md`` and ``specs/flips3d.md``.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from types import MappingProxyType

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.points import midpoint3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.snapshot import Edge, Face, Mesh3, Tetrahedron, undirected
from geomexact.mesh3d.transient import Transient3
from geomexact.trace.protocols import apply_from, kind_of
from geomexact.trace.step import Step

__all__ = [
    "FLIP_NAMES",
    "FLIP_OPS",
    "OPERATIONS",
    "FaceConfiguration",
    "FaceKind",
    "FlipTally",
    "apply",
    "apply_in",
    "classify_face",
    "flip",
    "flip_in",
    "flippable_kinds",
    "made_tetrahedra",
    "split_tetra",
    "split_tetra_in",
]

_CCW = Orientation.COUNTERCLOCKWISE
_CW = Orientation.CLOCKWISE


class FaceKind(enum.Enum):
    """Joe's configurations of an interior face abc between tetrahedra abcd and acbe
    (``specs/flips3d.md``): T* are transformable, N* are not."""

    T23 = "T23"  # de crosses the interior of abc: 2 tetrahedra -> 3
    T32 = "T32"  # de passes beyond one edge ab, which has exactly 3 tetrahedra: 3 -> 2
    T22 = "T22"  # a, b, d, e coplanar, de crosses ab inside, faces abd, abe on the boundary
    T44 = "T44"  # as T22, but abd, abe interior, their tetrahedra abdf, abef share f: 4 -> 4
    N32 = "N32"  # as T32, but edge ab has more than 3 tetrahedra (or is on the boundary)
    N44 = "N44"  # as T22/T44 otherwise (one face boundary, or no common f)
    N40 = "N40"  # a, b, d, e coplanar but de meets line ab outside segment ab
    N30 = "N30"  # d, e and a vertex of abc collinear
    N20 = "N20"  # de passes beyond two edges of abc (beyond a vertex)


TRANSFORMABLE = frozenset({FaceKind.T23, FaceKind.T32, FaceKind.T22, FaceKind.T44})


@attrs.frozen(slots=True)
class FaceConfiguration:
    """The configuration of an interior face: its ``kind``; the face ``(a, b, c)``
    oriented with ``d`` on its positive side (tetrahedron abcd positive) and ``e`` on the
    other (acbe positive); ``edge``, the edge of abc that matters (the one de passes
    beyond for T32/N32/N40, the one de crosses for T22/T44/N44), else None; ``apex_f``,
    the common fourth vertex of T44."""

    kind: FaceKind
    face: Face
    d: int
    e: int
    edge: Edge | None = None
    apex_f: int | None = None

    @property
    def transformable(self) -> bool:
        return self.kind in TRANSFORMABLE


def _oriented(t: Transient3, a: int, b: int, c: int, d: int) -> tuple[int, int, int, int]:
    """(a, b, c, d) or (b, a, c, d), whichever is positive; flat is a PreconditionError
    (never reached from a valid classification)."""
    orientation = orient3d(t.point(a), t.point(b), t.point(c), t.point(d))
    if orientation == _CCW:
        return a, b, c, d
    if orientation == _CW:
        return b, a, c, d
    raise PreconditionError("flip", f"the new tetrahedron {(a, b, c, d)} would be flat")


def _interior_face(t: Transient3, op: str, face: Face) -> tuple[int, int, int, int, int]:
    """(a, b, c, d, e) of the interior face ``face`` (any order of its three ids): abcd
    and acbe its two positive tetrahedra, a, b, c in increasing id order or its reverse."""
    if len(set(face)) != 3:
        raise PreconditionError(op, f"{face} is not a face")
    a, b, c = sorted(face)
    d = t.apex(a, b, c)
    e = t.apex(a, c, b)
    if d is None or e is None:
        raise PreconditionError(op, f"{(a, b, c)} is not an interior face of the mesh")
    return a, b, c, d, e


def classify_face_in(t: Transient3, face: Face) -> FaceConfiguration:
    """Joe's configuration of the interior face ``face`` (exact orient3d signs)."""
    a, b, c, d, e = _interior_face(t, "classify_face", face)
    pa, pb, pc, pd, pe = (t.point(v) for v in (a, b, c, d, e))
    # "inner" sign of each edge: > 0 when the line de meets the plane of abc on the side
    # of that edge where the third vertex lies
    inner = {
        (a, b): -orient3d(pd, pe, pa, pb),
        (b, c): -orient3d(pd, pe, pb, pc),
        (c, a): -orient3d(pd, pe, pc, pa),
    }
    zeros = [edge for edge, s in inner.items() if s == 0]
    negatives = [edge for edge, s in inner.items() if s < 0]
    oriented = (a, b, c)
    if not zeros and not negatives:
        return FaceConfiguration(FaceKind.T23, oriented, d, e)
    if len(zeros) == 2:
        return FaceConfiguration(FaceKind.N30, oriented, d, e)
    if not zeros and len(negatives) == 2:
        return FaceConfiguration(FaceKind.N20, oriented, d, e)
    if len(zeros) == 1 and negatives:
        return FaceConfiguration(FaceKind.N40, oriented, d, e, undirected(*zeros[0]))
    if not zeros:  # one reflex edge
        u, v = negatives[0]
        around = t.around_edge(u, v)
        third = sorted((u, v, d, e))
        kind = FaceKind.T32 if len(around) == 3 and any(
            sorted(tetrahedron) == third for tetrahedron in around
        ) else FaceKind.N32
        return FaceConfiguration(kind, oriented, d, e, undirected(u, v))
    u, v = zeros[0]  # a, b, d, e coplanar; de crosses uv inside
    around = t.around_edge(u, v)
    edge = undirected(u, v)
    if len(around) == 2 and _is_boundary_edge_pair(t, u, v, d, e):
        return FaceConfiguration(FaceKind.T22, oriented, d, e, edge)
    if len(around) == 4:  # T44: the other two are uvdf and uvef, one f
        w = oriented_third(oriented, u, v)
        others = [set(tetrahedron) - {u, v} for tetrahedron in around if w not in tetrahedron]
        fs = set().union(*others) - {d, e}
        if len(others) == 2 and len(fs) == 1 and {d, *fs} in others and {e, *fs} in others:
            return FaceConfiguration(FaceKind.T44, oriented, d, e, edge, fs.pop())
    return FaceConfiguration(FaceKind.N44, oriented, d, e, edge)


def oriented_third(face: Face, u: int, v: int) -> int:
    """The vertex of ``face`` other than u and v."""
    return next(vertex for vertex in face if vertex != u and vertex != v)


def _is_boundary_edge_pair(t: Transient3, u: int, v: int, d: int, e: int) -> bool:
    """True when the faces uvd and uve each have a tetrahedron on one side only."""
    return all((t.apex(u, v, w) is None) != (t.apex(u, w, v) is None) for w in (d, e))


def _remove(t: Transient3, tetrahedra: list[Tetrahedron]) -> None:
    for tetrahedron in tetrahedra:
        t.remove_tetrahedron(*tetrahedron)


def _tetrahedron_with(t: Transient3, vertices: set[int], around: list[Tetrahedron]) -> Tetrahedron:
    for tetrahedron in around:
        if set(tetrahedron) == vertices:
            return tetrahedron
    raise PreconditionError("flip", f"no tetrahedron {sorted(vertices)}")  # pragma: no cover


def flip_in(t: Transient3, op: str, face: Face) -> FaceConfiguration:
    """Apply Joe's transformation ``op`` (``flip23``, ``flip32``, ``flip22``, ``flip44``)
    at the interior face ``face``; :class:`PreconditionError` unless the face's
    configuration is that transformation's.  Returns the configuration it undid."""
    wanted = FLIP_OPS.get(op)
    if wanted is None:
        raise PreconditionError(op, f"unknown flip {op!r}")
    configuration = classify_face_in(t, face)
    if configuration.kind != wanted:
        raise PreconditionError(
            op, f"face {tuple(sorted(face))} is {configuration.kind.value}, not "
            f"{wanted.value}"
        )
    a, b, c = configuration.face
    d, e = configuration.d, configuration.e
    first, second = (a, b, c, d), (a, c, b, e)
    if wanted == FaceKind.T23:
        _remove(t, [first, second])
    elif wanted == FaceKind.T32:
        assert configuration.edge is not None
        u, v = configuration.edge
        third = _tetrahedron_with(t, {u, v, d, e}, t.around_edge(u, v))
        _remove(t, [first, second, third])
    else:  # T22, T44: the coplanar diagonal uv becomes de
        assert configuration.edge is not None
        _remove(t, t.around_edge(*configuration.edge))
    for tetrahedron in made_tetrahedra(configuration):
        t.add_tetrahedron(*_oriented(t, *tetrahedron))
    t.record(Step(op, tuple(sorted(face))))
    return configuration


def made_tetrahedra(configuration: FaceConfiguration) -> list[Tetrahedron]:
    """The tetrahedra a flip of the transformable ``configuration`` makes, each up to
    orientation, in the order :func:`flip_in` adds them."""
    a, b, c = configuration.face
    d, e = configuration.d, configuration.e
    kind = configuration.kind
    if kind == FaceKind.T23:
        return [(d, e, u, v) for u, v in ((a, b), (b, c), (c, a))]
    assert configuration.edge is not None
    u, v = configuration.edge
    w = oriented_third((a, b, c), u, v)
    if kind == FaceKind.T32:
        return [(w, d, e, x) for x in (u, v)]
    if kind == FaceKind.T22:
        apexes = [w]
    else:
        assert configuration.apex_f is not None
        apexes = [w, configuration.apex_f]
    return [(d, e, apex, x) for apex in apexes for x in (u, v)]


def flippable_kinds(boundary: bool) -> frozenset[FaceKind]:
    """The configurations an improvement transforms: T23, T32 and T44, and T22 (which
    re-triangulates two boundary faces) only with ``boundary``."""
    kinds = {FaceKind.T23, FaceKind.T32, FaceKind.T44}
    if boundary:
        kinds.add(FaceKind.T22)
    return frozenset(kinds)


FLIP_OPS: Mapping[str, FaceKind] = MappingProxyType({
    "flip23": FaceKind.T23,
    "flip32": FaceKind.T32,
    "flip22": FaceKind.T22,
    "flip44": FaceKind.T44,
})
"""The flip steps and the configuration each one transforms."""

FLIP_NAMES: tuple[str, ...] = tuple(FLIP_OPS)
"""The flip steps' names, in the order the improvement reports count them."""

FLIP_OF_KIND: Mapping[FaceKind, str] = MappingProxyType(
    {kind: op for op, kind in FLIP_OPS.items()}
)


class FlipTally:
    """What a report of flips offers: its ``flips`` (an attrs field of the subclass) count
    the flips of each kind in FLIP_NAMES order."""

    __slots__ = ()

    flips: tuple[int, int, int, int]

    @property
    def flip_count(self) -> int:
        return sum(self.flips)

    def flips_of(self, name: str) -> int:
        return self.flips[FLIP_NAMES.index(name)]


def split_tetra_in(t: Transient3, u: int, v: int) -> int:
    """Insert the exact midpoint n of edge {u, v} and split every tetrahedron sharing the
    edge into two: the first replaces the edge's higher vertex by n, the second its lower
    vertex (in place, so orientation is kept).  Returns n."""
    if u == v:
        raise PreconditionError("split_tetra", f"({u}, {v}) is not an edge")
    low, high = undirected(u, v)
    around = t.around_edge(low, high)
    if not around:
        raise PreconditionError("split_tetra", f"({low}, {high}) is not an edge of the mesh")
    n = t.add_vertex(midpoint3(t.point(low), t.point(high)))
    for tetrahedron in around:
        t.remove_tetrahedron(*tetrahedron)
        t.add_tetrahedron(*(n if vertex == high else vertex for vertex in tetrahedron))
        t.add_tetrahedron(*(n if vertex == low else vertex for vertex in tetrahedron))
    t.record(Step("split_tetra", (low, high)))
    return n


def _apply_split_tetra(t: Transient3, step: Step) -> None:
    u, v = step_ints(step, 2)
    split_tetra_in(t, u, v)


def _apply_flip(t: Transient3, step: Step) -> None:
    a, b, c = step_ints(step, 3)
    flip_in(t, step.op, (a, b, c))


def step_ints(step: Step, count: int) -> tuple[int, ...]:
    """The step's ``count`` vertex ids (PreconditionError when they are not that)."""
    if len(step.args) != count or not all(
            isinstance(arg, int) and not isinstance(arg, bool) for arg in step.args):
        raise PreconditionError(step.op, f"{step.op} takes {count} vertex ids, not {step.args}")
    return tuple(int(arg) for arg in step.args)


OPERATIONS: Mapping[str, Callable[[Transient3, Step], None]] = MappingProxyType({
    "split_tetra": _apply_split_tetra,
    **{op: _apply_flip for op in FLIP_OPS},
})
"""The tetrahedral steps of this module (:data:`geomexact.trace.protocols.
OperationTable`); the kind's whole table (``kind_of(Mesh3).operations``) adds
``insert_cuboid`` of ``cuboid/insertion``, which builds on this module."""


def apply_in(t: Transient3, step: Step) -> None:
    """Apply ``step`` (any step of the kind's table) to the transient (it records the
    step)."""
    apply_from(kind_of(Mesh3).operations, t, step)


# ---------------------------------------------------------------------------------------
# pure functions
# ---------------------------------------------------------------------------------------
def apply(mesh: Mesh3, step: Step, /) -> Mesh3:
    """The mesh after ``step``; ``mesh`` is unchanged."""
    t = Transient3(mesh)
    apply_in(t, step)
    return t.seal()


def split_tetra(mesh: Mesh3, edge: Edge, /) -> Mesh3:
    """The mesh with ``edge`` split at its midpoint (see :func:`split_tetra_in`); the new
    vertex is ``mesh.vertex_count``."""
    return apply(mesh, Step("split_tetra", undirected(*edge)))


def flip(mesh: Mesh3, op: str, face: Face, /) -> Mesh3:
    """The mesh after Joe's transformation ``op`` at ``face`` (see :func:`flip_in`)."""
    return apply(mesh, Step(op, tuple(sorted(face))))


def classify_face(mesh: Mesh3, face: Face, /) -> FaceConfiguration:
    """Joe's configuration of the interior face ``face`` of ``mesh``."""
    return classify_face_in(Transient3(mesh), face)
