"""A tetrahedral snapshot whose tables come from a bulk builder's arrays (``FaceSource``,
as ``mesh3_from_positive_arrays`` leaves them): the same value as one built tetrahedron by
tetrahedron, whether its tables are built or not."""

from __future__ import annotations

import pickle

import attrs
import numpy as np
import pytest

from geomexact import io
from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import unit_cube
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.regions import SphereSurfaceRegion
from geomexact.mesh3d.octree.stages import RefineWhere
from geomexact.mesh3d.snapshot import Mesh3, full_digest3
from geomexact.mesh3d.transient import mesh3_from_positive_arrays, mesh3_from_tetrahedra
from geomexact.mesh3d.validation import validate3


def lazy_and_eager() -> tuple[Mesh3, Mesh3]:
    """An octree mesh from the bulk builder (tables not built) and the same tetrahedra
    added one by one (built)."""
    run = generate(unit_cube(),
                   refinement=RefineWhere(2, region=SphereSurfaceRegion(("1/2",) * 3, "0.3")),
                   trace=False)
    points = run.leaf_mesh.lattice.exact_points()
    tetrahedra = np.asarray(run.leaf_mesh.tetrahedra)
    return (mesh3_from_positive_arrays(points, tetrahedra),
            mesh3_from_tetrahedra(points, tetrahedra.tolist()))


def test_a_bulk_mesh_builds_its_tables_only_when_asked() -> None:
    lazy, eager = lazy_and_eager()
    assert lazy.source is not None and eager.source is None
    # what needs no table
    assert lazy.vertex_count == eager.vertex_count
    assert lazy.point_list() == eager.point_list()
    assert np.array_equal(lazy.tetrahedron_array(), eager.tetrahedron_array())
    assert lazy.boundary_faces() == eager.boundary_faces()
    assert lazy.digest == eager.digest and lazy.tetrahedron_count == eager.tetrahedron_count
    assert lazy.source is not None  # still not built
    # the tables, once built, are the same content, and the source is let go
    assert lazy == eager
    assert lazy.source is None
    assert dict(lazy.vertices) == dict(eager.vertices)
    assert dict(lazy.faces) == dict(eager.faces)
    assert full_digest3(lazy) == lazy.digest
    assert validate3(lazy) == []


def test_each_hint_is_a_face_of_its_vertex() -> None:
    lazy, eager = lazy_and_eager()
    assert set(lazy.hints) == set(eager.hints) == set(range(lazy.vertex_count))
    for vertex, face in lazy.hints.items():
        assert vertex in face and face in lazy.faces


def test_a_bulk_mesh_pickles_and_evolves_as_a_value() -> None:
    lazy, eager = lazy_and_eager()
    again = pickle.loads(pickle.dumps(lazy))
    assert again == eager and again.digest == eager.digest
    assert lazy.source is not None  # pickling kept the arrays, built nothing here
    changed = attrs.evolve(lazy, digest=lazy.digest)
    assert changed == eager


def test_writing_a_bulk_mesh_builds_no_table(tmp_path) -> None:
    lazy, eager = lazy_and_eager()
    for name in ("m.ele", "m.vtu", "m.vtk"):
        io.write(tmp_path / f"lazy-{name}", lazy)
        io.write(tmp_path / f"eager-{name}", eager)
    assert lazy.source is not None
    for name in ("m.node", "m.ele", "m.face", "m.vtu", "m.vtk"):
        assert (tmp_path / f"lazy-{name}").read_bytes() == (
            tmp_path / f"eager-{name}").read_bytes()


def test_the_bulk_builder_still_refuses_two_tetrahedra_on_one_side_of_a_face() -> None:
    lazy, _ = lazy_and_eager()
    points = lazy.point_list()
    tetrahedra = np.asarray(lazy.tetrahedron_array())
    with pytest.raises(PreconditionError, match="same side of a face"):
        mesh3_from_positive_arrays(points, np.concatenate((tetrahedra, tetrahedra[-1:])))
