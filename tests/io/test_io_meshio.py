"""The meshio bridge: 2D triangle meshes through VTK, VTU, Gmsh, Medit, OBJ, PLY; floats
in (their exact binary value), doubles out."""

from __future__ import annotations

import importlib.util
import tempfile
from pathlib import Path

import meshio
import numpy
import pytest
from helpers.io_cases import grid_meshes, same_doubles
from hypothesis import given

from geomexact import Mesh2, io, mesh_from_triangles, mpq
from geomexact.errors import FormatError, OverwriteError
from geomexact.io.meshio_bridge import meshio_fixed
from geomexact.mesh2d.pslg import PSLG

ROUND_TRIP = [".vtk", ".vtu", ".msh", ".mesh", ".obj", ".ply"]
XDMF = [
    pytest.param(
        extension,
        marks=pytest.mark.skipif(
            importlib.util.find_spec("h5py") is None, reason="meshio's XDMF needs h5py"
        ),
    )
    for extension in (".xdmf", ".xmf")
]


@pytest.mark.parametrize("extension", ROUND_TRIP + XDMF)
def test_round_trip_keeps_the_doubles(tmp_path: Path, extension: str) -> None:
    """Written as doubles and read back: same triangles, same doubles."""
    mesh = mesh_from_triangles(
        [(0, 0), (1, 0), (1, 1), (0, 1), (mpq(1, 3), mpq(1, 7))],
        [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)],
    )
    assert io.detect_format(f"m{extension}") == "meshio"
    written = io.write(tmp_path / f"m{extension}", mesh)
    assert written == [tmp_path / f"m{extension}"]
    assert sorted(path.name for path in tmp_path.iterdir()) == [f"m{extension}"]
    again = io.read(tmp_path / f"m{extension}")
    assert isinstance(again, Mesh2) and same_doubles(mesh, again)


@given(grid_meshes(dyadic=True))
def test_meshes_of_doubles_round_trip_exactly(mesh: Mesh2) -> None:
    """Coordinates that are doubles come back exactly, and so do segments, markers and
    attributes (issue 26, item 3: they were dropped) in VTU, VTK and Gmsh files."""
    with tempfile.TemporaryDirectory() as directory:
        for suffix in (".vtu", ".vtk", ".msh"):
            target = Path(directory) / f"m{suffix}"
            report = io.write_with_report(target, mesh)
            assert report.dropped == ()
            back = io.read(target)
            assert back == mesh and back.digest == mesh.digest, suffix


def _save(path: Path, points: list[list[float]], cells: list[tuple[str, list[list[int]]]]) -> None:
    meshio.write(
        path,
        meshio.Mesh(
            numpy.array(points, dtype=float),
            [(kind, numpy.array(data, dtype=numpy.int32)) for kind, data in cells],
        ),
    )


def test_floats_read_as_their_exact_binary_value(tmp_path: Path) -> None:
    """0.1 in a binary file is the double nearest 0.1, exactly, not 1/10; line cells are
    segments (marker 1 without cell data); clockwise triangles are oriented."""
    _save(
        tmp_path / "f.vtu",
        [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0]],
        [("triangle", [[0, 2, 1]]), ("line", [[0, 1]])],
    )
    mesh, notes = io.read_with_notes(tmp_path / "f.vtu")
    assert isinstance(mesh, Mesh2)
    assert mesh.point(1).x == mpq(0.1) != mpq(1, 10)
    assert mesh.triangles() == [(0, 1, 2)]
    assert notes == ["the only triangle was clockwise; reversed it"]
    assert dict(mesh.segments) == {(0, 1): 1}


