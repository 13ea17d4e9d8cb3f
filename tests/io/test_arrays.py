"""Meshes as NumPy arrays (issue 26, item 2): round trips keep everything (markers,
attributes, segments; exact numbers with numbers='exact'), doubles are never rounded
without being asked, bad arrays name the problem, and the Triangle-like one-call API
returns arrays that meet both bounds."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from helpers.paths import read_superior
from hypothesis import given, settings

from geomexact import mpq
from geomexact.errors import FormatError, PreconditionError
from geomexact.io.arrays import from_arrays, to_arrays, triangulate_arrays
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.stages import RefineWhere
from geomexact.strategies import pslgs, triangulations


def _superior() -> PSLG:
    value = read_superior()
    assert isinstance(value, PSLG)
    return value


def test_a_pslg_and_its_mesh_round_trip_exactly() -> None:
    pslg = _superior()
    arrays = to_arrays(pslg, numbers="exact")
    assert set(arrays) == {"vertices", "segments", "segment_markers", "holes"}
    assert from_arrays(arrays) == pslg
    mesh = triangulate(pslg).mesh
    back = from_arrays(to_arrays(mesh, numbers="exact"))
    assert isinstance(back, Mesh2) and back.digest == mesh.digest
    assert back.segments == mesh.segments


def test_doubles_are_never_rounded_silently() -> None:
    pslg = _superior()  # decimal coordinates: not doubles
    with pytest.raises(PreconditionError, match="not exactly a double"):
        to_arrays(pslg)
    nearest = to_arrays(pslg, numbers="nearest")
    assert nearest["vertices"].dtype == np.float64
    assert nearest["vertices"][0, 0] == float(pslg.vertices[0].x)


@given(triangulations())
@settings(max_examples=40, deadline=None)
def test_random_meshes_round_trip(mesh: Mesh2) -> None:
    back = from_arrays(to_arrays(mesh, numbers="exact"))
    assert isinstance(back, Mesh2) and back.digest == mesh.digest


@given(pslgs())
@settings(max_examples=40, deadline=None)
def test_random_pslgs_round_trip(pslg: PSLG) -> None:
    assert from_arrays(to_arrays(pslg, numbers="exact")) == pslg


def test_markers_and_attributes_come_back(tmp_path: object) -> None:
    arrays = {"vertices": np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=np.float64),
              "triangles": np.array([[0, 1, 2], [0, 2, 3]]),
              "triangle_attributes": np.array([[1.5], [2.5]]),
              "vertex_markers": np.array([1, 1, 2, 2]),
              "vertex_attributes": np.array([[0.5], [1.0], [0.25], [2.0]]),
              "segments": np.array([[0, 1], [1, 2]]), "segment_markers": np.array([7, 8])}
    mesh = from_arrays(arrays)
    assert isinstance(mesh, Mesh2)
    again = to_arrays(mesh)
    assert set(again) == set(arrays)
    for key, value in arrays.items():
        assert np.array_equal(np.asarray(again[key], dtype=float), np.asarray(value, float)), key
    assert from_arrays(again).digest == mesh.digest


def test_a_tetrahedral_mesh_round_trips() -> None:
    mesh = generate(Box((0, 0, 0), (1, 1, 1)), refinement=RefineWhere(2),
                    trace=False).mesh
    arrays = to_arrays(mesh)
    assert arrays["tetrahedra"].shape == (mesh.tetrahedron_count, 4)
    assert from_arrays(arrays).digest == mesh.digest


def test_bad_arrays_name_the_problem() -> None:
    with pytest.raises(PreconditionError, match="no 'vertices'"):
        from_arrays({})
    with pytest.raises(PreconditionError, match=r"outside 0\.\.2"):
        from_arrays({"vertices": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 5]]})
    with pytest.raises(PreconditionError, match="not a finite number"):
        from_arrays({"vertices": [[0, 0], [1, float("nan")], [0, 1]],
                     "triangles": [[0, 1, 2]]})
    with pytest.raises(FormatError, match="arrays"):  # a degenerate triangle, as a file's
        from_arrays({"vertices": [[0, 0], [1, 0], [2, 0]], "triangles": [[0, 1, 2]]})


def test_exact_text_and_fractions_are_read_exactly() -> None:
    mesh = from_arrays({"vertices": [["0", "0"], [Fraction(1, 3), "0"], ["0", mpq(1, 7)]],
                        "triangles": [[0, 1, 2]]})
    assert isinstance(mesh, Mesh2) and mesh.point(1).x == mpq(1, 3)
    assert to_arrays(mesh, numbers="exact")["vertices"][2, 1] == mpq(1, 7)


def test_triangulate_like_the_triangle_package() -> None:
    square = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]],
              "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
    result = triangulate_arrays(square, min_angle=30, max_area=0.01)
    points, triangles = result["vertices"], result["triangles"]
    a, b, c = (points[triangles[:, k]] for k in range(3))
    u, v = b - a, c - a
    area = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2
    assert area.max() <= 0.01
    sides = [np.linalg.norm(x - y, axis=1) for x, y in ((b, c), (c, a), (a, b))]
    for k in range(3):
        p, q, r = sides[k], sides[(k + 1) % 3], sides[(k + 2) % 3]
        angle = np.degrees(np.arccos(np.clip((q**2 + r**2 - p**2) / (2 * q * r), -1, 1)))
        assert angle.min() >= 30 - 1e-9
    assert set(result) >= {"vertices", "triangles", "segments", "segment_markers"}
