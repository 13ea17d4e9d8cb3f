"""The batch builder (``geomexact.mesh2d.transient``): each low-level edit keeps the digest
and the tables consistent, a sealed transient refuses every write, snapshots never change
(a stateful test over random ops), and ``mesh_from_triangles`` builds or refuses tables."""

from __future__ import annotations

from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, note, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

from geomexact.errors import PreconditionError, TransientSealedError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d import ops
from geomexact.mesh2d.measures import total_area
from geomexact.mesh2d.snapshot import Mesh2, full_digest
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.mesh2d.validation import validate
from geomexact.strategies import convex_polygons
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace
from geomexact.trace.step import Step

SQUARE = [(0, 0), (2, 0), (2, 2), (0, 2), (1, 1)]
FAN = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
SIDES = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1)]


def square(segments: list[tuple[int, int, int]] = SIDES) -> Mesh2:
    """The square 0-1-2-3 fanned from its centre 4."""
    return mesh_from_triangles(SQUARE, FAN, segments)


def sealed_is_consistent(t: Transient2) -> Mesh2:
    """Seal ``t`` and check the running digest against a recomputation."""
    running = t.digest
    mesh = t.seal()
    assert mesh.digest == running == full_digest(mesh)
    return mesh


# -- reads ------------------------------------------------------------------------------------
def test_a_new_transient_reads_like_its_snapshot() -> None:
    """Counts, digest, points, apexes, markers and attributes read through the transient are
    the snapshot's."""
    mesh = mesh_from_triangles(SQUARE, FAN, SIDES, vertex_markers=[0, 2, 0, 0, 0],
                               triangle_attributes=[(mpq(1, 2),), (), (), ()])
    t = Transient2(mesh)
    assert (t.vertex_count, t.triangle_count, t.digest) == (5, 4, mesh.digest)
    assert t.point(4) == point2(1, 1)
    assert t.apex(0, 1) == 4 and t.apex(1, 0) is None
    assert t.segment_marker(1, 0) == 1 == t.segment_marker(0, 1)
    assert t.segment_marker(0, 4) is None
    assert t.vertex_marker(1) == 2 and t.vertex_marker(0) == 0
    assert t.triangle_attributes((4, 0, 1)) == (mpq(1, 2),)
    assert t.triangle_attributes((1, 2, 4)) is None
    for vertex in range(5):
        w = t.outgoing(vertex)
        assert w is not None and t.apex(vertex, w) is not None


def test_triangle_attributes_read_none_on_a_mesh_without_attributes() -> None:
    """Without any attributes every triangle reads None."""
    assert Transient2(square()).triangle_attributes((0, 1, 4)) is None


# -- edits ------------------------------------------------------------------------------------
def test_add_vertex_appends_with_marker_and_attributes() -> None:
    """A new vertex gets the next id and keeps its marker and attributes; the digest follows.
    """
    t = Transient2(square())
    assert t.add_vertex(point2(3, 3)) == 5
    assert t.add_vertex(point2(4, 3), marker=7, attributes=(mpq(1, 3), mpq(2))) == 6
    assert t.outgoing(5) is None
    mesh = sealed_is_consistent(t)
    assert dict(mesh.vertex_markers.items()) == {6: 7}
    assert dict(mesh.vertex_attributes.items()) == {6: (mpq(1, 3), mpq(2))}
    assert mesh.point(5) == point2(3, 3)


def test_set_vertex_marker_changes_clears_and_restores_the_digest() -> None:
    """Setting, replacing and clearing a marker keeps the digest exact; clearing returns to
    the original digest, and setting the same marker changes nothing."""
    mesh = square()
    t = Transient2(mesh)
    t.set_vertex_marker(2, 5)
    with_five = t.digest
    t.set_vertex_marker(2, 5)
    assert t.digest == with_five
    t.set_vertex_marker(2, 9)
    assert t.vertex_marker(2) == 9 and t.digest != with_five
    t.set_vertex_marker(2, 0)
    assert t.digest == mesh.digest and t.vertex_marker(2) == 0
    assert sealed_is_consistent(t) == mesh