@pytest.mark.parametrize(
    ("points", "cells", "fragment"),
    [
        ([[0, 0, 0], [1, 0, 0], [0, 1, 1]], [("triangle", [[0, 1, 2]])],
         "point 2 has z = 1.0"),
        ([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [("quad", [[0, 1, 2, 3]])],
         "has quad cells; only triangle meshes are supported"),
        ([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [("triangle", [[0, 1, 2]])],
         "triangle 0 (0, 1, 2) is degenerate"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
         [("triangle", [[0, 1, 2], [1, 2, 3]])], "mixed orientations"),
        ([[0, 0, 0], [float("nan"), 0, 0], [0, 1, 0]], [("triangle", [[0, 1, 2]])],
         "point 1"),
    ],
)
def test_bad_meshes(
    tmp_path: Path,
    points: list[list[float]],
    cells: list[tuple[str, list[list[int]]]],
    fragment: str,
) -> None:
    """What geomexact cannot use is a FormatError (no line numbers in binary files)."""
    _save(tmp_path / "b.vtu", points, cells)
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "b.vtu")
    assert fragment in caught.value.problem
    assert caught.value.line is None


def test_unreadable_file(tmp_path: Path) -> None:
    """A file meshio cannot parse is a FormatError."""
    (tmp_path / "junk.vtu").write_text("not xml at all")
    with pytest.raises(FormatError, match="meshio cannot read it"):
        io.read(tmp_path / "junk.vtu")
    with pytest.raises(FormatError, match="no such file"):
        io.read(tmp_path / "absent.vtk")


def test_overwrite_and_kinds(tmp_path: Path) -> None:
    """Refuses to replace a file unless asked; writes only meshes."""
    mesh = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    io.write(tmp_path / "o.vtk", mesh)
    with pytest.raises(OverwriteError):
        io.write(tmp_path / "o.vtk", mesh)
    io.write(tmp_path / "o.vtk", mesh, overwrite=True)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["o.vtk"]
    with pytest.raises(TypeError,
                       match="writes a Mesh2 or Mesh3 or MixedMesh3 or MixedMeshData, not a PSLG"):
        io.write(tmp_path / "p.vtk", PSLG(vertices=[]))


def test_quality_arrays_for_paraview(tmp_path: Path) -> None:
    """Issue 26, item 3: VTU/VTK/Gmsh files carry each triangle's smallest angle and each
    tetrahedron's smallest dihedral angle (degrees) as cell data; reading ignores them
    (derived), so the mesh reads back the same."""
    from geomexact.mesh3d.cuboid.boxes import Box
    from geomexact.mesh3d.octree.pipeline import generate
    from geomexact.mesh3d.octree.stages import RefineWhere

    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)],
                                 [(0, 1, 3)])
    cube = generate(Box((0, 0, 0), (1, 1, 1)), refinement=RefineWhere(1), trace=False).mesh
    for suffix in (".vtu", ".vtk", ".msh"):
        io.write(tmp_path / f"s{suffix}", square)
        io.write(tmp_path / f"c{suffix}", cube)
        with meshio_fixed():
            flat = meshio.read(tmp_path / f"s{suffix}", **(
                {"file_format": "gmsh"} if suffix == ".msh" else {}))
            solid = meshio.read(tmp_path / f"c{suffix}", **(
                {"file_format": "gmsh"} if suffix == ".msh" else {}))
        assert numpy.allclose(flat.cell_data["min_angle"][0], [45.0, 45.0])
        smallest = solid.cell_data["min_dihedral"][0]
        assert len(smallest) == cube.tetrahedron_count and 0 < min(smallest) < 90
        assert io.read(tmp_path / f"s{suffix}").digest == square.digest
        assert io.read(tmp_path / f"c{suffix}").digest == cube.digest


@pytest.mark.parametrize("kind", ["string", "real", "integer"])
@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_a_gmsh_tag_count_beyond_the_file_is_refused_at_once(tmp_path: Path, kind: str,
                                                             newline: str) -> None:
    """A data block announcing 10^9 tags in a small file is a clear error naming its line
    (meshio would read 10^9 lines one by one: the fuzz suite found it hanging)."""
    import time

    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)])
    path = tmp_path / "q.msh"
    io.write(path, square)  # Gmsh 2.2 text with $ElementData blocks (min_angle)
    lines = path.read_text().splitlines()
    block = lines.index("$ElementData")
    at = block + 1
    if kind != "string":
        at += 1 + int(lines[at])
    if kind == "integer":
        at += 1 + int(lines[at])
    lines[at] = "1000000000"
    path.write_bytes(newline.join(lines).encode() + newline.encode())
    started = time.perf_counter()
    with pytest.raises(FormatError, match=rf":{at + 1}: the \$ElementData block announces 1000000000 {kind} tags"):
        io.read(path)
    assert time.perf_counter() - started < 5
