"""Every third-party file in ``../shared/data`` reads with the counts its README states,
and writes back: exactly (equal values) with ``exact=True``, to the same doubles with
``exact=False``.  Skipped when ``../shared/data`` is absent."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.io_cases import geometric_triangles, plain, same_doubles

from geomexact import Mesh2, io, mpq, point2, total_area, validate
from geomexact.kernel.numbers import to_float
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG

# file, kind, vertices, triangles|polygons|segments, holes, a note the reader must make
MESHES = [
    ("polylla-refinement/500poisson.off", 539, 1012, None),
    ("polylla-refinement/1500random.off", 1502, 2883, None),
    ("polylla-refinement/pikachu_triangle.off", 352, 531,
     "all 531 triangles were clockwise; reversed them"),
    ("polylla-dcel/pikachu.1.ele", 352, 531, "all 531 triangles were clockwise; reversed them"),
    ("polylla-dcel/points50.1.ele", 50, 83, "points50.1.neigh agrees with the adjacency"),
    ("polylla-unified/pikachu.1.ele", 152, 154, "pikachu.1.neigh agrees with the adjacency"),
    ("qlepp2d/A.off", 4, 2, None),
    ("qlepp2d/B.off", 5, 4, None),
    ("lepp-delaunay-course/Triangles1.txt", None, 18, None),
    ("lepp-delaunay-course/Triangles2.txt", None, 24, None),
    ("lepp-delaunay-course/Triangles3.txt", None, 36, None),
    ("lepp-delaunay-course/Triangles4.txt", None, 60, None),
]

PSLGS = [
    ("triangle-net/superior.poly", 518, 518, 6),
    ("polylla-unified/pikachu_poly.poly", 152, 152, 4),
]

POLYGON_MESHES = [
    ("polylla-dcel/pikachu.1.off", 352, 165),
    ("polylla-dcel/points50.1.off", 50, 17),
    ("polylla-refinement/polygon.off", 5, 1),
]

EVERY_FILE = (
    [name for name, *_ in MESHES]
    + [name for name, *_ in PSLGS]
    + [name for name, *_ in POLYGON_MESHES]
)


@pytest.mark.parametrize(("name", "vertices", "triangles", "note"), MESHES)
def test_shared_mesh_reads_with_its_counts(
    shared_data: Path, name: str, vertices: int | None, triangles: int, note: str | None
) -> None:
    """Triangle meshes: the README's vertex and triangle counts, valid, expected note."""
    mesh, notes = io.read_with_notes(shared_data / name)
    assert isinstance(mesh, Mesh2)
    assert mesh.triangle_count == triangles
    if vertices is not None:
        assert mesh.vertex_count == vertices
    if note is not None:
        assert note in notes
    # validate's only complaint may be the stray duplicate corner points of the meshio
    # files (vertices in no triangle)
    kinds = {violation.kind for violation in validate(mesh)}
    assert kinds <= {"dangling-vertex"}, validate(mesh)


def test_500poisson_covers_the_unit_square_exactly(shared_data: Path) -> None:
    """500poisson.off: the triangles' exact areas add up to exactly 1."""
    mesh = io.read(shared_data / "polylla-refinement/500poisson.off")
    assert isinstance(mesh, Mesh2)
    assert total_area(mesh) == 1


def test_stray_duplicate_corners_are_kept_and_noted(shared_data: Path) -> None:
    """500poisson.off lists (1, 1) and (1, 0) twice, the copies in no triangle: kept."""
    mesh, notes = io.read_with_notes(shared_data / "polylla-refinement/500poisson.off")
    assert isinstance(mesh, Mesh2)
    assert mesh.point(536) == mesh.point(532)
    assert any("repeat another vertex's coordinates" in note for note in notes)


def test_lepp_course_files_are_counter_clockwise(shared_data: Path) -> None:
    """The LeppDelaunay course lists its triangles counter-clockwise: nothing reversed;
    vertices are merged by exact coordinates."""
    mesh, notes = io.read_with_notes(shared_data / "lepp-delaunay-course/Triangles1.txt")
    assert isinstance(mesh, Mesh2)
    assert not any("clockwise" in note for note in notes)
    assert mesh.point(0) == point2(0, 0)
    assert validate(mesh) == []


@pytest.mark.parametrize(("name", "vertices", "segments", "holes"), PSLGS)
def test_shared_pslg_reads_with_its_counts(
    shared_data: Path, name: str, vertices: int, segments: int, holes: int
) -> None:
    """PSLGs: vertex, segment and hole counts."""
    pslg = io.read(shared_data / name)
    assert isinstance(pslg, PSLG)
    assert (len(pslg.vertices), len(pslg.segments), len(pslg.holes)) == (
        vertices,
        segments,
        holes,
    )