def test_add_triangle_refuses_a_taken_half_edge_and_changes_nothing() -> None:
    """A triangle on a half-edge that is already used is refused, leaving the transient as
    it was; a triangle on free half-edges is added."""
    mesh = square()
    t = Transient2(mesh)
    with pytest.raises(PreconditionError, match="overlaps"):
        t.add_triangle(0, 1, 2)
    assert t.digest == mesh.digest and t.triangle_count == 4
    assert t.apex(1, 2) == 4
    t.add_vertex(point2(1, -1))
    t.add_triangle(1, 0, 5)
    assert t.triangle_count == 5 and t.apex(0, 5) == 1
    assert validate(sealed_is_consistent(t)) == []


def test_remove_triangle_takes_any_rotation_and_returns_its_attributes() -> None:
    """A triangle is removed by any rotation, returning its attributes (None without);
    a reversed or absent triple is refused."""
    mesh = mesh_from_triangles(SQUARE, FAN, triangle_attributes=[(mpq(3),), (), (), ()])
    t = Transient2(mesh)
    with pytest.raises(PreconditionError, match="not a triangle"):
        t.remove_triangle(0, 4, 1)
    assert t.remove_triangle(4, 0, 1) == (mpq(3),)
    assert t.remove_triangle(2, 4, 1) is None
    with pytest.raises(PreconditionError, match="not a triangle"):
        t.remove_triangle(0, 1, 4)
    result = sealed_is_consistent(t)
    assert result.triangles() == [(0, 4, 3), (2, 3, 4)]
    assert not result.triangle_attributes


def test_set_triangle_attributes_replaces_and_clears() -> None:
    """Attributes are replaced whichever rotation names the triangle; () clears them and
    gives back the plain mesh."""
    mesh = square()
    t = Transient2(mesh)
    t.set_triangle_attributes((1, 4, 0), (mpq(1, 2),))
    assert t.triangle_attributes((0, 1, 4)) == (mpq(1, 2),)
    t.set_triangle_attributes((0, 1, 4), (mpq(2), mpq(5)))
    assert t.triangle_attributes((4, 0, 1)) == (mpq(2), mpq(5))
    t.set_triangle_attributes((0, 1, 4), ())
    assert t.triangle_attributes((0, 1, 4)) is None
    assert sealed_is_consistent(t) == mesh


def test_segments_are_set_replaced_and_removed() -> None:
    """set_segment on either orientation replaces the marker; remove_segment returns it;
    a segment with equal ends and removing a missing one are refused."""
    mesh = square([])
    t = Transient2(mesh)
    t.set_segment(4, 0, 3)
    t.set_segment(0, 4, 8)
    assert t.segment_marker(0, 4) == 8
    assert sealed_is_consistent(t) == square([(0, 4, 8)])
    t = Transient2(square([(0, 4, 8)]))
    assert t.remove_segment(4, 0) == 8
    with pytest.raises(KeyError):
        t.remove_segment(0, 4)
    with pytest.raises(PreconditionError, match="equal ends"):
        t.set_segment(2, 2)
    assert sealed_is_consistent(t) == mesh


def _flip_refused(t: Transient2) -> None:
    with pytest.raises(PreconditionError):
        t.apply(Step("flip", (0, 1)))


def test_apply_records_steps_and_the_digest_after_each() -> None:
    """apply dispatches a Step to its op and records it with the digest after it; a refused
    or unknown step records nothing."""
    t = Transient2(square([]))
    _flip_refused(t)
    with pytest.raises(PreconditionError, match="unknown step"):
        t.apply(Step("no_such_op", ()))
    assert t.steps == [] and t.step_digests == []
    t.apply(Step("bisect", (0, 1)))
    after_bisect = t.digest
    t.apply(Step("flip", (0, 4)))
    assert t.steps == [Step("bisect", (0, 1)), Step("flip", (0, 4))]
    assert t.step_digests == [after_bisect, t.digest]
    mesh = sealed_is_consistent(t)
    assert validate(mesh) == []


def test_record_appends_the_current_digest() -> None:
    """record(step) stores the step with the transient's digest at that moment."""
    t = Transient2(square())
    t.add_vertex(point2(9, 9))
    t.record(Step("custom", (1,)))
    assert t.steps == [Step("custom", (1,))] and t.step_digests == [t.digest]


