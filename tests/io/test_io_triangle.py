"""Triangle's .node/.ele/.neigh/.poly: exact round trips of random meshes and PSLGs with
markers and attributes, 0/1-based indices, orientation, the .neigh check, and the
multi-file writing rules."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers.io_cases import grid_meshes, pslgs, same_doubles, write
from hypothesis import given

from geomexact import Mesh2, io, mesh_from_triangles, mpq, point2
from geomexact.errors import FormatError, OverwriteError
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.validation import validate

SQUARE = mesh_from_triangles(
    [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 1, 2), (0, 2, 3)], [(0, 1, 5), (1, 2, 6)]
)


@given(grid_meshes())
def test_mesh_round_trips_exactly(mesh: Mesh2) -> None:
    """write(exact=True) then read: equal mesh (markers, attributes, segments included)."""
    import tempfile

    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.ele"
        io.write(target, mesh, exact=True)
        assert io.read(target) == mesh


@given(grid_meshes(dyadic=True))
def test_mesh_of_doubles_round_trips_through_float_text(mesh: Mesh2) -> None:
    """Coordinates that are doubles survive exact=False (nearest double) unchanged."""
    import tempfile

    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.ele"
        io.write(target, mesh)
        assert io.read(target) == mesh


@given(grid_meshes(extras=False))
def test_float_text_keeps_the_doubles(mesh: Mesh2) -> None:
    """Any rational written with exact=False reads back to the same doubles."""
    import tempfile

    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "m.ele"
        io.write(target, mesh)
        again = io.read(target)
        assert isinstance(again, Mesh2) and same_doubles(mesh, again)


@given(pslgs())
def test_pslg_round_trips_through_poly(pslg: PSLG) -> None:
    """A PSLG with segments, holes, regions, markers and attributes round-trips .poly."""
    import tempfile

    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "p.poly"
        io.write(target, pslg, exact=True)
        assert io.read(target) == pslg


@given(pslgs())
def test_pslg_vertices_round_trip_through_node(pslg: PSLG) -> None:
    """A .node keeps a PSLG's vertices, markers and attributes (not its segments)."""
    import tempfile

    with tempfile.TemporaryDirectory() as directory:
        target = Path(directory) / "p.node"
        io.write(target, pslg, exact=True)
        expected = PSLG(
            vertices=pslg.vertices,
            vertex_markers=pslg.vertex_markers,
            vertex_attributes=pslg.vertex_attributes,
        )
        assert io.read(target) == expected


def test_writing_a_mesh_writes_node_ele_neigh_and_poly(tmp_path: Path) -> None:
    """x.ele names the mesh: x.node, x.ele, x.neigh, and x.poly for its segments."""
    written = io.write(tmp_path / "x.ele", SQUARE)
    assert [path.name for path in written] == ["x.node", "x.ele", "x.neigh", "x.poly"]
    poly = (tmp_path / "x.poly").read_text().splitlines()
    assert poly[:-1] == ["0 2 0 1", "2 1", "0 0 1 5", "1 1 2 6", "0", "0"]
    # the last line of each file of the set: the same stamp (specs/formats/registry.md)
    stamps = {(tmp_path / name).read_text().splitlines()[-1] for name in
              ("x.node", "x.ele", "x.neigh", "x.poly")}
    assert stamps == {poly[-1]} and poly[-1].startswith("# geomexact file set ")
    again, notes = io.read_with_notes(tmp_path / "x.ele")
    assert again == SQUARE
    assert f"read 2 segments from {tmp_path / 'x.poly'}" in notes
    assert "x.neigh agrees with the adjacency" in notes


def test_mesh_without_segments_writes_three_files(tmp_path: Path) -> None:
    """No segments, no .poly."""
    plain = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    written = io.write(tmp_path / "t.ele", plain)
    assert [path.name for path in written] == ["t.node", "t.ele", "t.neigh"]


def test_stem_may_carry_dots(tmp_path: Path) -> None:
    """'x.1' with format='triangle' names x.1.node/x.1.ele (never replacing '.1')."""
    written = io.write(tmp_path / "x.1", SQUARE, format="triangle")
    assert {path.name for path in written} == {"x.1.node", "x.1.ele", "x.1.neigh", "x.1.poly"}
    assert io.read(tmp_path / "x.1", format="triangle") == SQUARE
    assert io.read(tmp_path / "x.1.ele") == SQUARE


