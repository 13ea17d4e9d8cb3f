"""A snapshot whose tables come from a kernel's arrays (``TableSource``): it is the same
value as one built from tables, whether its tables are built or not."""

from __future__ import annotations

import pickle

import attrs
import numpy as np
import pytest

from geomexact import io, mesh_from_triangles
from geomexact.io.bulk import triangle_array
from geomexact.mesh2d.mesh_arrays import mesh_arrays
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea, MinAngle
from geomexact.mesh2d.refinement.engines import compiled
from geomexact.mesh2d.snapshot import Mesh2, full_digest
from geomexact.mesh2d.summary import mesh_summary, scalar_mesh_summary
from geomexact.mesh2d.validation import validate

pytestmark = pytest.mark.skipif(not compiled.AVAILABLE, reason="the Lepp kernel is not built")


def square() -> Mesh2:
    return mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                               [(0, 1, 1), (1, 2, 1), (2, 3, 2), (3, 0, 2)])


def lazy_and_eager(criterion: object, method: str) -> tuple[Mesh2, Mesh2]:
    """The kernel's result (tables not built) and the Python engine's (built)."""
    lazy = refine(square(), criterion, method=method, engine="compiled").mesh
    eager = refine(square(), criterion, method=method, engine="python").mesh
    return lazy, eager


CASES = [(MaxArea("0.003"), "bisection"), (MinAngle(28), "centroid")]


@pytest.mark.parametrize(("criterion", "method"), CASES)
def test_a_kernel_result_builds_its_tables_only_when_asked(criterion, method) -> None:
    lazy, eager = lazy_and_eager(criterion, method)
    assert lazy.source is not None and eager.source is None
    # what needs no table
    assert lazy.vertex_count == eager.vertex_count
    assert lazy.point_list() == eager.point_list()
    assert sorted(lazy.iter_triangles()) == eager.triangles()
    assert np.array_equal(triangle_array(lazy), triangle_array(eager))
    assert lazy.source is not None  # still not built
    # the tables, once built, are the same content, and the source is let go
    assert lazy == eager
    assert lazy.source is None
    assert dict(lazy.vertices) == dict(eager.vertices)
    assert dict(lazy.halfedges) == dict(eager.halfedges)
    assert full_digest(lazy) == lazy.digest
    validate(lazy)


@pytest.mark.parametrize(("criterion", "method"), CASES)
def test_the_arrays_and_summary_of_a_kernel_result_need_no_table(criterion, method) -> None:
    lazy, eager = lazy_and_eager(criterion, method)
    assert mesh_summary(lazy) == mesh_summary(eager) == scalar_mesh_summary(eager)
    fast, slow = mesh_arrays(lazy), mesh_arrays(eager)
    assert fast is not None and slow is not None
    assert lazy.source is not None
    assert np.array_equal(fast.triangles[np.lexsort(fast.triangles.T[::-1])],
                          slow.triangles[np.lexsort(slow.triangles.T[::-1])])


def test_the_tables_share_the_start_snapshot_and_the_start_is_unchanged() -> None:
    start = square()
    before = dict(start.halfedges), dict(start.vertices), start.digest
    lazy = refine(start, MaxArea("0.01"), engine="compiled").mesh
    assert lazy.vertices[0] is start.vertices[0]
    assert (dict(start.halfedges), dict(start.vertices), start.digest) == before


def test_evolve_pickle_and_writing_keep_the_value(tmp_path) -> None:
    lazy, eager = lazy_and_eager(MaxArea("0.003"), "bisection")
    copy = pickle.loads(pickle.dumps(lazy))
    assert copy == eager
    moved = attrs.evolve(lazy, digest=lazy.digest)
    assert moved.source is not None
    assert moved == eager
    io.write(tmp_path / "lazy.off", refine(square(), MaxArea("0.003")).mesh)
    io.write(tmp_path / "eager.off", eager)
    assert (tmp_path / "lazy.off").read_bytes() == (tmp_path / "eager.off").read_bytes()
    io.write(tmp_path / "lazy.ele", refine(square(), MaxArea("0.003")).mesh)
    io.write(tmp_path / "eager.ele", eager)
    for extension in (".node", ".ele", ".neigh", ".poly"):
        assert ((tmp_path / f"lazy{extension}").read_bytes()
                == (tmp_path / f"eager{extension}").read_bytes())