def test_halfedges_snapshot_is_not_changed_by_later_writes() -> None:
    """The immutable half-edge table taken from a transient keeps its content while the
    transient goes on editing."""
    t = Transient2(square())
    before = t.halfedges_snapshot()
    content = dict(before.items())
    t.remove_triangle(0, 1, 4)
    t.add_vertex(point2(1, -1))
    t.add_triangle(0, 1, 5)
    assert dict(before.items()) == content
    assert (0, 1) in t.halfedges_snapshot() and t.apex(0, 1) == 5
    assert before[(0, 1)] == 4


def test_iter_edges_lists_every_edge_once() -> None:
    """iter_edges gives each edge of the mesh once as (min, max)."""
    t = Transient2(square())
    ops.bisect_in(t, 0, 4)
    edges = list(t.iter_edges())
    assert len(edges) == len(set(edges))
    assert all(u < v for u, v in edges)
    assert sorted(edges) == t.seal().edges()


def test_seal_repairs_outgoing_hints_of_removed_triangles() -> None:
    """Removing triangles leaves stale outgoing hints; the sealed snapshot has a valid hint
    for every vertex still in a triangle and none for a vertex left in no triangle."""
    mesh = square()
    t = Transient2(mesh)
    t.remove_triangle(0, 1, 4)
    t.remove_triangle(3, 0, 4)
    t.remove_segment(0, 1)
    t.remove_segment(3, 0)
    result = t.seal()
    assert 0 not in result.outgoing
    for vertex in (1, 2, 3, 4):
        assert (vertex, result.outgoing[vertex]) in result.halfedges
    assert validate(result) == []


def test_two_transients_on_one_snapshot_are_independent() -> None:
    """Edits in one transient are not seen by another opened on the same snapshot, nor by
    the snapshot."""
    mesh = square()
    first, second = Transient2(mesh), Transient2(mesh)
    ops.bisect_in(first, 0, 4)
    ops.insert_in_triangle_in(second, (0, 1, 4), point2(1, mpq(1, 2)))
    assert first.point(5) == point2(mpq(1, 2), mpq(1, 2))
    assert second.point(5) == point2(1, mpq(1, 2))
    a, b = first.seal(), second.seal()
    assert validate(a) == [] and validate(b) == []
    assert a != b and mesh == square()
    assert a.triangle_count == 6 and b.triangle_count == 6 and mesh.triangle_count == 4


# -- sealing ----------------------------------------------------------------------------------
def kite() -> Mesh2:
    """The square fanned from (5/4, 5/4): its edge (0, 4) can be flipped."""
    return mesh_from_triangles([*SQUARE[:4], (mpq(5, 4), mpq(5, 4))], FAN, SIDES)


WRITES: dict[str, Callable[[Transient2], object]] = {
    "add_vertex": lambda t: t.add_vertex(point2(5, 5)),
    "set_vertex_marker": lambda t: t.set_vertex_marker(0, 3),
    "add_triangle": lambda t: t.add_triangle(1, 0, 2),
    "remove_triangle": lambda t: t.remove_triangle(0, 1, 4),
    "set_triangle_attributes": lambda t: t.set_triangle_attributes((0, 1, 4), (mpq(1),)),
    "set_segment": lambda t: t.set_segment(0, 4, 2),
    "remove_segment": lambda t: t.remove_segment(0, 1),
    "seal": lambda t: t.seal(),
    "apply bisect": lambda t: t.apply(Step("bisect", (0, 4))),
    "apply flip": lambda t: t.apply(Step("flip", (0, 4))),
    "flip_in": lambda t: ops.flip_in(t, 0, 4),
    "insert_centroid_in": lambda t: ops.insert_centroid_in(t, 0, 4),
    "insert_in_triangle_in": lambda t: ops.insert_in_triangle_in(
        t, (0, 1, 4), point2(1, mpq(1, 4))),
    "carve": lambda t: t.apply(Step("carve", (mpq(1), mpq(1, 2)))),
}


@pytest.mark.parametrize("write", list(WRITES), ids=list(WRITES))
def test_a_sealed_transient_refuses_every_write(write: str) -> None:
    """After seal every edit, op and a second seal raise TransientSealedError, and the
    sealed snapshot is unchanged by the attempt."""
    t = Transient2(kite())
    mesh = t.seal()
    triangles, digest = mesh.triangles(), mesh.digest
    with pytest.raises(TransientSealedError):
        WRITES[write](t)
    assert mesh.triangles() == triangles and mesh.digest == digest
    assert mesh == kite() and t.steps == []


