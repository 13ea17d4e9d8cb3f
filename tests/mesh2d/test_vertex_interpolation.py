"""New vertices get the vertex attributes interpolated linearly (as Triangle does), so a
refined mesh written and read back has the digest that was reported (issue 11)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import io, mesh_from_triangles, mpq, point2
from geomexact.kernel.numbers import Rational
from geomexact.mesh2d.ops import bisect, insert_in_edge, insert_in_triangle
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MaxArea
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.vertex_interpolation import interpolated_in_triangle, interpolated_on_edge
from geomexact.trace.playback import replay


def _linear(x: Rational, y: Rational) -> tuple[Rational, Rational]:
    return (3 * x - 2 * y + 1, mpq(7, 3) * y)


def _square(scale: Rational = 1) -> Mesh2:  # type: ignore[assignment]
    points = [(0, 0), (4, 0), (4, 4), (0, 4)]
    return mesh_from_triangles(
        [(mpq(x) * scale, mpq(y) * scale) for x, y in points],
        [(0, 1, 2), (0, 2, 3)],
        vertex_attributes=[_linear(mpq(x) * scale, mpq(y) * scale) for x, y in points],
    )


def test_the_midpoint_gets_the_exact_average() -> None:
    a, b = point2(0, 0), point2(2, 6)
    assert interpolated_on_edge(a, (mpq(1),), b, (mpq(2),), point2(1, 3)) == (mpq(3, 2),)
    # a vertical edge uses y
    assert interpolated_on_edge(a, (mpq(0),), point2(0, 4), (mpq(8),), point2(0, 1)) == (
        mpq(2),
    )


def test_barycentric_interpolation_reproduces_a_linear_field() -> None:
    corners = tuple((point2(x, y), _linear(mpq(x), mpq(y))) for x, y in ((0, 0), (5, 1), (2, 7)))
    point = point2(mpq(7, 3), mpq(8, 3))
    assert interpolated_in_triangle(corners, point) == _linear(point.x, point.y)  # type: ignore[arg-type]


def test_no_attributes_give_none() -> None:
    a, b = point2(0, 0), point2(2, 0)
    assert interpolated_on_edge(a, (), b, (), point2(1, 0)) == ()
    assert interpolated_on_edge(a, (mpq(1),), b, (), point2(1, 0)) == ()


@pytest.mark.parametrize("op", ["bisect", "edge", "triangle"])
def test_every_inserting_op_interpolates(op: str) -> None:
    mesh = _square()
    if op == "bisect":
        result = bisect(mesh, (0, 2))
    elif op == "edge":
        result = insert_in_edge(mesh, (0, 1), point2(1, 0))
    else:
        result = insert_in_triangle(mesh, (0, 1, 2), point2(3, 1))
    vertex = mesh.vertex_count
    point = result.point(vertex)
    assert result.vertex_attributes[vertex] == _linear(point.x, point.y)


@settings(max_examples=25, deadline=None)
@given(
    st.sampled_from(["bisection", "centroid", "quasi"]),
    st.sampled_from([mpq(1), mpq(1, 10), mpq(1000), mpq(-3, 7)]),
    st.integers(2, 40),
)
def test_a_refined_mesh_reads_back_with_its_digest(
    tmp_path_factory: pytest.TempPathFactory, method: str, scale: Rational, pieces: int
) -> None:
    """Before: new vertices had no attributes in memory and 0s in the file, so the digest
    read back differed.  Now every new vertex carries the linear field exactly, and the
    lossless .ele / .pslg files give back the reported digest."""
    start = _square(scale)
    result = refine(start, MaxArea(16 * scale * scale / pieces), method=method)
    mesh = result.mesh
    assert len(mesh.vertex_attributes) == mesh.vertex_count
    for vertex, values in mesh.vertex_attributes.items():
        point = mesh.point(vertex)
        assert values == _linear(point.x, point.y)
    assert replay(start, result.trace).digest == mesh.digest
    directory = tmp_path_factory.mktemp("attributes")
    for name in ("m.ele", "m.pslg"):
        io.write(directory / name, mesh, numbers="exact")
        assert io.read(directory / name).digest == mesh.digest, name


def test_a_file_with_attributes_refines_and_writes_losslessly(tmp_path: Path) -> None:
    (tmp_path / "m.node").write_text(
        "4 2 1 0\n0 0 0 1\n1 4 0 13\n2 4 4 5\n3 0 4 -7\n", encoding="utf-8"
    )
    (tmp_path / "m.ele").write_text("2 3 0\n0 0 1 2\n1 0 2 3\n", encoding="utf-8")
    mesh = io.read(tmp_path / "m.ele")
    assert isinstance(mesh, Mesh2)
    refined = refine(mesh, MaxArea(1), method="bisection").mesh
    io.write(tmp_path / "r.ele", refined)  # dyadic midpoints: lossless by default
    assert io.read(tmp_path / "r.ele").digest == refined.digest