def test_superior_is_one_based(shared_data: Path) -> None:
    """superior.poly numbers from 1: its first segment '1 1 2' joins vertices 0 and 1."""
    pslg = io.read(shared_data / "triangle-net/superior.poly")
    assert isinstance(pslg, PSLG)
    assert pslg.segments[0] == (0, 1, 0)
    assert pslg.vertices[0] == point2(mpq(1, 10), mpq(-629607, 1000000))
    assert pslg.holes[0] == point2(mpq(55, 100), mpq(-335, 1000))


def test_pikachu_poly_region(shared_data: Path) -> None:
    """pikachu_poly.poly has one region: attribute -1 and area 0 (no constraint)."""
    pslg = io.read(shared_data / "polylla-unified/pikachu_poly.poly")
    assert isinstance(pslg, PSLG)
    assert len(pslg.regions) == 1
    region = pslg.regions[0]
    assert (region.point, region.attribute, region.max_area) == (
        point2(5000, 5000),
        mpq(-1),
        None,
    )


@pytest.mark.parametrize(("name", "vertices", "polygons"), POLYGON_MESHES)
def test_shared_polygon_mesh_reads_with_its_counts(
    shared_data: Path, name: str, vertices: int, polygons: int
) -> None:
    """Polylla polygon meshes (pikachu's inside a Geomview wrapper)."""
    value, notes = io.read_with_notes(shared_data / name)
    assert isinstance(value, PolygonMesh)
    assert (len(value.vertices), len(value.polygons)) == (vertices, polygons)
    if name.startswith("polylla-dcel"):
        assert "read the OFF object inside a Geomview '{ … }' wrapper" in notes


def test_node_alone_is_a_point_set(shared_data: Path) -> None:
    """A .node read alone is a PSLG without segments, markers kept."""
    pslg = io.read(shared_data / "polylla-dcel/points50.1.node")
    assert isinstance(pslg, PSLG)
    assert len(pslg.vertices) == 50 and pslg.segments == ()
    assert pslg.vertex_markers[:3] == (1, 1, 1)


def test_ele_and_node_agree(shared_data: Path) -> None:
    """The mesh of pikachu.1.ele has the vertices and markers of pikachu.1.node."""
    mesh = io.read(shared_data / "polylla-dcel/pikachu.1.ele")
    nodes = io.read(shared_data / "polylla-dcel/pikachu.1.node")
    assert isinstance(mesh, Mesh2) and isinstance(nodes, PSLG)
    assert [mesh.point(v) for v in range(mesh.vertex_count)] == list(nodes.vertices)
    assert [mesh.vertex_markers.get(v, 0) for v in range(mesh.vertex_count)] == list(
        nodes.vertex_markers
    )


def _target(directory: Path, name: str) -> Path:
    return directory / Path(name).name


@pytest.mark.parametrize("name", EVERY_FILE)
def test_exact_round_trip_of_shared_files(shared_data: Path, tmp_path: Path, name: str) -> None:
    """write(exact=True) then read gives an equal value, in the same format (a triangle
    list numbers vertices by first appearance: equal triangles, as coordinates)."""
    value = io.read(shared_data / name)
    io.write(_target(tmp_path, name), value, exact=True)
    again = io.read(_target(tmp_path, name))
    if name.endswith(".txt"):
        assert isinstance(value, Mesh2) and isinstance(again, Mesh2)
        assert geometric_triangles(again) == geometric_triangles(value)
    else:
        assert again == value


@pytest.mark.parametrize("name", EVERY_FILE)
def test_float_round_trip_of_shared_files(shared_data: Path, tmp_path: Path, name: str) -> None:
    """write(exact=False) writes the nearest doubles: read back, every coordinate rounds
    to the same double as the original (decimal text like 0.1 is not a double, so the
    values themselves may differ)."""
    value = io.read(shared_data / name)
    io.write(_target(tmp_path, name), value)
    again = io.read(_target(tmp_path, name))
    if isinstance(value, Mesh2) and name.endswith(".txt"):
        assert isinstance(again, Mesh2)
        assert geometric_triangles(again) == geometric_triangles(value)  # integers
    elif isinstance(value, Mesh2):
        assert isinstance(again, Mesh2)
        assert same_doubles(value, again)
    else:
        assert isinstance(again, (PSLG, PolygonMesh))
        assert type(again) is type(value)
        assert [tuple(map(to_float, p[:2])) for p in again.vertices] == [
            tuple(map(to_float, p[:2])) for p in value.vertices
        ]


@pytest.mark.parametrize("name", [name for name, *_ in MESHES])
def test_shared_meshes_convert_losslessly_between_formats(
    shared_data: Path, tmp_path: Path, name: str
) -> None:
    """A mesh read from any format writes exactly to Triangle and PSLG text and reads
    back equal; through OFF equal but for the boundary markers OFF cannot hold."""
    mesh = io.read(shared_data / name)
    assert isinstance(mesh, Mesh2)
    for target in ("mesh.ele", "mesh.pslg"):
        io.write(tmp_path / target, mesh, exact=True)
        assert io.read(tmp_path / target) == mesh, target
    io.write(tmp_path / "mesh.off", mesh, exact=True)
    assert io.read(tmp_path / "mesh.off") == plain(mesh)