def test_a_sealed_transient_refuses_a_step_that_edits_nothing() -> None:
    """apply on a sealed transient raises even for a step with nothing to remove."""
    t = Transient2(square())
    t.seal()
    with pytest.raises(TransientSealedError):
        t.apply(Step("carve_exterior", ()))
    assert t.steps == []


# -- mesh_from_triangles ----------------------------------------------------------------------
def test_mesh_from_triangles_accepts_points_pairs_markers_and_attributes() -> None:
    """Point2s and coordinate pairs may be mixed; segments with or without marker; vertex
    markers, vertex and triangle attributes land in their tables."""
    mesh = mesh_from_triangles(
        [point2(0, 0), ("1", 0), (0, "0.5")],
        [(0, 1, 2)],
        [(0, 1), (1, 2, 4)],
        vertex_markers=[1, 0, 0],
        vertex_attributes=[(), (mpq(2),), ()],
        triangle_attributes=[(mpq(7, 2),)],
    )
    assert mesh.point(2) == point2(0, mpq(1, 2))
    assert mesh.segment_list() == [(0, 1, 0), (1, 2, 4)]
    assert dict(mesh.vertex_markers.items()) == {0: 1}
    assert dict(mesh.vertex_attributes.items()) == {1: (mpq(2),)}
    assert dict(mesh.triangle_attributes.items()) == {(0, 1, 2): (mpq(7, 2),)}
    assert validate(mesh) == [] and full_digest(mesh) == mesh.digest


def test_mesh_from_triangles_orients_on_request() -> None:
    """With orient=True a clockwise triangle is reversed; without it is refused."""
    with pytest.raises(PreconditionError, match="clockwise"):
        mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 2, 1)])
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 2, 1)], orient=True)
    assert mesh.triangles() == [(0, 1, 2)]


@pytest.mark.parametrize(
    ("triangles", "segments", "message"),
    [
        ([(0, 1, 1)], [], "repeats a vertex"),
        ([(0, 1, -1)], [], "refers to vertex -1"),
        ([(0, 1, 2)], [(0, 7)], "missing vertex"),
        ([(0, 1, 2)], [(1, 1, 3)], "equal ends"),
        ([(0, 1, 2), (2, 1, 3), (0, 1, 3)], [], "shares a directed edge"),
        ([(0, 1, 4)], [], "degenerate"),
    ],
)
def test_mesh_from_triangles_refuses_bad_tables(
    triangles: list[tuple[int, int, int]], segments: list[tuple[int, ...]], message: str
) -> None:
    """Repeated or missing vertices, bad segments, overlapping and degenerate triangles are
    refused with a PreconditionError saying which."""
    points = [(0, 0), (2, 0), (0, 2), (2, 2), (4, 0)]
    with pytest.raises(PreconditionError, match=message):
        mesh_from_triangles(points, triangles, segments)


