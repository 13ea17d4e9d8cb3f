"""Meshes as meshio objects in memory (issue 26, item 2): triangle, tetrahedral and
mixed-cell meshes round-trip through ``meshio.Mesh`` keeping everything (segments,
markers, attributes; exact numbers on request), doubles are never rounded without being
asked, Gmsh's physical tags are segment markers, and bad objects name the problem."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import from_meshio, io, mpq, to_meshio
from geomexact.errors import FormatError, PreconditionError, UnsupportedValueError
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed import MixedMesh3, box_grid_mesh
from geomexact.mesh3d.mixed.ops import split_cell
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.stages import RefineWhere
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.strategies import triangulations

meshio = pytest.importorskip("meshio")
np = pytest.importorskip("numpy")

from helpers.io_cases import grid_meshes  # noqa: E402
from helpers.mixed_files import every_kind_mesh  # noqa: E402
from helpers.paths import read_superior  # noqa: E402


def _attributed() -> Mesh2:
    """Two triangles with vertex markers and attributes, triangle attributes and marked
    segments; coordinates that are not doubles (0.1, 1/3)."""
    return mesh_from_triangles(
        [(0, 0), ("0.1", 0), (mpq(1, 3), "2.5"), (0, 1)],
        [(0, 1, 2), (0, 2, 3)],
        [(0, 1, 4), (2, 3, 7)],
        vertex_markers=[0, 1, 0, 2],
        vertex_attributes=[(mpq(1, 7),), (mpq(2),), (mpq(0),), (mpq(1, 2),)],
        triangle_attributes=[(mpq(5),), (mpq(-1, 3),)],
    )


def test_superior_round_trips_exactly_with_its_segments() -> None:
    pslg = read_superior()
    mesh = triangulate(pslg).mesh
    converted = to_meshio(mesh, numbers="exact")
    assert [block.type for block in converted.cells] == ["triangle", "line"]
    assert len(converted.cells[0].data) == mesh.triangle_count
    assert len(converted.cells[1].data) == len(mesh.segments)
    back = from_meshio(converted)
    assert isinstance(back, Mesh2)
    assert back.digest == mesh.digest and back.segments == mesh.segments


def test_markers_and_attributes_come_back() -> None:
    mesh = _attributed()
    converted = to_meshio(mesh, numbers="exact")
    assert converted.point_data["vertex_markers"].tolist() == [0, 1, 0, 2]
    assert converted.cell_data["marker"][1].tolist() == [4, 7]
    back = from_meshio(converted)
    assert isinstance(back, Mesh2)
    assert back.digest == mesh.digest
    assert dict(back.vertex_markers) == dict(mesh.vertex_markers)
    assert dict(back.vertex_attributes) == dict(mesh.vertex_attributes)
    assert dict(back.triangle_attributes) == dict(mesh.triangle_attributes)
    assert dict(back.segments) == dict(mesh.segments)


def test_doubles_are_never_rounded_silently() -> None:
    mesh = _attributed()
    with pytest.raises(PreconditionError, match="not exactly a double"):
        to_meshio(mesh)
    nearest = to_meshio(mesh, numbers="nearest")
    assert nearest.points.dtype == np.float64
    assert nearest.points[1, 0] == 0.1
    back = from_meshio(nearest)  # each double read as the rational it is
    assert isinstance(back, Mesh2)
    assert back.point(1).x == mpq(0.1) != mpq(1, 10)


@given(triangulations())
@settings(max_examples=30, deadline=None)
def test_random_meshes_round_trip(mesh: Mesh2) -> None:
    back = from_meshio(to_meshio(mesh, numbers="exact"))
    assert isinstance(back, Mesh2) and back.digest == mesh.digest


def test_a_written_object_reads_back_from_the_file(tmp_path: Path) -> None:
    """What meshio writes from ``to_meshio`` geomexact reads as the same triangles."""
    mesh = triangulate(read_superior()).mesh
    path = tmp_path / "superior.vtu"
    meshio.write(path, to_meshio(mesh, numbers="nearest"))
    back = io.read(path)
    assert isinstance(back, Mesh2) and back.triangle_count == mesh.triangle_count


def test_gmsh_physical_tags_are_segment_markers() -> None:
    converted = meshio.Mesh(
        np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        [("triangle", np.array([[0, 1, 2]])), ("line", np.array([[0, 1], [1, 2]])),
         ("vertex", np.array([[0]]))],
        cell_data={"gmsh:physical": [np.array([1]), np.array([5, 6]), np.array([9])]},
    )
    back = from_meshio(converted)
    assert isinstance(back, Mesh2)
    assert sorted(back.segments.values()) == [5, 6]
    assert dict(back.vertex_markers) == {0: 9}  # a physical point
    assert dict(back.triangle_attributes) == {(0, 1, 2): (1,)}  # a physical surface
    converted.cell_data.pop("gmsh:physical")
    converted.cell_data["gmsh:physical"] = [np.array([0]), np.array([0, 0]), np.array([0])]
    with pytest.warns(UserWarning, match="ignored 1 vertex cells"):
        plain = from_meshio(converted)  # meshio's zeros: no physical groups
    assert isinstance(plain, Mesh2) and not len(plain.triangle_attributes)
    assert sorted(plain.segments.values()) == [1, 1]


def test_tetrahedral_meshes_round_trip() -> None:
    mesh = generate(Box((0, 0, 0), (1, 1, 1)), refinement=RefineWhere(2),
                    trace=False).mesh
    converted = to_meshio(mesh)
    assert [block.type for block in converted.cells] == ["tetra"]
    back = from_meshio(converted)
    assert isinstance(back, Mesh3) and back.digest == mesh.digest


@pytest.mark.parametrize("build", [
    lambda: box_grid_mesh(Box((0, 0, 0), (1, "1.5", "0.75")), 2, 3, 2),
    lambda: split_cell(box_grid_mesh(Box((0, 0, 0), (1, 1, 1)), 1, 1, 1),
                       box_grid_mesh(Box((0, 0, 0), (1, 1, 1)), 1, 1, 1).cell_list()[0],
                       [0, 1, 6]),
])
def test_mixed_meshes_round_trip(build: object) -> None:
    mesh = build()  # type: ignore[operator]
    converted = to_meshio(mesh, numbers="exact")
    assert converted.cell_data["kind"][0].tolist()[0] in (10, 12, 13, 14)
    back = from_meshio(converted)
    assert isinstance(back, MixedMesh3)
    assert back.digest == mesh.digest and back.cell_list() == mesh.cell_list()


def test_polyhedra_are_refused_with_the_way_out() -> None:
    with pytest.raises(UnsupportedValueError, match=r"write it as \.vtu"):
        to_meshio(every_kind_mesh())


@pytest.mark.parametrize(("converted", "problem"), [
    (lambda: meshio.Mesh(np.zeros((3, 2)), [("quad", np.array([[0, 1, 2, 0]]))]),
     "quad cells"),
    (lambda: meshio.Mesh(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
                         [("triangle", np.array([[0, 1, 5]]))]), "out of range"),
    (lambda: meshio.Mesh(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 0.0]]),
                         [("triangle", np.array([[0, 1, 2]]))]), "only planar"),
    (lambda: meshio.Mesh(np.zeros((2, 2)), [("line", np.array([[0, 1]]))]),
     "no triangle"),
])
def test_bad_objects_name_the_problem(converted: object, problem: str) -> None:
    with pytest.raises((FormatError, PreconditionError), match=problem):
        from_meshio(converted())  # type: ignore[operator]


def test_not_a_meshio_object() -> None:
    with pytest.raises(UnsupportedValueError, match=r"meshio\.Mesh"):
        from_meshio({"points": []})
    with pytest.raises(UnsupportedValueError, match="Mesh2, Mesh3 or MixedMesh3"):
        to_meshio("mesh")  # type: ignore[arg-type]


@given(st.integers(0, 2**62))
@settings(max_examples=10, deadline=None)
def test_large_markers_survive(marker: int) -> None:
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)], [(0, 1, marker)])
    back = from_meshio(to_meshio(mesh))
    assert isinstance(back, Mesh2) and dict(back.segments) == dict(mesh.segments)


@given(grid_meshes(dyadic=False, extras=True), st.sampled_from(["exact", "nearest"]))
@settings(max_examples=30, deadline=None)
def test_meshes_with_everything_round_trip(mesh: Mesh2, numbers: str) -> None:
    """Segments, markers, vertex and triangle attributes and exact coordinates come back
    from a meshio object (exactly with numbers='exact'; with 'nearest' every part but the
    rounded numbers)."""
    back = from_meshio(to_meshio(mesh, numbers=numbers))  # type: ignore[arg-type]
    assert isinstance(back, Mesh2)
    if numbers == "exact":
        assert back.digest == mesh.digest
    assert dict(back.segments) == dict(mesh.segments)
    assert dict(back.vertex_markers) == dict(mesh.vertex_markers)
    assert back.triangles() == mesh.triangles()
    assert set(back.triangle_attributes) == set(mesh.triangle_attributes)
