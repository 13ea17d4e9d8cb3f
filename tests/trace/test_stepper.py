"""The trace stepper and the bisection of a failing property: positions, checkpoints,
digest checks, the cells each step changed, and a planted fault found in O(log n) checks."""

from __future__ import annotations

import math

import pytest
from helpers.trace_faults import planted_trace
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import mesh_from_triangles
from geomexact.errors import TraceError
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.measures import total_area
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace
from geomexact.trace.stepper import Stepper, first_failing_step


def square_run(area: str = "0.002"):
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    return refine(square, MaxArea(area), method="bisection")


@pytest.fixture(scope="module")
def run():
    return square_run()


def test_goto_gives_the_replayed_mesh_everywhere(run) -> None:
    stepper = Stepper(run.start, run.trace)
    total = len(run.trace)
    for k in (total, 0, total // 2, total // 2 - 1, 7, total):
        assert stepper.goto(k) == replay(run.start, run.trace, until=k)
        assert stepper.position == k
    assert stepper.mesh == run.mesh


def test_back_and_step_walk_one_step(run) -> None:
    stepper = Stepper(run.start, run.trace)
    stepper.goto(10)
    stepper.back()
    assert stepper.position == 9 and stepper.mesh == replay(run.start, run.trace, until=9)
    stepper.step()
    assert stepper.mesh == replay(run.start, run.trace, until=10)
    with pytest.raises(TraceError):
        Stepper(run.start, run.trace).back()
    end = Stepper(run.start, run.trace)
    end.goto(len(run.trace))
    with pytest.raises(TraceError):
        end.step()


def test_checkpoints_bound_the_replay_work(run) -> None:
    stepper = Stepper(run.start, run.trace)
    total = len(run.trace)
    stepper.goto(total)
    before = stepper.applied
    stepper.goto(total // 2 + 3)  # back: from the nearest checkpoint at or before it
    assert stepper.applied - before <= stepper.spacing
    assert stepper.spacing == max(1, math.isqrt(total))


def test_changed_names_the_cells_of_one_step(run) -> None:
    stepper = Stepper(run.start, run.trace)
    stepper.goto(1)
    change = stepper.changed
    step = stepper.step_at(1)
    assert step.op == "bisect"
    # a bisection of an interior edge removes 2 triangles and adds 4
    assert len(change.removed) in (1, 2) and len(change.added) == 2 * len(change.removed)
    assert set(change.removed) <= set(run.start.triangles())
    assert stepper.position == 1 and Stepper(run.start, run.trace).changed.added == ()


def test_a_3d_trace_steps_too() -> None:
    cuboid = partition_cuboid(70688, improve=True)
    stepper = Stepper(cuboid.start, cuboid.trace)
    stepper.goto(len(cuboid.trace))
    assert stepper.mesh == cuboid.mesh
    stepper.goto(1)
    assert len(stepper.changed.added) == 2 * len(stepper.changed.removed)


def test_a_wrong_start_or_a_diverging_step_is_refused(run) -> None:
    with pytest.raises(TraceError):
        Stepper(run.mesh, run.trace)
    digests = list(run.trace.digests)
    digests[5] ^= 1
    broken = Trace(run.trace.input_digest, run.trace.steps, digests)
    stepper = Stepper(run.start, broken)
    stepper.goto(5)
    with pytest.raises(TraceError, match="step 6"):
        stepper.goto(6)


@settings(max_examples=6, deadline=None)
@given(fraction=st.floats(0.05, 0.95))
def test_bisect_finds_a_planted_bad_step_in_log_checks(run, fraction) -> None:
    at = int(len(run.trace) * fraction)
    start, trace, at = planted_trace(run, at)
    assert is_delaunay(replay(start, trace, until=at))
    result = first_failing_step(Stepper(start, trace), is_delaunay)
    assert result.step == at + 1 and trace.steps[at].op == "flip"
    assert result.checks <= math.ceil(math.log2(len(trace))) + 2


def test_bisect_reports_a_property_that_holds_or_fails_from_the_start(run) -> None:
    assert first_failing_step(Stepper(run.start, run.trace), is_delaunay).step is None
    area = total_area(run.start)
    assert first_failing_step(Stepper(run.start, run.trace),
                              lambda mesh: total_area(mesh) == area).step is None
    result = first_failing_step(Stepper(run.start, run.trace), lambda mesh: False)
    assert result.failed_at_start and result.checks == 1


def test_a_step_naming_a_missing_vertex_is_a_trace_error_not_a_key_error(run) -> None:
    from geomexact.trace.step import Step

    for start, step in ((run.start, Step("bisect", (0, 99))),
                        (partition_cuboid(0).start, Step("split_tetra", (0, 99)))):
        trace = Trace(start.digest, [step], [0])
        with pytest.raises(TraceError, match="cannot be applied: .*(99 does not exist|not an edge)"):
            replay(start, trace)