# -- the stateful test ------------------------------------------------------------------------
class TransientMachine(RuleBasedStateMachine):
    """Random valid steps, each in its own transient (or a few in one): every snapshot ever
    made keeps its digest and triangles, every sealed transient refuses writes, the current
    snapshot validates with its exact area unchanged, and the recorded steps replay."""

    def __init__(self) -> None:
        super().__init__()
        self.history: list[tuple[Mesh2, int, list[tuple[int, int, int]],
                                 dict[int, Point2], list[tuple[int, int, int]]]] = []
        self.sealed: list[Transient2] = []
        self.steps: list[Step] = []
        self.digests: list[int] = []
        self.area: Rational = mpq(0)

    def _remember(self, mesh: Mesh2) -> None:
        self.history.append(
            (mesh, mesh.digest, mesh.triangles(), dict(mesh.vertices.items()),
             mesh.segment_list()))

    @property
    def current(self) -> Mesh2:
        return self.history[-1][0]

    @initialize(polygon=convex_polygons(max_size=6), constrained=st.booleans())
    def start(self, polygon: list[Point2], constrained: bool) -> None:
        n = len(polygon)
        segments = [(i, (i + 1) % n, 1) for i in range(n)] if constrained else []
        mesh = mesh_from_triangles(polygon, [(0, i, i + 1) for i in range(1, n - 1)], segments)
        self.area = total_area(mesh)
        self._remember(mesh)

    def _step(self, t: Transient2, data: st.DataObject, kind: str) -> bool:
        """Try one op of ``kind`` on a drawn edge; True when it applied."""
        edges = sorted(t.iter_edges())
        u, v = data.draw(st.sampled_from(edges), label="edge")
        before, recorded = t.digest, len(t.steps)
        try:
            if kind == "flip":
                ops.flip_in(t, u, v)
            elif kind == "bisect":
                ops.bisect_in(t, u, v)
            elif kind == "insert_centroid":
                ops.insert_centroid_in(t, u, v, kind=data.draw(
                    st.sampled_from(["area", "vertices"]), label="centroid"))
            else:
                w = t.apex(u, v)
                if w is None:
                    u, v = v, u
                    w = t.apex(u, v)
                assert w is not None
                a, b, c = t.point(u), t.point(v), t.point(w)
                i, j, k = data.draw(st.tuples(*[st.integers(1, 5)] * 3), label="weights")
                s = i + j + k
                point = point2((i * a.x + j * b.x + k * c.x) / s, (i * a.y + j * b.y + k * c.y) / s)
                ops.insert_in_triangle_in(t, (u, v, w), point)
        except PreconditionError:
            assert t.digest == before and len(t.steps) == recorded  # refused: unchanged
            return False
        assert len(t.steps) == recorded + 1 and t.step_digests[-1] == t.digest
        return True

    def _run(self, data: st.DataObject, kinds: list[str]) -> None:
        t = Transient2(self.current)
        applied = [kind for kind in kinds if self._step(t, data, kind)]
        note(f"applied {applied}")
        mesh = t.seal()
        self.sealed.append(t)
        assert len(t.steps) == len(applied)
        self.steps.extend(t.steps)
        self.digests.extend(t.step_digests)
        if applied:
            self._remember(mesh)
        else:
            assert mesh == self.current

    @rule(data=st.data())
    def flip(self, data: st.DataObject) -> None:
        self._run(data, ["flip"])

    @rule(data=st.data())
    def bisect(self, data: st.DataObject) -> None:
        self._run(data, ["bisect"])

    @rule(data=st.data())
    def insert_centroid(self, data: st.DataObject) -> None:
        self._run(data, ["insert_centroid"])

    @rule(data=st.data())
    def insert_in_triangle(self, data: st.DataObject) -> None:
        self._run(data, ["insert_in_triangle"])

    @rule(data=st.data(), kinds=st.lists(
        st.sampled_from(["flip", "bisect", "insert_centroid", "insert_in_triangle"]),
        min_size=2, max_size=5))
    def several_in_one_transient(self, data: st.DataObject, kinds: list[str]) -> None:
        self._run(data, kinds)

    @invariant()
    def earlier_snapshots_are_unchanged(self) -> None:
        for mesh, digest, triangles, vertices, segments in self.history:
            assert mesh.digest == digest
            assert mesh.triangles() == triangles
            assert dict(mesh.vertices.items()) == vertices
            assert mesh.segment_list() == segments

    @invariant()
    def sealed_transients_refuse_writes(self) -> None:
        for t in self.sealed[-3:]:
            with pytest.raises(TransientSealedError):
                t.add_vertex(point2(0, 0))
            with pytest.raises(TransientSealedError):
                t.seal()
            edge = next(t.iter_edges())
            with pytest.raises(TransientSealedError):
                t.apply(Step("bisect", edge))

    @invariant()
    def current_snapshot_is_valid_with_the_same_area(self) -> None:
        mesh = self.current
        assert validate(mesh) == []
        assert total_area(mesh) == self.area

    @invariant()
    def the_recorded_steps_replay_to_the_current_snapshot(self) -> None:
        trace = Trace(self.history[0][1], self.steps, self.digests)
        assert replay(self.history[0][0], trace) == self.current


TestTransientMachine = TransientMachine.TestCase
TestTransientMachine.settings = settings(
    max_examples=min(settings().max_examples, 25),
    stateful_step_count=12,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
