"""Batch transients (plain dict tables) and mutation transients give the same snapshots:
the same steps applied either way seal into equal meshes with equal digests and equal
tables, in 2D and in 3D."""

from __future__ import annotations

import pytest

from geomexact import mesh_from_triangles
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.trace.playback import BATCH_STEPS, replay


def _apply_all(start, steps, *, batch: bool):
    t = start.transient(batch=batch)
    for step in steps:
        t.apply(step)
    return t.seal()


def test_2d_batch_and_mutation_transients_agree() -> None:
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    run = refine(square, MaxArea("0.003"), method="bisection")
    assert len(run.trace) >= BATCH_STEPS  # replay() takes the batch path
    batch = _apply_all(run.start, run.trace.steps, batch=True)
    plain = _apply_all(run.start, run.trace.steps, batch=False)
    assert batch == plain == run.mesh == replay(run.start, run.trace)
    assert dict(batch.outgoing) == dict(plain.outgoing)
    assert batch.digest == plain.digest


@pytest.mark.parametrize("pattern", [0, 70688, (1 << 18) - 1])
def test_3d_batch_and_mutation_transients_agree(pattern: int) -> None:
    run = partition_cuboid(pattern, improve=True)
    batch = _apply_all(run.start, run.trace.steps, batch=True)
    plain = _apply_all(run.start, run.trace.steps, batch=False)
    assert batch == plain == run.mesh
    assert dict(batch.hints) == dict(plain.hints)


def test_a_sealed_batch_transient_is_closed() -> None:
    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    t = square.transient(batch=True)
    t.seal()
    from geomexact.errors import TransientSealedError

    with pytest.raises(TransientSealedError):
        t.add_triangle(0, 1, 2)