def test_one_based_files(tmp_path: Path) -> None:
    """Indices start at 1 when the first vertex is numbered 1, in every file."""
    write(tmp_path, "one.node", "4 2 1 1\n1 0 0 7 1\n2 1 0 8 1\n3 1 1 9 0\n4 0 1 1/3 2\n")
    write(tmp_path, "one.ele", "2 3 1\n1 1 2 3 0.5\n2 1 3 4 -2\n")
    write(tmp_path, "one.neigh", "2 3\n1 -1 2 -1\n2 -1 -1 1\n")
    write(tmp_path, "one.poly", "0 2 0 1\n1 1\n1 1 2 4\n0\n")
    mesh = io.read(tmp_path / "one.ele")
    assert isinstance(mesh, Mesh2)
    assert mesh.triangles() == [(0, 1, 2), (0, 2, 3)]
    assert dict(mesh.vertex_markers) == {0: 1, 1: 1, 3: 2}
    assert mesh.vertex_attributes[3] == (mpq(1, 3),)
    assert mesh.triangle_attributes[(0, 2, 3)] == (mpq(-2),)
    assert mesh.segment_list() == [(0, 1, 4)]


def test_clockwise_file_is_reversed_and_neigh_still_checked(tmp_path: Path) -> None:
    """An all-clockwise .ele is oriented (noted); .neigh refers to the file's order."""
    write(tmp_path, "cw.node", "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n")
    write(tmp_path, "cw.ele", "2 3 0\n0 0 2 1\n1 0 3 2\n")
    write(tmp_path, "cw.neigh", "2 3\n0 -1 -1 1\n1 -1 0 -1\n")
    mesh, notes = io.read_with_notes(tmp_path / "cw.ele")
    assert isinstance(mesh, Mesh2)
    assert mesh.triangles() == [(0, 1, 2), (0, 2, 3)]
    assert notes[0] == "all 2 triangles were clockwise; reversed them"


def test_neigh_count_must_match(tmp_path: Path) -> None:
    """A .neigh for another mesh is rejected on its header line."""
    io.write(tmp_path / "s.ele", SQUARE)
    write(tmp_path, "s.neigh", "3 3\n")
    with pytest.raises(FormatError, match=r"lists 3 triangles, but the \.ele file has 2") as caught:
        io.read(tmp_path / "s.ele")
    assert caught.value.line == 1


def test_poly_beside_with_its_own_vertices_is_not_used(tmp_path: Path) -> None:
    """A .poly with vertices of its own is another PSLG: its segments are not the mesh's."""
    io.write(tmp_path / "s.ele", mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)]))
    write(tmp_path, "s.poly", "3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n0 0 1\n0\n")
    mesh, notes = io.read_with_notes(tmp_path / "s.ele")
    assert isinstance(mesh, Mesh2) and mesh.segment_list() == []
    assert any("lists its own vertices" in note for note in notes)


def test_poly_with_vertices_in_node(tmp_path: Path) -> None:
    """'0 2 0 1' in a .poly means: the vertices are in the .node beside it."""
    write(tmp_path, "p.node", "3 2 0 1\n0 0 0 1\n1 1 0 2\n2 0 1 0\n")
    write(tmp_path, "p.poly", "0 2 0 1\n2 1\n0 0 1 3\n1 1 2 4\n1\n0 0.1 0.1\n")
    pslg, notes = io.read_with_notes(tmp_path / "p.poly")
    assert pslg == PSLG(
        vertices=[point2(0, 0), point2(1, 0), point2(0, 1)],
        segments=[(0, 1, 3), (1, 2, 4)],
        holes=[point2(mpq(1, 10), mpq(1, 10))],
        vertex_markers=(1, 2, 0),
    )
    assert notes == [f"vertices read from {tmp_path / 'p.node'}"]


def test_rationals_are_read_exactly(tmp_path: Path) -> None:
    """Decimal text is its exact rational, and p/q is accepted everywhere."""
    write(tmp_path, "q.node", "3 2 0 0\n0 0.1 1e-3\n1 1/3 -2.5E+1\n2 .5 7.\n")
    pslg = io.read(tmp_path / "q.node")
    assert isinstance(pslg, PSLG)
    assert pslg.vertices == (
        point2(mpq(1, 10), mpq(1, 1000)),
        point2(mpq(1, 3), mpq(-25)),
        point2(mpq(1, 2), mpq(7)),
    )


def test_comments_and_blank_lines(tmp_path: Path) -> None:
    """'#' starts a comment anywhere; blank lines are ignored; line numbers stay true."""
    write(tmp_path, "c.node", "# header next\n\n3 2 0 0  # count\n0 0 0\n\n1 1 0\n2 0 1 # last\n")
    write(tmp_path, "c.ele", "1 3 0\n# one\n0 0 1 2\n# Generated by nothing\n")
    mesh = io.read(tmp_path / "c.ele")
    assert isinstance(mesh, Mesh2) and mesh.triangle_count == 1
    write(tmp_path, "d.node", "# header next\n\n2 2 0 0\n0 0 0\n\n1 1 zero\n")
    with pytest.raises(FormatError) as caught:
        io.read(tmp_path / "d.node")
    assert caught.value.line == 6


def test_overwrite_is_refused_before_any_file_is_written(tmp_path: Path) -> None:
    """When one target exists nothing is written (all targets checked first)."""
    (tmp_path / "m.neigh").write_text("keep me\n")
    with pytest.raises(OverwriteError):
        io.write(tmp_path / "m.ele", SQUARE)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["m.neigh"]
    io.write(tmp_path / "m.ele", SQUARE, overwrite=True)
    assert io.read(tmp_path / "m.ele") == SQUARE


