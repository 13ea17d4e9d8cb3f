"""The compiled replay (``Mesh2.replayed_by_engine``, the Lepp kernel) against the reference
ops: the same mesh after the same steps on real runs (bisection with and without Delaunay
flips, centroid insertions, constrained boundaries), the same refusal of a tampered trace
and of a step that cannot be applied, and a clean fallback for steps it does not record."""

from __future__ import annotations

import importlib.resources

import pytest

from geomexact import io, mesh_from_triangles
from geomexact.errors import TraceError
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea, MinAngle
from geomexact.mesh2d.refinement.engines import compiled
from geomexact.trace.playback import BATCH_STEPS, apply_checked, replay
from geomexact.trace.record import Trace
from geomexact.trace.step import Step

pytestmark = pytest.mark.skipif(not compiled.AVAILABLE, reason="the Lepp kernel is not built")


def reference_replay(start, trace):
    t = start.transient(batch=True)
    for index in range(len(trace)):
        apply_checked(t, trace, index)
    return t.seal()


def square():
    return mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                               [(0, 1, 1), (1, 2, 1), (2, 3, 2), (3, 0, 2)])


def superior():
    source = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(source) as path:
        return triangulate(io.read(path, format="poly")).mesh


RUNS = {
    "bisection-delaunay": lambda: refine(square(), MaxArea("0.002"), method="bisection"),
    "bisection-plain": lambda: refine(square(), MaxArea("0.002"), method="bisection",
                                      delaunay=False),
    "centroid-area": lambda: refine(superior(), MaxArea("0.5"), method="centroid"),
    "superior-bisection": lambda: refine(superior(), MaxArea("0.2"), method="bisection"),
}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_the_engine_replays_to_the_reference_mesh(name: str) -> None:
    run = RUNS[name]()
    assert {step.op for step in run.trace.steps} <= compiled.REPLAYED_OPS
    fast = run.start.replayed_by_engine(run.trace.steps, run.trace.digests)
    assert fast is not None
    assert fast == reference_replay(run.start, run.trace) == run.mesh
    assert fast.digest == run.mesh.digest


def test_a_tampered_digest_is_refused_with_the_reference_message() -> None:
    run = RUNS["bisection-delaunay"]()
    assert len(run.trace) >= BATCH_STEPS  # replay() asks the engine first
    digests = list(run.trace.digests)
    digests[100] ^= 1
    tampered = Trace(run.trace.input_digest, run.trace.steps, digests)
    assert run.start.replayed_by_engine(tampered.steps, tampered.digests) is None
    with pytest.raises(TraceError, match="step 101 ") as caught:
        replay(run.start, tampered)
    assert caught.value.step == 101


@pytest.mark.parametrize("bad", [Step("bisect", (0, 999_999)), Step("flip", (0, 1)),
                                 Step("bisect", (True, 1)), Step("flip", (0, 2**70))])
def test_a_step_that_cannot_be_applied_is_refused(bad: Step) -> None:
    run = RUNS["bisection-delaunay"]()
    k = len(run.trace) // 2
    steps = [*run.trace.steps[:k], bad, *run.trace.steps[k:]]
    trace = Trace(run.trace.input_digest, steps, [*run.trace.digests[:k], 0,
                                                  *run.trace.digests[k:]])
    assert run.start.replayed_by_engine(trace.steps, trace.digests) is None
    with pytest.raises(TraceError, match=f"step {k + 1} .*cannot be applied"):
        replay(run.start, trace)


def test_steps_it_does_not_record_go_to_the_reference() -> None:
    start = square()
    t = start.transient()
    from geomexact.kernel.points import point2
    from geomexact.mesh2d import ops

    a, b = t.point(0), t.point(2)  # insert_in_edge: recorded by no refinement engine
    ops.insert_in_edge_in(t, 0, 2, point2((a.x + b.x) / 2, (a.y + b.y) / 2))
    for _ in range(BATCH_STEPS):
        ops.bisect_in(t, *min(t.iter_edges()))
    trace = Trace(start.digest, t.steps, t.step_digests)
    assert start.replayed_by_engine(trace.steps, trace.digests) is None
    assert replay(start, trace) == t.seal()


def test_min_angle_runs_replay_too() -> None:
    run = refine(superior(), MinAngle(25), method="centroid")
    assert replay(run.start, run.trace) == run.mesh


@pytest.mark.parametrize("centroid", ["vertices", "area-exact"])
def test_exact_centroid_steps_replay_in_the_kernel(centroid: str) -> None:
    """insert_vertex_centroid (Mellado's preset) and insert_centroid replay compiled, the
    same mesh as the reference, and a tampered digest is refused (issue 25)."""
    steps = None if centroid == "vertices" else 8  # exact area centroids grow fast
    run = refine(superior(), MinAngle(30), method="centroid", centroid=centroid,
                 order="passes", max_steps=steps)
    ops = {step.op for step in run.trace.steps}
    assert ("insert_vertex_centroid" if centroid == "vertices" else "insert_centroid") in ops
    replayed = run.start.replayed_by_engine(run.trace.steps, run.trace.digests)
    assert replayed is not None and replayed == run.mesh
    assert replayed == reference_replay(run.start, run.trace)
    digests = list(run.trace.digests)
    digests[-1] ^= 1
    assert run.start.replayed_by_engine(run.trace.steps, digests) is None
