"""refine's step_cap (a limit from outside, such as a command's memory budget): a run it
does not stop is the same run, trace and all; a run it stops has status "budget" and
records the cap as its step budget, with a valid partial mesh."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import mesh_from_triangles, validate
from geomexact.errors import PreconditionError
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea

SQUARE = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])


def test_a_cap_that_does_not_stop_the_run_changes_nothing() -> None:
    """The same mesh and the same trace, parameters included."""
    free = refine(SQUARE, MaxArea("1/64"))
    capped = refine(SQUARE, MaxArea("1/64"), step_cap=free.stats.steps)
    assert capped.mesh == free.mesh and capped.trace == free.trace


@settings(max_examples=10, deadline=None)
@given(st.integers(min_value=0, max_value=40))
def test_a_cap_that_stops_the_run_is_a_budget(cap: int) -> None:
    """Stopped at the cap: status budget, the cap recorded, the partial mesh valid and
    exactly the free run's mesh after that many steps."""
    free = refine(SQUARE, MaxArea("1/64"), engine="python")
    if cap >= free.stats.steps:
        return
    capped = refine(SQUARE, MaxArea("1/64"), step_cap=cap, engine="python")
    assert capped.stats.status == "budget" and capped.stats.steps == cap
    assert dict(capped.trace.parameters)["step_budget"] == cap
    assert validate(capped.mesh) == []
    assert capped.trace.digests == free.trace.digests[:cap]


def test_a_negative_cap_is_refused() -> None:
    with pytest.raises(PreconditionError, match="step_cap"):
        refine(SQUARE, MaxArea("1/64"), step_cap=-1)