def test_uneven_attributes_are_padded_with_zeros(tmp_path: Path) -> None:
    """A mesh whose vertices have attributes only in part writes zeros for the others."""
    mesh = mesh_from_triangles(
        [(0, 0), (1, 0), (0, 1)],
        [(0, 1, 2)],
        vertex_attributes=[(mpq(5),), (), (mpq(6),)],
    )
    io.write(tmp_path / "u.ele", mesh)
    again = io.read(tmp_path / "u.ele")
    assert isinstance(again, Mesh2)
    assert again.vertex_attributes[1] == (mpq(0),)


def test_writer_refuses_other_kinds(tmp_path: Path) -> None:
    """The triangle format writes meshes, node and poly write PSLGs."""
    pslg = PSLG(vertices=[point2(0, 0)])
    with pytest.raises(TypeError, match="writes a Mesh2 or Mesh3, not a PSLG"):
        io.write(tmp_path / "a.ele", pslg)
    with pytest.raises(TypeError, match="writes a PSLG, not a Mesh2"):
        io.write(tmp_path / "a.poly", SQUARE)


def _grid_files(directory: Path, side: int) -> Path:
    """A side x side grid mesh as .node/.ele, vertex ids scattered (a fixed shuffle)."""
    count = side * side
    order = [(index * 7919) % count for index in range(count)]  # 7919 is prime
    node = [f"{count} 2 0 1"]
    position = [0] * count
    for grid_index, vertex in enumerate(order):
        position[vertex] = grid_index
    for vertex in range(count):
        j, i = divmod(position[vertex], side)
        node.append(f"{vertex} {i}.{(i * j) % 97:02d} {j}.{(i + j) % 89:02d} 0")
    ele = []
    for j in range(side - 1):
        for i in range(side - 1):
            a = j * side + i
            b, c, d = a + 1, a + side + 1, a + side
            ele.append((order[a], order[b], order[c]))
            ele.append((order[a], order[c], order[d]))
    write(directory, "big.node", "\n".join(node) + "\n")
    lines = [f"{len(ele)} 3 0"] + [f"{k} {a} {b} {c}" for k, (a, b, c) in enumerate(ele)]
    return write(directory, "big.ele", "\n".join(lines) + "\n")


@pytest.mark.slow
def test_reading_100k_triangles(tmp_path: Path) -> None:
    """A 100k-triangle .node/.ele reads whole (its speed: benchmarks/bench_io.py)."""
    path = _grid_files(tmp_path, 225)
    mesh = io.read(path)
    assert isinstance(mesh, Mesh2) and mesh.triangle_count == 2 * 224 * 224
    assert validate(mesh) == []


def test_10k_triangles_round_trip(tmp_path: Path) -> None:
    """A 10k-triangle mesh, written and read back with its .neigh, is the same mesh (its
    speed is measured by benchmarks/bench_io.py, not here)."""
    path = _grid_files(tmp_path, 72)
    mesh = io.read(path)
    io.write(tmp_path / "out.ele", mesh)
    again = io.read(tmp_path / "out.ele")
    assert again == mesh and again.digest == mesh.digest
    assert mesh.triangle_count == 2 * 71 * 71


def test_byte_order_mark_and_crlf(tmp_path: Path) -> None:
    """A UTF-8 byte-order mark and Windows line ends are not data."""
    (tmp_path / "w.node").write_bytes(b"\xef\xbb\xbf3 2 0 0\r\n0 0 0\r\n1 1 0\r\n2 0 1\r\n")
    (tmp_path / "w.ele").write_bytes(b"1 3 0\r\n0 0 1 2\r\n")
    mesh = io.read(tmp_path / "w.ele")
    assert mesh == mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])


def test_any_file_of_the_mesh_names_it(tmp_path: Path) -> None:
    """With format='triangle', x.node or x.neigh name the mesh x as well as x.ele."""
    io.write(tmp_path / "x.node", SQUARE, format="triangle")
    assert (tmp_path / "x.ele").exists()
    assert io.read(tmp_path / "x.neigh", format="triangle") == SQUARE


def test_segments_that_are_not_edges_are_noted(tmp_path: Path) -> None:
    """A segment of the .poly that is no edge of the mesh is kept and noted."""
    io.write(tmp_path / "d.ele", mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, 1)],
                                                     [(0, 1, 2), (0, 2, 3)]))
    write(tmp_path, "d.poly", "0 2 0 1\n1 1\n0 1 3 9\n0\n")
    mesh, notes = io.read_with_notes(tmp_path / "d.ele")
    assert isinstance(mesh, Mesh2) and mesh.segment_list() == [(1, 3, 9)]
    assert "1 segment is not an edge of the mesh (validate reports them)" in notes
