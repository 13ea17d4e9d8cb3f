"""DeferredSequence: a kernel's steps and digests, made on first read and then the tuple of
them; a compiled run's trace stays unmade until something reads it."""

from __future__ import annotations

import pickle
import random

import pytest

from geomexact import io, point2
from geomexact.mesh2d.delaunay import compiled as compiled_delaunay
from geomexact.mesh2d.delaunay.triangulation import triangulate_points
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MinAngle
from geomexact.mesh2d.refinement.engines import compiled as compiled_refinement
from geomexact.trace.deferred import DeferredSequence
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace


def random_doubles(count: int, seed: int) -> list:  # type: ignore[type-arg]
    rng = random.Random(seed)
    return [point2(rng.random(), rng.random()) for _ in range(count)]


def counted(items: list[int]) -> tuple[DeferredSequence[int], list[int]]:
    calls: list[int] = []

    def make() -> list[int]:
        calls.append(1)
        return list(items)

    return DeferredSequence(len(items), make, lambda i: items[i] * 1), calls


def test_made_once_on_first_read_and_then_the_tuple() -> None:
    deferred, calls = counted([3, 1, 4, 1, 5])
    assert len(deferred) == 5 and not deferred.made and calls == []
    assert deferred[-1] == 5 and deferred[0] == 3 and calls == []  # one item: not made
    assert deferred == (3, 1, 4, 1, 5) and deferred == [3, 1, 4, 1, 5]
    assert calls == [1] and deferred.made
    assert deferred[1:3] == (1, 4) and list(deferred) == [3, 1, 4, 1, 5]
    assert hash(deferred) == hash((3, 1, 4, 1, 5)) and deferred != (3, 1)
    assert deferred + (9,) == (3, 1, 4, 1, 5, 9) and (0,) + deferred == (0, 3, 1, 4, 1, 5)
    assert pickle.loads(pickle.dumps(deferred)) == (3, 1, 4, 1, 5)
    assert calls == [1]
    with pytest.raises(IndexError):
        counted([1, 2])[0][2]


def test_a_wrong_count_is_refused() -> None:
    with pytest.raises(ValueError, match="3 items made 2"):
        DeferredSequence(3, lambda: [1, 2]).items()


def test_traces_with_deferred_and_made_steps_are_equal() -> None:
    deferred, _ = counted([7, 8])
    made = Trace(1, (), (), {"a": 1})
    assert Trace(1, DeferredSequence(0, list), DeferredSequence(0, list), {"a": 1}) == made
    assert len(Trace(1, deferred, deferred)) == 2


@pytest.mark.skipif(not compiled_delaunay.AVAILABLE, reason="the Delaunay kernel is not built")
def test_a_compiled_triangulation_makes_its_steps_when_read() -> None:
    points = random_doubles(200, 5)
    run = triangulate_points(points, engine="compiled")
    steps, digests = run.trace.steps, run.trace.digests
    assert isinstance(steps, DeferredSequence) and not steps.made
    assert run.trace.final_digest == run.mesh.digest and not steps.made
    reference = triangulate_points(points, engine="reference")
    assert run.trace == reference.trace and steps.made and digests.made  # type: ignore[attr-defined]
    assert replay(run.start, run.trace).digest == run.mesh.digest


@pytest.mark.skipif(not compiled_refinement.AVAILABLE, reason="the Lepp kernel is not built")
def test_a_compiled_refinement_makes_its_steps_when_read(shared_data) -> None:  # type: ignore[no-untyped-def]
    mesh = io.read(shared_data / "polylla-refinement" / "500poisson.off")
    run = refine(mesh, MinAngle(30), method="centroid")
    assert isinstance(run.trace.steps, DeferredSequence) and not run.trace.steps.made
    assert len(run.trace) == run.stats.steps == run.stats.flips + run.stats.bisections \
        + run.stats.centroids
    assert run.trace == refine(mesh, MinAngle(30), method="centroid", engine="reference").trace
    assert replay(mesh, run.trace).digest == run.mesh.digest
